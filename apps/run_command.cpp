#include "run_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <memory>

#include "carom/checkpoint.hpp"
#include "carom/classic_input.hpp"
#include "carom/observables.hpp"
#include "carom/overlap.hpp"
#include "carom/trajectory.hpp"
#include "cli_support.hpp"
#include "progress.hpp"

namespace carom::cli {

namespace {

constexpr const char* kFormatHelp = R"(The classic input FILE holds whitespace-separated numbers:
  line 1       N                  the number of disks
  line 2       R                  their radius
  line 3       Lx Ly              the box, [0, Lx] x [0, Ly]
  N lines      x y vx vy [r [m]]  each disk's centre and velocity at t = 0, optionally its own
                                  radius and mass (default R and 1)
Walls are labelled -1 left, -2 right, -3 bottom, -4 top; disks 0..N-1.)";

constexpr const char* kExamples = R"(Examples:
  carom run examples/walls_only.txt 20            final state, the seed's table
  carom run examples/normal.txt 20 --format csv   x, y, wall and disk collision counts
  carom run examples/normal.txt 20 --trace        every collision, step by step
  carom run examples/normal.txt 100 --format json -o result.json
  carom run gas.txt 200 --rule elastic --boundary periodic --equilibrate 50 --format json)";

void check(const RunArguments& args, double end_time) {
  if (args.trace && args.format != Format::table) {
    throw UsageError(
        "--trace prints the seed's step-by-step table; it cannot be combined with --format csv "
        "or json");
  }
  if (!(args.restitution > 0.0 && args.restitution <= 1.0)) {
    throw UsageError(fmt::format("--restitution must be in (0, 1], got {}", args.restitution));
  }
  if (args.restitution < 1.0 && args.rule != Rule::elastic) {
    throw UsageError(
        "--restitution below 1 needs --rule elastic (the swap rule has no restitution)");
  }
  if (!(args.tc >= 0.0)) throw UsageError(fmt::format("--tc must be >= 0, got {}", args.tc));
  if (!args.dump.empty() && !(args.every > 0.0)) {
    throw UsageError("--dump needs --every DT > 0: the time between frames");
  }
  if (args.dump.empty() && args.every != 0.0) throw UsageError("--every needs --dump FILE");
  if (!args.dump.empty() && end_time / args.every > 1e7) {
    throw UsageError(
        fmt::format("--every {} would write more than 10^7 frames up to {}", args.every, end_time));
  }
  // A checkpointed run may stop before its equilibration ends: the resumed run finishes it.
  if (!(args.equilibrate >= 0.0 && (args.equilibrate <= end_time || !args.checkpoint.empty()))) {
    throw UsageError(fmt::format("--equilibrate must be between 0 and END_TIME ({}), got {}",
                                 end_time, args.equilibrate));
  }
}

// Where a run begins: a classic file, or a checkpoint to resume.
struct Start {
  Checkpoint checkpoint;
  bool resumed = false;
};

Start start_from(const RunArguments& args) {
  ClassicInput input = read_classic_file(args.input, args.boundary);
  Start start;
  Checkpoint& c = start.checkpoint;
  c.input = args.input;
  c.system = std::move(input.system);
  c.rule = {args.rule, args.restitution, args.tc};
  c.engine = args.engine;
  c.equilibrate = args.equilibrate;
  return start;
}

Start resume_from(const std::string& path) {
  std::ifstream file = open_input(path);
  Start start{read_checkpoint(file, path), true};
  return start;
}

// The signal that asked the run to stop, or 0.
volatile std::sig_atomic_t stop_signal = 0;
extern "C" void request_stop(int signal) {
  stop_signal = signal;
}

// Writes --checkpoint: every --checkpoint-every events or seconds, at the end, and when SIGINT or
// SIGTERM asks the run to stop (then the run ends with Interrupted).
class CheckpointWriter {
 public:
  CheckpointWriter(const RunArguments& args, const Checkpoint& start)
      : path_(args.checkpoint), template_(start) {
    template_.system.particles.clear();
    if (path_.empty()) return;
    const std::string& every = args.checkpoint_every;
    if (!every.empty()) {
      const bool seconds = every.back() == 's';
      const double value =
          parse_number(seconds ? every.substr(0, every.size() - 1) : every, "--checkpoint-every");
      if (!(value > 0.0)) throw UsageError("--checkpoint-every must be greater than 0");
      (seconds ? every_seconds_ : every_events_) = value;
    }
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
  }

