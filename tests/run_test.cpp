// A whole run through a Runner (run.hpp), stopped or failed at any instant and resumed from the
// checkpoint it saved there, reports the summary of the run never interrupted: every record the
// summary needs (the drift verdict's intervals, the pressure tensor's, the transport blocks, the
// seed) is in every checkpoint, however the run got there.
#include "carom/run/run.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "carom/engine/initial.hpp"
#include "carom/io/checkpoint.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/run_report.hpp"
#include "carom/run/start.hpp"

namespace carom {
namespace {

namespace fs = std::filesystem;

// A run as carom run would make it: its start and what it is asked for.
struct RunCase {
  std::string name;
  int dimension = 2;
  InitialOptions initial;
  Settings settings;
  ShearRequest shear;
  // Read from a start file with new velocities (--kT, --seed) instead, when given.
  std::optional<StartSpec> start_file;
  RunSpec spec;
};

// A run of 64 particles measured from t = 5 to 30, asking for everything a summary can report
// beyond the state: the drift verdict, the pressure tensor's errors, and the transport
// coefficients (at rest) or the shear stress and viscosity (sheared, with a thermostat).
std::vector<RunCase> cases(const fs::path& folder) {
  RunCase at_rest;
  at_rest.name = "transport";
  at_rest.initial.n = 64;
  at_rest.initial.packing_fraction = 0.3;
  at_rest.initial.seed = 4;
  at_rest.initial.boundary = Boundary::periodic;
  at_rest.settings.rule.rule = Rule::elastic;
  at_rest.spec.transport = true;
  RunCase sheared = at_rest;
  sheared.name = "shear";
  sheared.spec.transport = false;
  sheared.shear = {.rate = 0.2, .profile = true};
  sheared.settings.thermostat = {.kind = ThermostatKind::rescale, .kT = 1.0, .every = 1.0};
  // Spheres whose velocities a seed drew, which the summary reports.
  RunCase spheres = at_rest;
  spheres.name = "spheres";
  spheres.dimension = 3;
  spheres.initial.n = 48;
  const fs::path start = folder / "spheres.txt";
  std::ofstream(start) << [&] {
    std::ostringstream text;
    write_start(text, make_initial<3>(spheres.initial), Rule::elastic);
    return text.str();
  }();
  spheres.start_file.emplace();
  spheres.start_file->path = start.string();
  spheres.start_file->temperature = 1.0;
  spheres.start_file->seed = 7;
  std::vector<RunCase> all = {at_rest, sheared, spheres};
  for (RunCase& c : all) {
    c.spec.end_time = 30.0;
    c.spec.measure_from = 5.0;
    c.spec.summary = (folder / (c.name + ".json")).string();
    c.spec.checkpoint = (folder / (c.name + ".ckpt")).string();
  }
  return all;
}

Start start_of(const RunCase& c) {
  if (c.start_file) return load_start(*c.start_file);
  return init_start(c.dimension, c.initial, c.settings, c.shear);
}

// A summary without the clock (wall_seconds, events_per_second), which no two runs share.
nlohmann::json summary_without_clock(const std::string& path) {
  std::ifstream in(path);
  nlohmann::json summary = nlohmann::json::parse(in);
  summary.erase("wall_seconds");
  summary.erase("events_per_second");
  return summary;
}

// Sets a stop flag when `when` holds at an instant its trigger looks at.
template <std::size_t D>
class StopWhen final : public Observer<D> {
 public:
  StopWhen(Trigger trigger, std::atomic<int>& flag, std::function<bool(const Simulation<D>&)> when)
      : Observer<D>(trigger), flag_(flag), when_(std::move(when)) {}
  void observe(const Simulation<D>& simulation) override {
    if (when_(simulation)) flag_.store(1);
  }

