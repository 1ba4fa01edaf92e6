// The library's owner of a run: the state, the engine, the measurement window and the
// non-physical timeline (frames, checkpoints, checks, progress) that observers are called on.
// Every front end (the command line, the Python module, a C++ program) drives a run through it:
//
//   carom::Simulation<2> sim(carom::read_classic_file("gas.txt").system, {.rule =
//   {carom::Rule::elastic}}); sim.measure_from(50.0);                          // equilibrate, then
//   measure sim.run_until(100.0); carom::Observables<2> o = sim.observables();     // pressure,
//   temperature, rates std::vector<carom::Particle<2>> now = sim.snapshot();
//
// Modelled on Box2D's world (a definition struct with defaults, a step, nothing global) and
// HOOMD-blue's Simulation (a State and operations on triggers). The library installs no signal
// handler and prints nothing: a caller that wants Ctrl-C to stop a run owns a flag and hands it
// over (set_stop_flag).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "carom/core/measurement.hpp"
#include "carom/core/observables.hpp"
#include "carom/core/thermostat.hpp"
#include "carom/engine/engine.hpp"
#include "carom/engine/sampler.hpp"

namespace carom {

// How a run is made; the defaults are the classic assignment's (swap rule, walls come with the
// System's box).
struct Settings {
  CollisionRule rule;  // Rule::swap, restitution 1, TC time kDefaultTc
  EngineKind engine = EngineKind::fast;
  Thermostat thermostat{};  // none
  // Dynamics, or event chains (which take no rule, engine or thermostat: see check_settings).
  Sampler sampler{};
};

// Throws std::invalid_argument for settings no run can have: a restitution outside (0, 1], below
// 1 under the swap rule, a negative TC time, or a thermostat check_thermostat refuses; for event
// chains, a thermostat, a restitution below 1, the reference engine or a chain length not above
// 0 (or infinite).
void check_settings(const Settings& settings);

// When an observer looks at a run.
struct Trigger {
  enum class Kind {
    time,        // at t = 0, dt, 2 dt, ...: multiples of `period` counted from t = 0
    events,      // after every `period`-th event of the run (counted from its start)
    seconds,     // every `period` seconds of wall-clock time (looked at every 1024 events)
    each_event,  // after every event
  };
  Kind kind = Kind::time;
  double period = 0.0;
  // For events and seconds: call the observer only once the run is whole at the instant of the
  // event that made it due (every event at that time processed: settled()), as a checkpoint
  // needs, so that what was written up to it (an event log, say) can be cut at its time exactly.
  bool whole_instant = false;

  static Trigger every_time(double dt) { return {Kind::time, dt}; }
  static Trigger every_events(std::uint64_t n) { return {Kind::events, static_cast<double>(n)}; }
  static Trigger every_seconds(double seconds) { return {Kind::seconds, seconds}; }
  static Trigger each_event() { return {Kind::each_event, 0.0}; }
  Trigger at_whole_instants() const {
    Trigger whole = *this;
    whole.whole_instant = kind == Kind::events || kind == Kind::seconds;
    return whole;
  }
};

template <std::size_t D>
class Simulation;

// Something that looks at a run when its trigger fires: a trajectory writer, a checkpoint
// writer, an invariant check, a progress line. A time trigger fires once every event up to that
// time is processed; the others fire just after the event that makes them due
// (Simulation::last_event()).
template <std::size_t D>
class Observer {
 public:
  explicit Observer(Trigger trigger) : trigger_(trigger) {}
  virtual ~Observer() = default;
  const Trigger& trigger() const { return trigger_; }
  virtual void observe(const Simulation<D>& simulation) = 0;

 protected:
  // A time observer may change its period as it observes: it is next due at the first multiple
  // of the new one after now.
  void set_period(double period) { trigger_.period = period; }

 private:
  Trigger trigger_;
};

// Why run_until returned.
enum class RunStatus {
  reached,      // the target time: every event up to it is processed
  stopped,      // the stop flag was set
  event_limit,  // the events asked for are processed
};

// A target time the run cannot reach: before the current time, beyond the time resolution, or
// needing more box crossings than could ever be processed.
class RunLengthError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Throws RunLengthError unless event chains of `chain_length` mean diameters, each lasting
// `chain_duration` time units (its length over N: the moving particle runs at N mean diameters a
// unit of time), can run to `end_time`: a chain's end must lie after its start there, by a
// millionth of a chain at least.
void check_chain_clock(double end_time, double chain_length, double chain_duration);

template <std::size_t D>
struct Checkpoint;

template <std::size_t D>
class Simulation {
 public:
  // The physics runs on stored times counted from an epoch that moves with the run (see
  // rebase_period), so its resolution does not depend on the absolute time. The absolute times
  // a run reports (events, frames, windows, checkpoints) are doubles, though: beyond this one they
  // resolve less than 1e-4, and frames or windows closer than that could not be told apart.
  static constexpr double kLatestTime = 1e12;
  // The engine's epoch moves to the last event after every this many events of a run of `n`
  // particles (counted from its start, across checkpoints): a few hundred collisions per
  // particle, so that stored times span a few hundred mean free times (resolved to 1e-13 of one)
  // while predicting everything again costs well under 1% of the run.
  static constexpr std::uint64_t rebase_period(std::size_t n) { return 256 * n + 4096; }
  // Runs needing more box crossings than this (at the highest speed the energy allows) are
  // refused as impossible to finish.
  static constexpr double kMostCrossings = 1e13;
  static constexpr std::uint64_t kNoLimit = std::numeric_limits<std::uint64_t>::max();