  void after_event(const Engine<2>& engine) {
    if (path_.empty()) return;
    ++events_;
    if (stop_signal != 0) {
      save(engine);
      throw Interrupted(stop_signal, path_);
    }
    const bool due_by_events =
        every_events_ > 0.0 && events_ % static_cast<std::uint64_t>(every_events_) == 0;
    bool due_by_clock = false;
    if (every_seconds_ > 0.0 && events_ % 1024 == 0) {
      due_by_clock = std::chrono::duration<double>(Clock::now() - last_).count() >= every_seconds_;
    }
    if (due_by_events || due_by_clock) save(engine);
  }

  void save(const Engine<2>& engine) {
    if (path_.empty()) return;
    Checkpoint c = template_;
    c.system = engine.system();
    c.time = engine.time();
    c.counts = engine.counts();
    AtomicFile file(path_);
    write_checkpoint(file.stream(), c);
    file.commit();
    last_ = Clock::now();
  }

  // The measurement's starting energy changes when equilibration ends.
  void set_kinetic_energy_initial(double energy) { template_.kinetic_energy_initial = energy; }

 private:
  using Clock = std::chrono::steady_clock;
  std::string path_;
  Checkpoint template_;
  double every_events_ = 0.0, every_seconds_ = 0.0;
  std::uint64_t events_ = 0;
  Clock::time_point last_ = Clock::now();
};

// --check: event times never decrease, and every `every` events no pair overlaps and no disk is
// outside the box (O(N) through a cell grid, so O(1) per event when `every` is about N).
class InvariantChecker {
 public:
  InvariantChecker(bool enabled, std::uint64_t every) : enabled_(enabled), every_(every) {}

  void after_event(const Engine<2>& engine, const Event& event) {
    if (!enabled_) return;
    ++events_;
    if (event.time < last_) {
      fail(event, fmt::format("time ran backwards from {} to {}", last_, event.time));
    }
    last_ = event.time;
    if (events_ % every_ == 0) {
      if (const auto violation = find_violation(engine.system(), event.time)) {
        fail(event, *violation);
      }
    }
  }

 private:
  [[noreturn]] void fail(const Event& event, const std::string& what) const {
    throw std::runtime_error(fmt::format("--check: invariant violated at event {} (t = {}, {}): {}",
                                         events_, event.time, describe(event), what));
  }

  bool enabled_;
  std::uint64_t every_;
  std::uint64_t events_ = 0;
  double last_ = -kNever;
};

}  // namespace

CLI::App* add_run_command(CLI::App& app, RunArguments& args) {
  CLI::App* run = app.add_subcommand(
      "run", "Simulate FILE from t = 0 to END_TIME and print every disk's final state.");
  run->footer(std::string(kFormatHelp) + "\n\n" + kExamples);
  run->add_option("FILE", args.input, "Input in the classic format (see below); - reads stdin")
      ->required();
  run->add_option("END_TIME", args.end_time, "Time to simulate to (a number >= 0)")->required();
  add_choice<Format>(run, "--format", args.format,
                     {{"table", Format::table}, {"csv", Format::csv}, {"json", Format::json}},
                     "table: the seed's `particle i: (x, y) (vx, vy): t : (cwall, cpart)` lines; "
                     "csv: `x, y, cwall, cpart` lines; json: settings, counts, observables and "
                     "full state");
  run->add_flag("--trace", args.trace,
                "Print the initial state, then after every collision its time, what collided and "
                "every disk's stored state, then the final state");
  run->add_option("-o,--output", args.output,
                  "Write to this file (atomically: it appears complete or not at all) instead of "
                  "stdout");
  run->add_option("--dump", args.dump,
                  "Write frames of every disk at t = 0, DT, 2 DT, ... (--every DT) to this file: "
                  ".xyz (extended XYZ, for OVITO and ASE) or .lammpstrj (LAMMPS text dump)");
  run->add_option("--every", args.every, "Time between --dump frames");
  run->add_option("--events", args.events,
                  "Write every collision to this csv file: time,kind,first,partner (kind wall or "
                  "pair; partner a disk or a wall label)");
  run->add_option("--summary", args.summary,
                  "Also write the json settings, counts and observables (no particles) to this "
                  "file");
  add_choice<Rule>(run, "--rule", args.rule, {{"swap", Rule::swap}, {"elastic", Rule::elastic}},
                   "swap: touching disks exchange whole velocities (the seed's rule); elastic: "
                   "they exchange momentum along the line of centres, with masses (real hard "
                   "disks)");
  run->add_option("--restitution", args.restitution,
                  "Coefficient of normal restitution E in (0, 1] for --rule elastic; E < 1 makes "
                  "collisions inelastic (granular gas)")
      ->default_str("1");
  run->add_option("--tc", args.tc,
                  "TC model against inelastic collapse: a collision of a disk that collided less "
                  "than this long ago is elastic")
      ->default_str("1e-5");
  add_choice<Boundary>(run, "--boundary", args.boundary,
                       {{"walls", Boundary::walls}, {"periodic", Boundary::periodic}},
                       "walls: hard walls on all four sides (the seed's box); periodic: the box "
                       "repeats, no walls (sides must exceed two diameters)");
  run->add_option("--equilibrate", args.equilibrate,
                  "Measure observables only from this time on (the dynamics are unchanged)")
      ->default_str("0");
  run->add_flag(
      "--check", args.check,
      "Verify during the run that event times never decrease and, every --check-every "
      "events, that no disks overlap or leave the box; a violation stops the run (exit 1)");
  run->add_option("--check-every", args.check_every,
                  "Events between overlap checks (default: N, at least 1000)");
  run->add_flag("-q,--quiet", args.quiet,
                "No progress line (shown on stderr during long runs when it is a terminal)");
  add_choice<EngineKind>(run, "--engine", args.engine,
                         {{"fast", EngineKind::fast}, {"reference", EngineKind::reference}},
                         "fast: cell grid and event calendar, O(1) per event; reference: the "
                         "seed's algorithm, every pair checked after every event (O(N^2), for "
                         "checking)");
  run->add_option("--checkpoint", args.checkpoint,
                  "Save the complete state of the run to this file at the end, every "
                  "--checkpoint-every, and on SIGINT or SIGTERM (then stop)");
  run->add_option("--checkpoint-every", args.checkpoint_every,
                  "How often to save: a number of events (1000000) or of seconds (600s)");
  auto* resume = run->add_flag("--resume", args.resume,
                               "FILE is a checkpoint: continue that run to END_TIME, exactly as "
                               "if it had never stopped (its rule, boundary and engine apply)");
  for (const char* fixed_by_checkpoint :
       {"--rule", "--restitution", "--tc", "--boundary", "--equilibrate", "--engine"}) {
    run->get_option(fixed_by_checkpoint)->excludes(resume);
  }
  return run;
}