 private:
  std::atomic<int>& flag_;
  std::function<bool(const Simulation<D>&)> when_;
};

// Throws, as a write that fails (a full disk) does, when `when` holds.
template <std::size_t D>
class FailWhen final : public Observer<D> {
 public:
  FailWhen(Trigger trigger, std::function<bool(const Simulation<D>&)> when)
      : Observer<D>(trigger), when_(std::move(when)) {}
  void observe(const Simulation<D>& simulation) override {
    if (when_(simulation)) throw std::runtime_error("cannot write (a test's failure)");
  }

 private:
  std::function<bool(const Simulation<D>&)> when_;
};

// How an interruption is made: an observer added to the run's simulation before it runs.
using Interruption = std::function<void(AnySimulation&, std::atomic<int>&)>;

Interruption stop_after_event(std::uint64_t k) {
  return [k](AnySimulation& any, std::atomic<int>& flag) {
    any.visit([&]<std::size_t D>(Simulation<D>& s) {
      s.add_observer(std::make_shared<StopWhen<D>>(
          Trigger::each_event(), flag,
          [k](const Simulation<D>& at) { return at.counts().events == k; }));
    });
  };
}

// At a time the run settles at (a multiple of `every`, the end among them), once it is there.
Interruption stop_at_time(double t, double every) {
  return [t, every](AnySimulation& any, std::atomic<int>& flag) {
    any.visit([&]<std::size_t D>(Simulation<D>& s) {
      s.add_observer(
          std::make_shared<StopWhen<D>>(Trigger::every_time(every), flag,
                                        [t](const Simulation<D>& at) { return at.time() == t; }));
    });
  };
}

Interruption fail_at_time(double t, double every) {
  return [t, every](AnySimulation& any, std::atomic<int>&) {
    any.visit([&]<std::size_t D>(Simulation<D>& s) {
      s.add_observer(std::make_shared<FailWhen<D>>(
          Trigger::every_time(every), [t](const Simulation<D>& at) { return at.time() == t; }));
    });
  };
}

Interruption fail_after_event(std::uint64_t k) {
  return [k](AnySimulation& any, std::atomic<int>&) {
    any.visit([&]<std::size_t D>(Simulation<D>& s) {
      s.add_observer(std::make_shared<FailWhen<D>>(
          Trigger::each_event(), [k](const Simulation<D>& at) { return at.counts().events == k; }));
    });
  };
}

class CheckpointResume : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("carom-run-test-" +
               std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  // The summary of `c` run in one piece, and its event count.
  static std::pair<nlohmann::json, std::uint64_t> uninterrupted(const RunCase& c) {
    Runner runner(start_of(c));
    EXPECT_EQ(runner.run(c.spec).status, RunStatus::reached);
    const nlohmann::json summary = summary_without_clock(c.spec.summary);
    return {summary, summary["events"].get<std::uint64_t>()};
  }

  // Runs `c` interrupted as `interrupt` says (a stop or a failed write), then resumes its
  // checkpoint to the same end, as carom run --resume (and a sweep's rerun) does: the summary
  // must be the uninterrupted run's.
  static void expect_resumed_summary(const RunCase& c, const nlohmann::json& whole,
                                     const Interruption& interrupt, const std::string& what) {
    std::atomic<int> stop{0};
    fs::remove(c.spec.summary);
    {
      Runner runner(start_of(c));
      interrupt(runner.simulation(), stop);
      RunHooks hooks;
      hooks.stop = &stop;
      try {
        ASSERT_EQ(runner.run(c.spec, hooks).status, RunStatus::stopped) << what;
      } catch (const SavedRunError&) {
        // A failed write: the run so far is saved.
      }
    }
    ASSERT_FALSE(fs::exists(c.spec.summary)) << what;
    Runner resumed(resume_start(c.spec.checkpoint));
    RunSpec spec = c.spec;
    spec.measure_from.reset();  // the checkpoint holds the window
    ASSERT_EQ(resumed.run(spec).status, RunStatus::reached) << what;
    EXPECT_EQ(summary_without_clock(c.spec.summary).dump(2), whole.dump(2))
        << c.name << ": " << what;
  }

  fs::path folder_;
};

// Regression: a stop that landed once the end was reached (SIGTERM as the final checkpoint was
// written, before the summary) saved a checkpoint without the window's records, and the resumed
// run reported no drift verdict, no pressure tensor or shear errors and no transport.
TEST_F(CheckpointResume, AStopAtTheEndResumesToTheSummaryOfARunNeverStopped) {
  for (const RunCase& c : cases(folder_)) {
    const auto [whole, events] = uninterrupted(c);
    ASSERT_FALSE(whole["compressibility_factor_drift"].is_null()) << c.name;
    ASSERT_FALSE(whole["pressure_tensor_error"].is_null()) << c.name;
    ASSERT_EQ(whole["transport"].is_null(), !c.spec.transport) << c.name;
    ASSERT_EQ(whole["shear"].is_null(), c.shear.rate == 0.0) << c.name;
    ASSERT_EQ(whole["seed"].is_null(), !c.start_file) << c.name;
    expect_resumed_summary(c, whole, stop_at_time(c.spec.end_time, c.spec.end_time),
                           "stopped at the end");
  }
}

// The same at many instants: after event k for k from the first to the last, at times the
// measurements look at (the window's opening, its intervals' ends), and while equilibrating.
TEST_F(CheckpointResume, AStopAtAnyInstantResumesToTheSummaryOfARunNeverStopped) {
  for (const RunCase& c : cases(folder_)) {
    const auto [whole, events] = uninterrupted(c);
    constexpr std::uint64_t kStops = 12;
    for (std::uint64_t i = 1; i <= kStops; ++i) {
      const std::uint64_t k = std::max<std::uint64_t>(1, events * i / kStops);
      expect_resumed_summary(c, whole, stop_after_event(k),
                             "stopped after event " + std::to_string(k));
    }
    for (const double t : {2.5, 5.0, 6.25, 17.5, 28.75}) {
      expect_resumed_summary(c, whole, stop_at_time(t, 1.25),
                             "stopped at t = " + std::to_string(t));
    }
  }
}

// A write that fails (a full disk) saves the run so far, from which it goes on as if it had not
// failed: at an event, or at an instant the time-triggered outputs and measurements look at.
TEST_F(CheckpointResume, AFailedWriteResumesToTheSummaryOfARunNeverStopped) {
  for (const RunCase& c : cases(folder_)) {
    const auto [whole, events] = uninterrupted(c);
    for (const std::uint64_t k : {std::uint64_t{1}, events / 3, events - 1, events}) {
      expect_resumed_summary(c, whole, fail_after_event(k),
                             "failed after event " + std::to_string(k));
    }
    for (const double t : {5.0, 6.25, 17.5, 30.0}) {
      expect_resumed_summary(c, whole, fail_at_time(t, 1.25), "failed at t = " + std::to_string(t));
    }
  }
}

// A checkpoint saved at a run's end keeps its window's records, but a run resumed to measure
// another window (to a later end, from a later start) measures its own, as the same Runner
// running on would: the records of [0, 10] are not mixed into those of [10, 20] (20 blocks of
// 0.5, the first from t = 10).
TEST_F(CheckpointResume, ARunResumedToMeasureAnotherWindowDoesNotContinueTheFirstsRecords) {
  RunCase c = cases(folder_).front();
  RunSpec first = c.spec, second = c.spec;
  first.end_time = 10.0;
  first.measure_from.reset();
  second.end_time = 20.0;
  second.measure_from = 10.0;
  second.checkpoint.clear();
  Runner on(start_of(c));
  on.run(first);
  on.run(second);
  const nlohmann::json going_on = summary_without_clock(c.spec.summary);
  ASSERT_EQ(going_on["compressibility_factor_drift"]["intervals"], 20);

  Runner saved(start_of(c));
  saved.run(first);
  Runner resumed(resume_start(c.spec.checkpoint));
  resumed.run(second);
  EXPECT_EQ(summary_without_clock(c.spec.summary).dump(2), going_on.dump(2));
}

}  // namespace
}  // namespace carom
