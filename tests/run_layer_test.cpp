// The run layer in this process, as the front ends use it: a Runner writing every output a
// RunSpec names (the files read back), the starts (a file, a checkpoint, carom init's options)
// and a compression. run_test.cpp holds resuming from checkpoints to the uninterrupted summary.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "carom/core/statistics.hpp"
#include "carom/engine/invariant_check.hpp"
#include "carom/io/checkpoint.hpp"
#include "carom/io/event_log.hpp"
#include "carom/io/log_table.hpp"
#include "carom/io/trajectory_reader.hpp"
#include "carom/run/compress_run.hpp"
#include "carom/run/run.hpp"
#include "carom/run/start.hpp"
#include "carom/run/z_drift.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

namespace fs = std::filesystem;

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> lines_of(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

InitialOptions gas_options() {
  InitialOptions options;
  options.n = 32;
  options.packing_fraction = 0.3;
  options.seed = 3;
  options.boundary = Boundary::periodic;
  return options;
}

Settings elastic() {
  Settings settings;
  settings.rule.rule = Rule::elastic;
  return settings;
}

// Every particle's position at the simulation's time, row-major (N, D).
std::vector<double> positions_of(const AnySimulation& simulation) {
  std::vector<double> out(simulation.size() * static_cast<std::size_t>(simulation.dimension()));
  simulation.positions(out.data());
  return out;
}

RunSpec run_to(double end_time) {
  RunSpec spec;
  spec.end_time = end_time;
  return spec;
}

class RunLayer : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("carom_run_layer_" +
               std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }

  fs::path folder_;
};

TEST_F(RunLayer, InitStartIsCaromInitsStartAtTimeZero) {
  const Start start = init_start(2, gas_options(), elastic());
  EXPECT_EQ(start.simulation.dimension(), 2);
  EXPECT_EQ(start.simulation.size(), 32u);
  EXPECT_EQ(start.simulation.time(), 0.0);
  EXPECT_EQ(start.simulation.boundary(), Boundary::periodic);
  EXPECT_EQ(start.simulation.settings().rule.rule, Rule::elastic);
  EXPECT_FALSE(start.resumed);
  EXPECT_THROW(init_start(4, gas_options(), elastic()), RequestError);
}

TEST_F(RunLayer, DumpsHoldAFrameEveryIntervalInEachFormat) {
  for (const std::string name : {"movie.xyz", "movie.gsd"}) {
    Runner runner(init_start(2, gas_options(), elastic()));
    RunSpec spec = run_to(2.0);
    spec.dump = path(name);
    spec.dump_every = 0.5;
    const RunOutcome outcome = runner.run(spec);
    EXPECT_EQ(outcome.status, RunStatus::reached) << name;
    const std::vector<Frame> frames = read_trajectory_frames(spec.dump);
    ASSERT_EQ(frames.size(), 5u) << name;  // t = 0, 0.5, ..., 2
    for (std::size_t f = 0; f < frames.size(); ++f) {
      EXPECT_DOUBLE_EQ(frames[f].time, 0.5 * static_cast<double>(f)) << name;
      EXPECT_EQ(frames[f].position.size(), 32u) << name;
      EXPECT_TRUE(frames[f].periodic) << name;
    }
    // The last frame is the run's end state.
    const std::vector<double> end = positions_of(runner.simulation());
    for (std::size_t i = 0; i < 32; ++i) {
      EXPECT_NEAR(frames.back().position[i][0], end[2 * i], 1e-6) << name;
      EXPECT_NEAR(frames.back().position[i][1], end[2 * i + 1], 1e-6) << name;
    }
  }
  Runner runner(init_start(2, gas_options(), elastic()));
  RunSpec spec = run_to(2.0);
  spec.dump = path("movie.lammpstrj");
  spec.dump_every = 0.5;
  runner.run(spec);
  std::size_t frames = 0;
  for (const std::string& line : lines_of(spec.dump)) frames += line == "ITEM: TIMESTEP" ? 1 : 0;
  EXPECT_EQ(frames, 5u);
}

TEST_F(RunLayer, TheLogHasARowEveryIntervalAndTheEventLogEveryCollision) {
  Runner runner(init_start(2, gas_options(), elastic()));
  RunSpec spec = run_to(3.0);
  spec.log = path("log.csv");
  spec.log_every = 1.0;
  spec.events = path("events.csv");
  std::vector<Event> collisions;
  RunHooks hooks;
  hooks.collisions = &collisions;
  const RunOutcome outcome = runner.run(spec, hooks);
  EXPECT_EQ(outcome.status, RunStatus::reached);

  const LogTable log = read_log_table(spec.log);
  ASSERT_FALSE(log.columns.empty());
  EXPECT_EQ(log.columns.front(), "time");
  ASSERT_EQ(log.rows.size(), 4u);  // t = 0, 1, 2, 3
  for (std::size_t r = 0; r < log.rows.size(); ++r) {
    EXPECT_DOUBLE_EQ(log.rows[r].front(), static_cast<double>(r));
  }

  const std::vector<std::string> events = lines_of(spec.events);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front() + "\n", EventLogWriter<2>::kHeader);
  ASSERT_GT(collisions.size(), 0u);
  EXPECT_EQ(events.size() - 1, collisions.size());
  EXPECT_EQ(collisions.size(), runner.simulation().counts().events);
  EXPECT_EQ(outcome.report.events, runner.simulation().counts().events);
}