namespace {

// END_TIME as a number the run can reach: not negative, not beyond what a double resolves.
double parse_end_time(const std::string& text) {
  const double end_time = parse_number(text, "END_TIME");
  if (end_time < 0.0) {
    throw UsageError(fmt::format("END_TIME must not be negative, got {}", text));
  }
  // Times are absolute doubles: beyond this, a double resolves time only to 1e-4 and collisions
  // would pile up at one instant (time re-basing is not implemented yet).
  constexpr double kLatestTime = 1e12;
  if (end_time > kLatestTime) {
    throw UsageError(fmt::format(
        "END_TIME {} is beyond {}, where time is resolved too coarsely; rescale the time unit",
        text, kLatestTime));
  }
  return end_time;
}

// Refuses a start that cannot reach END_TIME: before the checkpoint, or needing more box
// crossings than could ever be processed.
void check_reachable(const Start& start, const std::string& end_text, double end_time) {
  if (end_time < start.checkpoint.time) {
    throw UsageError(fmt::format("END_TIME {} is before the checkpoint's time {}", end_text,
                                 start.checkpoint.time));
  }
  const double crossings =
      most_crossings(start.checkpoint.system, end_time - start.checkpoint.time);
  if (crossings > kMostCrossings) {
    throw UsageError(fmt::format(
        "a disk could cross the box about {:.3g} times before END_TIME (at the highest speed "
        "its energy allows), more than the {:.0e} carom can process: check the velocities, "
        "masses, box and time unit",
        crossings, kMostCrossings));
  }
}

// Every file a run writes, opened (as temporary files) before it starts and committed together
// at the end, so that a failed run leaves none of them behind.
struct RunOutputs {
  explicit RunOutputs(const RunArguments& args) : main(args.output) {
    if (!args.summary.empty()) summary.emplace(args.summary);
    if (!args.dump.empty()) {
      try {
        frames = trajectory_writer_for(args.dump);
      } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
      }
      dump.emplace(args.dump);
    }
    if (!args.events.empty()) {
      events.emplace(args.events);
      events->stream() << "time,kind,first,partner\n";
    }
  }

  void commit() {
    main.commit();
    if (dump) dump->commit();
    if (events) events->commit();
    if (summary) summary->commit();
  }

  Output main;
  std::optional<Output> summary, dump, events;
  std::unique_ptr<TrajectoryWriter> frames;
};