  // Starts a run from `system` (every particle's stored state; usually all at t = 0; no records
  // means mass 1 each). Throws std::invalid_argument for settings check_settings refuses and for
  // a system the engines cannot run (a periodic side not above two diameters, say).
  explicit Simulation(System<D> system, const Settings& settings = {});
  // Continues a checkpointed run exactly as if it had never stopped.
  explicit Simulation(const Checkpoint<D>& checkpoint);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  // Processes every event up to time `t` in order, calling observers as their triggers fire,
  // and returns `reached`; or returns early, after at least `max_events` events or once the stop
  // flag is set, with every event at the time of the last one processed (so that time() is a
  // moment the run is whole at). Any division of a run into calls gives the same events,
  // observations and results, bit for bit, as one call. Throws RunLengthError (see
  // check_target) and JamError.
  RunStatus run_until(double t, std::uint64_t max_events = kNoLimit);
  // Throws RunLengthError unless run_until(t) can be done: t not before time(), not beyond
  // kLatestTime, and no particle could cross the box more than kMostCrossings times.
  void check_target(double t) const;

  // The time the run has reached; every stored state is at or before it.
  double time() const { return time_; }
  // Whether every event up to time() is processed (and every observer due then called): after
  // any run_until; not for a new run at its start time, whose events then are still to come.
  bool settled() const { return settled_; }
  const Settings& settings() const { return settings_; }
  // The stored (lazy) states: each particle at the time of its last collision (Particle::time).
  const System<D>& state() const { return engine_->system(); }
  // time() as a stored time (System::epoch), exactly: where snapshots, frames and checks bring the
  // particles. Just after an event, that event's own stored time (an absolute time may not tell
  // it from the next one's); once the run is whole at time(), System::stored(time()).
  double stored_time() const { return stored_time_; }
  // Every particle at time(), wrapped into a periodic box; the stored states are not touched.
  std::vector<Particle<D>> snapshot() const { return synchronised(state(), stored_time_); }
  // The last processed event (valid once counts().events > 0).
  const Event& last_event() const { return last_event_; }
  // Everything counted since the run began, across checkpoints (the fluxes' integrals up to the
  // last event).
  const Counts& counts() const { return counts_; }
  // The same, the fluxes' integrals brought to time().
  Counts current_counts() const;

  // Every run keeps its momentum and energy fluxes (fluxes.hpp) in counts() and in the
  // measurement window: the pressure tensor of observables() and the transport moments. A run
  // continued from a checkpoint of carom before 1.6, which kept none, keeps them from then on.
  bool tracks_fluxes() const { return counts_.fluxes.has_value(); }
  // Keeps the heat flux too from now on (Fluxes::heat), for the thermal conductivity.
  void keep_heat_flux();

  // The measurement window and the observables measured over it.
  // The window's fluxes are brought to time().
  Measurement measurement() const;
  Observables<D> observables() const { return observables_over(measurement(), time_); }
  // The observables over any stretch of the run (a window opened at its start with its counts,
  // ending at `now`): measure()'s, and an event-chain run's in its units (at_unit_temperature).
  Observables<D> observables_over(const Measurement& stretch, double now) const;
  // kT now: the kinetic temperature of dynamics; 1 for event chains, which sample at kT = 1.
  double temperature() const;
  // kinetic_temperature(state()), without summing over the particles under event chains: their
  // one moving particle, at the engine's speed, gives the same value at every instant.
  double kinetic_temperature() const;
  // Opens the window now: counts from zero, the kinetic energy now.
  void reset_measurement();
  // Opens the window at time t (now if t is not ahead): equilibrate until then.
  void measure_from(double t);
  // The time a window is still to open at, if one is.
  std::optional<double> pending_measurement() const { return measure_from_; }