TEST_F(RunLayer, TheSummaryAndTheCheckpointHoldTheEndOfTheRun) {
  Runner runner(init_start(2, gas_options(), elastic()));
  RunSpec spec = run_to(4.0);
  spec.measure_from = 1.0;
  spec.summary = path("summary.json");
  spec.checkpoint = path("run.ckpt");
  const RunOutcome outcome = runner.run(spec);
  EXPECT_EQ(outcome.status, RunStatus::reached);
  EXPECT_GT(outcome.report.events, 0u);
  ASSERT_TRUE(outcome.report.drift.has_value());  // a window was measured

  const nlohmann::json summary = nlohmann::json::parse(contents(spec.summary));
  EXPECT_EQ(summary.at("end_time").get<double>(), 4.0);
  EXPECT_EQ(summary.at("equilibrate").get<double>(), 1.0);
  EXPECT_EQ(summary.at("n").get<int>(), 32);
  EXPECT_EQ(summary.at("events").get<std::uint64_t>(), runner.simulation().counts().events);
  EXPECT_FALSE(summary.at("compressibility_factor_drift").is_null());
  EXPECT_FALSE(summary.contains("particles"));  // a summary, not the state

  // The checkpoint continues the run exactly where it ended.
  const Start resumed = resume_start(spec.checkpoint);
  EXPECT_TRUE(resumed.resumed);
  EXPECT_EQ(resumed.input, spec.checkpoint);
  EXPECT_EQ(resumed.simulation.time(), 4.0);
  EXPECT_EQ(resumed.simulation.counts(), runner.simulation().counts());
  EXPECT_EQ(positions_of(resumed.simulation), positions_of(runner.simulation()));
}

TEST_F(RunLayer, AStoppedRunSavesItsCheckpointAndWritesNoSummary) {
  Runner runner(init_start(2, gas_options(), elastic()));
  RunSpec spec = run_to(4.0);
  spec.summary = path("summary.json");
  spec.checkpoint = path("run.ckpt");
  const std::atomic<int> stop{1};
  RunHooks hooks;
  hooks.stop = &stop;
  const RunOutcome outcome = runner.run(spec, hooks);
  EXPECT_EQ(outcome.status, RunStatus::stopped);
  EXPECT_FALSE(fs::exists(spec.summary));
  ASSERT_TRUE(fs::exists(spec.checkpoint));
  EXPECT_LT(resume_start(spec.checkpoint).simulation.time(), 4.0);
}

// Two disks that overlap, drifting apart too slowly to part before a third meets a wall: a state
// only --check notices.
Start overlapping_start() {
  System<2> system;
  system.box.size = {10.0, 10.0};
  system.particles = {{{5.0, 5.0}, {-0.01, 0.0}, 0.0, 0.5},
                      {{5.5, 5.0}, {0.01, 0.0}, 0.0, 0.5},
                      {{1.0, 8.0}, {-1.0, 0.0}, 0.0, 0.5}};
  system.records.resize(3);
  return Start{AnySimulation(AnySystem(std::move(system)), elastic()),
               "overlap",
               "overlap",
               false,
               "",
               std::nullopt,
               {}};
}

TEST_F(RunLayer, TheCheckFindsABrokenInvariantARunWithoutItMissesIt) {
  RunSpec spec = run_to(1.0);
  EXPECT_EQ(Runner(overlapping_start()).run(spec).status, RunStatus::reached);
  spec.check = true;
  spec.check_every = 1;
  Runner checked(overlapping_start());
  EXPECT_THROW(checked.run(spec), InvariantError);
}

TEST_F(RunLayer, LoadStartReadsAFileAndDrawsTheVelocitiesAsked) {
  std::ofstream(path("start.txt")) << [] {
    std::ostringstream text;
    write_start(text, init_start(2, gas_options(), elastic()).simulation.snapshot_system(),
                Rule::elastic);
    return text.str();
  }();
  StartSpec spec;
  spec.path = path("start.txt");
  const Start plain = load_start(spec);
  EXPECT_EQ(plain.simulation.size(), 32u);
  EXPECT_EQ(plain.simulation.boundary(), Boundary::periodic);  // as the file records
  EXPECT_EQ(plain.input, spec.path);
  EXPECT_FALSE(plain.seed.has_value());
  EXPECT_FALSE(plain.resumed);

  spec.temperature = 2.0;
  spec.seed = 9;
  const Start drawn = load_start(spec);
  ASSERT_TRUE(drawn.seed.has_value());
  EXPECT_EQ(*drawn.seed, 9u);
  EXPECT_EQ(positions_of(drawn.simulation), positions_of(plain.simulation));
  std::vector<double> plain_v(64), drawn_v(64);
  plain.simulation.velocities(plain_v.data());
  drawn.simulation.velocities(drawn_v.data());
  EXPECT_NE(plain_v, drawn_v);

  spec.path = path("missing.txt");
  EXPECT_THROW(load_start(spec), InputError);
}

