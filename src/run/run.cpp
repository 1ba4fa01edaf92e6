#include "carom/run/run.hpp"

#include <fmt/format.h>

#include <chrono>
#include <stdexcept>

#include "carom/engine/invariant_check.hpp"
#include "carom/io/atomic_file.hpp"
#include "carom/io/checkpoint.hpp"
#include "carom/io/final_state.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/input_error.hpp"
#include "carom/io/time_series.hpp"
#include "carom/io/trajectory.hpp"
#include "carom/io/shown_velocities.hpp"
#include "run_checks.hpp"
#include "run_outputs.hpp"
#include "transport_meter.hpp"

namespace carom {

namespace {

constexpr const char* kCannotStream =
    "cannot write the trajectory, the event log or the time series (is the disk full?)";

// Calls the caller's progress function every kProgressEvents events.
template <std::size_t D>
class ProgressCall final : public Observer<D> {
 public:
  ProgressCall(const AnySimulation& any, const RunHooks& hooks, double end_time)
      : Observer<D>(Trigger::every_events(kProgressEvents)), any_(any), call_(hooks.progress) {
    progress_.start_time = any.time();
    progress_.end_time = end_time;
  }
  void observe(const Simulation<D>&) override {
    progress_.events += kProgressEvents;
    progress_.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - began_).count();
    call_(any_, progress_);
  }

 private:
  const AnySimulation& any_;
  const std::function<void(const AnySimulation&, const RunProgress&)>& call_;
  RunProgress progress_;
  std::chrono::steady_clock::time_point began_ = std::chrono::steady_clock::now();
};

// Appends every collision to a caller's list.
template <std::size_t D>
class CollisionCollector final : public Observer<D> {
 public:
  explicit CollisionCollector(std::vector<Event>& out)
      : Observer<D>(Trigger::each_event()), out_(out) {}
  void observe(const Simulation<D>& simulation) override {
    out_.push_back(simulation.last_event());
  }

 private:
  std::vector<Event>& out_;
};

// The observers of one run() (checks, checkpoints, the drift verdict, the caller's hooks):
// detached when it returns, however it returns.
template <std::size_t D>
class RunObservers {
 public:
  explicit RunObservers(Simulation<D>& simulation) : simulation_(simulation) {}
  ~RunObservers() {
    for (const auto& observer : added_) simulation_.remove_observer(observer.get());
    simulation_.set_stop_flag(nullptr);
  }
  RunObservers(const RunObservers&) = delete;
  RunObservers& operator=(const RunObservers&) = delete;
  template <class O>
  std::shared_ptr<O> add(std::shared_ptr<O> observer,
                         typename Simulation<D>::FirstLook first = Simulation<D>::FirstLook::next) {
    simulation_.add_observer(observer, first);
    added_.push_back(observer);
    return observer;
  }

 private:
  Simulation<D>& simulation_;
  std::vector<std::shared_ptr<Observer<D>>> added_;
};

}  // namespace

SavedRunError::SavedRunError(const std::string& cause, std::string checkpoint, double time)
    : std::runtime_error(
          fmt::format("{}; the run so far (t = {}) is saved in {}", cause, time, checkpoint)),
      checkpoint_(std::move(checkpoint)),
      time_(time) {}

struct Runner::State {
  // A resumed run's report is its checkpoint's until it runs on.
  explicit State(Start s) : start(std::move(s)), records(start.records) {
    start.simulation.visit([&](const auto& simulation) { take_errors(simulation); });
  }
  Start start;
  // What the measurements of the last run() gathered (before any, the resumed checkpoint's):
  // what a checkpoint saved now holds with the state, and the next run() goes on with when it
  // measures the same window to the same end.
  WindowRecords records;
  // RunOutputs<2> or <3>, as the simulation is; made by the first run().
  std::shared_ptr<void> outputs;
  double wall_seconds = 0.0;                             // in run(), over the Runner's life
  std::uint64_t events = 0;                              // the events of that time
  std::optional<DriftVerdict> drift;                     // of the last run
  std::optional<SymmetricTensor> pressure_tensor_error;  // of the last run
  std::optional<double> compressibility_factor_error;    // of the last run
  std::optional<TransportEstimate> transport;            // of the last run

  template <std::size_t D>
  RunOutputs<D>& outputs_of(Simulation<D>& simulation) {
    if (!outputs) outputs = std::make_shared<RunOutputs<D>>(simulation, start.resumed);
    return *static_cast<RunOutputs<D>*>(outputs.get());
  }