  // Observers are called in the order they were added; adding one at a time it is due (a frame
  // at t = 0) calls it at the next run_until. A run already whole at its time (settled: what is
  // due then has been observed) has a time-triggered observer start at the next multiple of its
  // period, as a continued output does; `first` = FirstLook::now calls a new output (a file
  // that begins here) now as well when now is such a multiple.
  enum class FirstLook { next, now };
  void add_observer(std::shared_ptr<Observer<D>> observer, FirstLook first = FirstLook::next);
  // Stops calling `observer` (a front end's per-call trajectory or collision log, say).
  void remove_observer(const Observer<D>* observer);
  // A flag the caller owns (and may set from a signal handler): nonzero stops run_until after
  // the event being processed. nullptr: none.
  void set_stop_flag(const std::atomic<int>* flag) { stop_ = flag; }

  // What a checkpoint holds: everything needed to continue exactly. `source` names the input
  // the run began from.
  Checkpoint<D> checkpoint(const std::string& source) const;
  // An event-chain run's chain in flight (nullopt for dynamics).
  std::optional<ChainState> chain() const;

 private:
  struct Scheduled {
    std::shared_ptr<Observer<D>> observer;
    double next_time = 0.0;                            // Kind::time
    std::uint64_t next_event = 0;                      // Kind::events
    std::chrono::steady_clock::time_point next_clock;  // Kind::seconds
    bool due = false;  // a whole_instant trigger fired: called once the instant is complete
  };

  void schedule(Scheduled& entry) const;
  double next_due_time() const;
  // Records a processed event and calls the observers it makes due.
  void record(const Event& event);
  // After `count` events were counted, `last` the last: the clock, and a rebase when due.
  void after_events(const Event& last, std::uint64_t count);
  // run_until's events up to `stop_at` for event chains that no observer looks at one by one,
  // lifted by the engine in batches (EcmcEngine::lift_quietly): `processed` goes up by them. A
  // status when the run stops (its stop flag, or max_events), else nullopt (stop_at reached).
  std::optional<RunStatus> lift_quietly(double stop_at, std::uint64_t max_events,
                                        std::uint64_t& processed);
  // The engine's velocity changes since the last call, taken into the fluxes.
  void take_velocity_changes();
  // The engine's next event up to `end_time` (step()), its velocity changes between events taken
  // into the fluxes first.
  std::optional<Event> next_event(double end_time);
  // Keeps the fluxes from now on.
  void track_fluxes();
  // The fluxes' kinetic rates computed afresh from every particle (incremental updates gather
  // round-off over a long run).
  void renew_flux_rates();
  // Calls an observer that is due, or marks it to be called once the instant is complete.
  void call_or_await(Scheduled& entry);
  // Every event at the time of the last one, then the observers due then (those waiting for
  // a whole instant last).
  void complete_instant();
  // The run has every event up to `t` processed: time observers, the window and the thermostat
  // due then.
  void settle_at(double t);
  // The thermostat's action at time_ (settings_.thermostat), and the next instant it acts at.
  void apply_thermostat();
  double next_thermostat_time() const;
  // Andersen's resets as events: one particle drawn at random, at time_, reset.
  void reset_one_velocity();

  Settings settings_;  // the chain length resolved (default_chain_length for 0)
  bool chains_ = false;  // settings_.sampler.kind is event chains
  std::unique_ptr<Engine<D>> engine_;
  double chains_kinetic_temperature_ = 0.0;  // kinetic_temperature() under event chains
  double time_ = 0.0;
  double stored_time_ = 0.0;  // see stored_time()
  // Every event up to time_ is processed and every time observer due then has been called (false
  // for a new run at its start time, whose events at that time are still to come).
  bool settled_ = false;
  Counts counts_;
  Measurement measurement_;
  std::optional<double> measure_from_;
  Event last_event_;
  const std::atomic<int>* stop_ = nullptr;
  // A stretch of time over which the engine's work between events is bounded (see
  // Engine::slice_length): run_until looks at the stop flag at least this often in simulated
  // time.
  double slice_ = kNever;
  std::uint64_t rebase_period_;     // see rebase_period()
  std::uint64_t events_to_rebase_;  // until counts_.events is the next multiple of it
  std::vector<Scheduled> observers_;
  bool watch_events_ = false;     // an observer needs looking at after events
  bool instant_awaited_ = false;  // an observer waits for the instant to be complete
  // The thermostat's instants are `every` apart from t = 0; it has acted at this many of them
  // (counted from the first, whether or not the run saw them: a run from t acts from then on).
  std::uint64_t thermostat_instants_ = 0;
  pcg32 thermostat_rng_;  // Andersen's draws
  // Andersen's resets as events: the absolute time of the next (the run has made
  // thermostat_instants_ of them).
  double thermostat_next_ = kNever;
};

// Throws RunLengthError for a time beyond Simulation's kLatestTime (which a double resolves too
// coarsely): what check_target says of it, for a run whose particles are not made yet.
void check_latest_time(double t);

}  // namespace carom