// Runs the engine to END_TIME, stopping at every frame time and at the end of equilibration;
// stopping changes nothing (events are processed as they come), so the dynamics are the same
// with or without them. Returns the kinetic energy the measurement started from.
template <class OnEvent>
double simulate(Engine<2>& engine, const RunArguments& args, const Start& start,
                const Checkpoint& saved, double end_time, RunOutputs& outputs,
                CheckpointWriter& checkpoints, OnEvent&& on_event) {
  const double equilibrate = saved.equilibrate;
  TrajectoryWriter* const frames = outputs.frames.get();
  // Frames fall on multiples of --every, counted from t = 0 also when resuming.
  auto frame = static_cast<std::uint64_t>(frames ? std::ceil(engine.time() / args.every) : 0.0);
  double next_frame = frames ? static_cast<double>(frame) * args.every : kNever;
  if (next_frame > end_time) next_frame = kNever;
  bool equilibrating = equilibrate > engine.time() ||
                       (equilibrate > 0.0 && equilibrate == engine.time() && !start.resumed);
  double kinetic_energy_initial =
      start.resumed ? saved.kinetic_energy_initial : kinetic_energy(engine.system());
  checkpoints.set_kinetic_energy_initial(kinetic_energy_initial);
  while (true) {
    const double stop = std::min({next_frame, equilibrating ? equilibrate : kNever, end_time});
    while (const auto event = engine.step(stop)) on_event(*event);
    if (equilibrating && stop == equilibrate) {
      engine.reset_counts();
      kinetic_energy_initial = kinetic_energy(engine.system());
      checkpoints.set_kinetic_energy_initial(kinetic_energy_initial);
      equilibrating = false;
    }
    if (stop == next_frame) {
      frames->frame(outputs.dump->stream(), stop, engine.system());
      next_frame = static_cast<double>(++frame) * args.every;
      if (next_frame > end_time) next_frame = kNever;
    }
    if (stop == end_time) break;
  }
  // Saved before the particles are brought to the end time, so that a resumed run continues
  // from exactly the state an uninterrupted one would have.
  checkpoints.save(engine);
  engine.finish(end_time);
  return kinetic_energy_initial;
}

// The final state in the chosen format, and the summary.
void write_results(const RunArguments& args, const RunSettings& settings, const Engine<2>& engine,
                   std::optional<TraceWriter>& trace, RunOutputs& outputs) {
  const auto& particles = engine.system().particles;
  if (trace) {
    trace->finish(particles);
  } else if (args.format == Format::table) {
    write_table(outputs.main.stream(), particles);
  } else if (args.format == Format::csv) {
    write_csv(outputs.main.stream(), particles);
  } else {
    write_json(outputs.main.stream(), settings, engine);
  }
  if (outputs.summary) write_json(outputs.summary->stream(), settings, engine, false);
}

}  // namespace

void run_command(const RunArguments& args) {
  const double end_time = parse_end_time(args.end_time);
  check(args, end_time);
  Start start = args.resume ? resume_from(args.input) : start_from(args);
  check_reachable(start, args.end_time, end_time);
  RunOutputs outputs(args);

  Checkpoint& saved = start.checkpoint;
  auto engine = make_engine(saved.engine, std::move(saved.system), saved.rule);
  engine->restore_counts(saved.counts);
  const auto& particles = engine->system().particles;
  CheckpointWriter checkpoints(args, saved);
  InvariantChecker invariants(args.check, args.check_every > 0
                                              ? args.check_every
                                              : std::max<std::uint64_t>(1000, particles.size()));
  std::optional<TraceWriter> trace;
  if (args.trace) {
    trace.emplace(outputs.main.stream());
    trace->start(args.input, end_time, particles);
  }
  Progress progress(engine->time(), end_time, args.quiet);
  const auto on_event = [&](const Event& event) {
    if (trace) trace->event(event, particles);
    if (outputs.events) {
      outputs.events->stream() << fmt::format("{},{},{},{}\n", event.time,
                                              event.is_wall() ? "wall" : "pair", event.first,
                                              event.partner);
    }
    progress.update(event.time);
    invariants.after_event(*engine, event);
    checkpoints.after_event(*engine);
  };

  const auto started = std::chrono::steady_clock::now();
  const double kinetic_energy_initial =
      simulate(*engine, args, start, saved, end_time, outputs, checkpoints, on_event);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  const RunSettings settings{saved.input, end_time,     saved.equilibrate,
                             saved.rule,  saved.engine, kinetic_energy_initial,
                             seconds};
  write_results(args, settings, *engine, trace, outputs);
  outputs.commit();
}

}  // namespace carom::cli