  // The checkpoint of `simulation` with what its run keeps beyond the state: the seed its
  // summary reports and the window's records.
  template <std::size_t D>
  Checkpoint<D> checkpoint_of(const Simulation<D>& simulation,
                              const WindowRecords& window_records) const {
    Checkpoint<D> checkpoint = simulation.checkpoint(start.source);
    checkpoint.seed = start.seed;
    checkpoint.records = window_records;
    return checkpoint;
  }
  template <std::size_t D>
  RunOutcome run(Simulation<D>& simulation, const RunSpec& spec, const RunHooks& hooks);
  // The drift verdict and errors from the records' blocks. Event chains' blocks must each hold
  // a turn of chains (one along every axis) or more, else they are pieces of a few chains,
  // neither alike nor apart, and say nothing of an error.
  template <std::size_t D>
  void take_errors(const Simulation<D>& simulation) {
    const BlockErrors errors =
        records.drift ? block_errors(*records.drift, simulation) : BlockErrors{};
    const bool blocks_apart =
        errors.block_length >= chain_turn_duration(simulation.settings().sampler,
                                                   simulation.state().size(), D);
    drift = blocks_apart ? errors.verdict : std::nullopt;
    pressure_tensor_error = blocks_apart ? errors.pressure_tensor : std::nullopt;
    compressibility_factor_error = blocks_apart ? errors.compressibility_factor : std::nullopt;
  }
};

template <std::size_t D>
RunOutcome Runner::State::run(Simulation<D>& simulation, const RunSpec& spec,
                              const RunHooks& hooks) {
  check_run(simulation, start, spec, {});
  if (spec.measure_from) simulation.measure_from(*spec.measure_from);
  std::unique_ptr<AtomicFile> summary;
  if (!spec.summary.empty()) summary = std::make_unique<AtomicFile>(spec.summary);
  RunOutputs<D>& outputs = outputs_of(simulation);
  outputs.update(spec);

  RunObservers<D> observers(simulation);
  std::shared_ptr<TraceWriter<D>> trace;
  if (hooks.trace) {
    trace = std::make_shared<TraceWriter<D>>(*hooks.trace);
    trace->start(start.input, spec.end_time, simulation);
    observers.add(trace);
  }
  if (hooks.collisions) {
    observers.add(std::make_shared<CollisionCollector<D>>(*hooks.collisions));
  }
  if (spec.check) {
    const std::uint64_t every = spec.check_every > 0
                                    ? spec.check_every
                                    : std::max<std::uint64_t>(1000, simulation.state().size());
    observers.add(std::make_shared<InvariantCheck<D>>(every));
  }
  // Z over blocks of the measurement window, first half against second; a run continued (in
  // pieces, or resumed from a checkpoint) goes on with the blocks it holds when it measures the
  // same window, to any end, and with its transport blocks when to the same end or one that
  // spaces them alike (TransportMeter::continued): one resumed at its end rebuilds its summary
  // from them.
  const double window_start =
      simulation.pending_measurement().value_or(simulation.measurement().start_time);
  std::shared_ptr<ZDrift<D>> z_drift;
  if (spec.end_time > window_start) {
    // A window that opens now has a block boundary now (a run's first instant, or one resumed
    // where it opens), which a block continued to here holds already.
    z_drift = observers.add(
        std::make_shared<ZDrift<D>>(
            window_start, records.same_window(window_start) ? records.drift : std::nullopt),
        Simulation<D>::FirstLook::now);
  }
  std::shared_ptr<TransportMeter<D>> transport_meter;
  if (spec.transport && spec.end_time > window_start) {
    simulation.keep_heat_flux();
    transport_meter = observers.add(std::make_shared<TransportMeter<D>>(
        simulation.state(), window_start, spec.end_time,
        TransportMeter<D>::continued(records, window_start, spec.end_time)));
  }
  const auto records_now = [&] {
    WindowRecords now{window_start, spec.end_time, std::nullopt, std::nullopt};
    if (z_drift) now.drift = z_drift->record();
    if (transport_meter) now.transport = transport_meter->record();
    return now;
  };
  // Every checkpoint holds what the summary needs beyond the state, whenever it is saved: on the
  // run's way, stopped, failed or at its end (a stop may land after the end is reached and
  // before the summary is written, and the resumed run must write the summary this one would).
  const auto checkpoint_now = [&] { return checkpoint_of(simulation, records_now()); };
  if (spec.checkpoint_every) {
    const auto flush_outputs = [&outputs] {
      if (!outputs.flush()) throw std::runtime_error(kCannotStream);
    };
    observers.add(std::make_shared<CheckpointWriter<D>>(spec.checkpoint, *spec.checkpoint_every,
                                                        checkpoint_now, flush_outputs));
  }
  if (hooks.progress) {
    observers.add(std::make_shared<ProgressCall<D>>(start.simulation, hooks, spec.end_time));
  }
  simulation.set_stop_flag(hooks.stop);

  const auto began = std::chrono::steady_clock::now();
  const std::uint64_t events_before = simulation.counts().events;
  const auto account = [&] {
    wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    events += simulation.counts().events - events_before;
  };
  RunStatus status = RunStatus::reached;
  try {
    status = simulation.run_until(spec.end_time);
  } catch (const std::runtime_error& e) {
    account();
    records = records_now();
    // A write that failed as the run went (a full disk): the state the run has reached is sound
    // and worth keeping when there is somewhere to keep it. A jam or a broken invariant is not.
    const bool broken = dynamic_cast<const JamError*>(&e) != nullptr ||
                        dynamic_cast<const InvariantError*>(&e) != nullptr;
    if (spec.checkpoint.empty() || broken) throw;
    save_checkpoint(spec.checkpoint, checkpoint_of(simulation, records));
    throw SavedRunError(e.what(), spec.checkpoint, simulation.time());
  }
  account();
  records = records_now();
  take_errors(simulation);
  transport = transport_meter ? transport_meter->estimate(simulation.state()) : std::nullopt;
  // The streamed files are complete (or the failure is known) before any result is written.
  const bool streamed_ok = outputs.flush();
  if (!spec.checkpoint.empty()) {
    save_checkpoint(spec.checkpoint, checkpoint_of(simulation, records));
  }
  if (!streamed_ok) {
    throw std::runtime_error(
        fmt::format("{}{}", kCannotStream,
                    spec.checkpoint.empty()
                        ? std::string()
                        : fmt::format("; the run's end state is saved in {}", spec.checkpoint)));
  }
  // A stop asked for once the end was reached still stops: nothing more is written (the
  // checkpoint just saved holds what the summary needs: a run resumed from it writes it).
  if (hooks.stop && hooks.stop->load() != 0) status = RunStatus::stopped;
  RunOutcome outcome{status, RunReport{}};
  if (status == RunStatus::stopped) return outcome;
  if (trace) trace->finish(simulation);
  outcome.report.input = start.source;
  outcome.report.wall_seconds = wall_seconds;
  outcome.report.events = events;
  outcome.report.seed = start.seed;
  outcome.report.drift = drift;
  outcome.report.pressure_tensor_error = pressure_tensor_error;
  outcome.report.compressibility_factor_error = compressibility_factor_error;
  outcome.report.transport = transport;
  if (!spec.final_state.empty()) {
    const bool at_rest = shows_at_rest(simulation);
    AtomicFile final_state(spec.final_state);
    write_final_state(final_state.stream(), final_format(spec.final_state), simulation.state(),
                      simulation.time(), at_rest ? Rule::elastic : simulation.settings().rule.rule,
                      at_rest);
    final_state.commit();
  }
  if (summary) {
    write_json(summary->stream(), simulation, outcome.report, false);
    summary->commit();
  }
  return outcome;
}