TEST_F(RunLayer, CompressReachesItsTargetOrStopsWithAValidPacking) {
  const AnySystem start = init_start(2, gas_options(), elastic()).simulation.snapshot_system();
  CompressionSpec spec;
  spec.settings.target = 0.5;
  spec.input = "gas";
  const CompressionResult result = compress(start, spec);
  EXPECT_EQ(result.summary.status, "reached_target");
  EXPECT_NEAR(result.summary.packing_fraction, 0.5, 1e-9);
  EXPECT_EQ(result.summary.n, 32u);
  EXPECT_EQ(result.summary.input, "gas");
  const System<2>& packing = std::get<System<2>>(result.packing);
  EXPECT_EQ(packing.size(), 32u);
  EXPECT_GT(packing.particles.front().radius, std::get<System<2>>(start).particles.front().radius);

  const std::atomic<int> stop{1};
  CompressionHooks hooks;
  hooks.stop = &stop;
  const CompressionResult stopped = compress(start, spec, hooks);
  EXPECT_EQ(stopped.summary.status, "interrupted");
  EXPECT_LT(stopped.summary.packing_fraction, 0.5);
}

// The drift verdict's blocks: Z that remembers itself from block to block (a slow oscillation,
// two whole periods, so the halves agree) is told apart from Z that does not (alternating about
// the same mean), and neither drifted.
TEST(DriftVerdict, SaysWhenZsBlocksAreCorrelated) {
  pcg32 rng(3);
  const Simulation<2> simulation(testing::random_gas(rng, 20, 0.3, 0.5, 10, 8), {{Rule::elastic}});
  const auto record_of = [&](auto block_z) {
    DriftRecord record{1.0, {}, {}, {}};
    Counts total;
    for (int i = 0; i <= 32; ++i) {
      if (i > 0) total.virial += 2.0 * 20.0 * (block_z(i) - 1.0);  // Z = 1 + virial / (D N)
      record.boundaries.push_back(i);
      record.totals.push_back(total);
      record.temperatures.push_back(1.0);
    }
    return record;
  };
  const double pi = std::acos(-1.0);
  const BlockErrors slow =
      block_errors(record_of([&](int i) { return 5.0 + std::sin(2 * pi * i / 16.0); }), simulation);
  ASSERT_TRUE(slow.verdict);
  EXPECT_EQ(slow.verdict->intervals, 32u);
  EXPECT_FALSE(slow.verdict->drifted()) << slow.verdict->sigmas;
  EXPECT_NEAR(slow.verdict->block_correlation, std::cos(2 * pi / 16.0), 0.05);
  EXPECT_TRUE(slow.verdict->blocks_correlated());
  const BlockErrors fast =
      block_errors(record_of([](int i) { return i % 2 == 0 ? 4.0 : 6.0; }), simulation);
  ASSERT_TRUE(fast.verdict);
  EXPECT_FALSE(fast.verdict->drifted());
  EXPECT_LT(fast.verdict->block_correlation, 0.0);
  EXPECT_FALSE(fast.verdict->blocks_correlated());
  // Z = 5 in every block: no correlation to speak of (NaN, null in the summary), no warning.
  const BlockErrors still = block_errors(record_of([](int) { return 5.0; }), simulation);
  ASSERT_TRUE(still.verdict);
  EXPECT_TRUE(std::isnan(still.verdict->block_correlation));
  EXPECT_FALSE(still.verdict->blocks_correlated());
  EXPECT_EQ(slow.verdict->correlation_spreads(), slow.verdict->block_correlation * std::sqrt(32.0));
  // Blocks on either side of a gap (boundaries 16 and 17 missing: the blocks that end at 15 and
  // at 19 are not neighbours) are not a pair: alternating Z with a 6 either side of the gap.
  DriftRecord gapped = record_of([](int i) { return i % 2 == 0 ? 4.0 : 6.0; });
  gapped.totals.erase(gapped.totals.begin() + 16, gapped.totals.begin() + 18);
  gapped.boundaries.erase(gapped.boundaries.begin() + 16, gapped.boundaries.begin() + 18);
  gapped.temperatures.erase(gapped.temperatures.begin() + 16, gapped.temperatures.begin() + 18);
  const BlockErrors across = block_errors(gapped, simulation);
  ASSERT_TRUE(across.verdict);
  std::vector<double> z;
  std::vector<std::uint8_t> follows;
  for (int i = 1; i <= 32; ++i) {
    if (i >= 16 && i <= 18) continue;  // the blocks that end at 16, 17 and 18 are gone
    z.push_back(i % 2 == 0 ? 4.0 : 6.0);
    follows.push_back(i != 1 && i != 19 ? 1 : 0);
  }
  ASSERT_EQ(across.verdict->intervals, z.size());
  EXPECT_NEAR(across.verdict->block_correlation, lag_one_autocorrelation(z, follows), 1e-12);
  EXPECT_LT(across.verdict->block_correlation, lag_one_autocorrelation(z) - 0.01);
}

}  // namespace
}  // namespace carom