Runner::Runner(Start start) : state_(std::make_unique<State>(std::move(start))) {}
Runner::~Runner() = default;
Runner::Runner(Runner&&) noexcept = default;
Runner& Runner::operator=(Runner&&) noexcept = default;

void Runner::check(const RunSpec& spec, const std::vector<NamedFile>& other_outputs) const {
  state_->start.simulation.visit(
      [&](const auto& s) { check_run(s, state_->start, spec, other_outputs); });
}

RunOutcome Runner::run(const RunSpec& spec, const RunHooks& hooks) {
  return state_->start.simulation.visit([&](auto& s) { return state_->run(s, spec, hooks); });
}

void Runner::save(const std::string& path) const {
  state_->start.simulation.visit(
      [&](const auto& s) { save_checkpoint(path, state_->checkpoint_of(s, state_->records)); });
}

AnySimulation& Runner::simulation() {
  return state_->start.simulation;
}
const AnySimulation& Runner::simulation() const {
  return state_->start.simulation;
}
const Start& Runner::start() const {
  return state_->start;
}

RunReport Runner::report() const {
  RunReport report;
  report.input = state_->start.source;
  report.wall_seconds = state_->wall_seconds;
  report.events = state_->events;
  report.seed = state_->start.seed;
  report.drift = state_->drift;
  report.pressure_tensor_error = state_->pressure_tensor_error;
  report.compressibility_factor_error = state_->compressibility_factor_error;
  report.transport = state_->transport;
  return report;
}

}  // namespace carom
