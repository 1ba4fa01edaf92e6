#include "run_command.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include "carom/checkpoint.hpp"
#include "carom/classic_input.hpp"
#include "carom/overlap.hpp"
#include "carom/simulation.hpp"
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
Walls are labelled -1 left, -2 right, -3 bottom, -4 top; disks 0..N-1.
Three numbers on line 3 (Lx Ly Lz) make it spheres, with lines x y z vx vy vz [r [m]] and two more
walls, -5 back (z = 0) and -6 front (z = Lz); every output then carries z.)";

constexpr const char* kExamples = R"(Examples:
  carom run examples/walls_only.txt 20            final state, the seed's table
  carom run examples/normal.txt 20 --format csv   x, y, wall and disk collision counts
  carom run examples/normal.txt 20 --trace        every collision, step by step
  carom run examples/normal.txt 100 --format json -o result.json
  carom run gas.txt 200 --rule elastic --boundary periodic --equilibrate 50 --format json
  carom run gas.txt 1e4 --rule elastic --boundary periodic --checkpoint run.ckpt --dump movie.xyz --every 10
  carom run --resume run.ckpt 2e4 --equilibrate 1e4 --dump movie.xyz --every 10 --format json
  carom run spheres.txt 100 --rule elastic --boundary periodic --format json   (carom init --dim 3))";

// Options that only make sense together, and ranges the parser cannot check alone.
void check(const RunArguments& args) {
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
  if (!args.checkpoint_every.empty() && args.checkpoint.empty()) {
    throw UsageError("--checkpoint-every needs --checkpoint FILE: where to save");
  }
  if (args.equilibrate && !(*args.equilibrate >= 0.0)) {
    throw UsageError(fmt::format("--equilibrate must be >= 0, got {}", *args.equilibrate));
  }
}

// --checkpoint-every: a number of events (1000000) or of seconds (600s).
Trigger checkpoint_trigger(const std::string& every) {
  const bool seconds = every.back() == 's';
  const double value =
      parse_number(seconds ? every.substr(0, every.size() - 1) : every, "--checkpoint-every");
  if (!(value > 0.0)) throw UsageError("--checkpoint-every must be greater than 0");
  if (seconds) return Trigger::every_seconds(value);
  if (value < 1.0 || value != std::floor(value)) {
    throw UsageError("--checkpoint-every counts events: a whole number, or seconds as 600s");
  }
  return Trigger::every_events(static_cast<std::uint64_t>(value));
}

// The Simulation for what was read (a ClassicInput or a Checkpoint of either dimension).
template <class Read>
using SimulationFor =
    Simulation<std::remove_cvref_t<decltype(std::declval<Read>().system)>::dimension>;

// Where a run begins: a classic file, or a checkpoint to resume. The dimension is chosen here,
// once.
struct Start {
  AnySimulation simulation;
  std::string source;  // the file the run began from
  bool resumed = false;
};

Start load(const RunArguments& args) {
  if (args.resume) {
    std::ifstream file = open_input(args.input);
    return std::visit(
        [&](const auto& checkpoint) {
          using Sim = SimulationFor<decltype(checkpoint)>;
          return Start{AnySimulation(std::in_place_type<Sim>, checkpoint), checkpoint.source, true};
        },
        read_checkpoint(file, args.input));
  }
  const Settings settings{{args.rule, args.restitution, args.tc}, args.engine};
  return std::visit(
      [&](auto&& input) {
        using Sim = SimulationFor<decltype(input)>;
        return Start{AnySimulation(std::in_place_type<Sim>, std::move(input.system), settings),
                     args.input, false};
      },
      read_any_classic_file(args.input, args.boundary));
}

// Refuses, before anything is created, a path that cannot be written: its folder is missing or
// not writable, or it is a folder itself.
void check_writable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(path, error)) {
    throw UsageError(fmt::format("cannot write '{}': it is a directory", path));
  }
  fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  if (!fs::is_directory(folder, error)) {
    throw UsageError(fmt::format("cannot write '{}': no folder {}", path, folder.string()));
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    throw UsageError(fmt::format("cannot write '{}': {}", path, std::strerror(errno)));
  }
}

// A file written as the run goes (frames, the event log): kept when the run stops early. A
// resumed run continues it: whatever it holds from after the checkpoint (written by a run killed
// after its last checkpoint) is cut off first, so that pieces of a run give one file.
std::ofstream open_streamed(const std::string& path, bool resumed,
                            const std::function<std::uint64_t(std::istream&)>& keep) {
  namespace fs = std::filesystem;
  std::error_code error;
  auto mode = std::ios::binary | std::ios::trunc;
  if (resumed && fs::is_regular_file(path, error)) {
    std::uint64_t kept = 0;
    {
      std::ifstream in(path, std::ios::binary);
      kept = keep(in);
    }
    fs::resize_file(path, kept, error);
    if (error) throw UsageError(fmt::format("cannot continue '{}': {}", path, error.message()));
    mode = std::ios::binary | std::ios::app;
  }
  std::ofstream out(path, mode);
  if (!out) throw UsageError(fmt::format("cannot write '{}': {}", path, std::strerror(errno)));
  return out;
}

// Every file a run writes. The result (-o) and the summary appear whole at the end or not at all;
// frames and the event log are written as the run goes.
template <std::size_t D>
struct RunOutputs {
  RunOutputs(const RunArguments& args, const Simulation<D>& simulation, bool resumed)
      : main(args.output) {
    for (const std::string& streamed : {args.dump, args.events}) {
      if (!streamed.empty()) check_writable(streamed);
    }
    if (!args.summary.empty()) summary.emplace(args.summary);
    const double t = simulation.time();
    const bool inclusive = simulation.settled();
    if (!args.dump.empty()) {
      std::unique_ptr<TrajectoryFormat<D>> format;
      try {
        format = trajectory_format_for<D>(args.dump);
      } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
      }
      dump = open_streamed(args.dump, resumed, [&](std::istream& in) {
        return format->whole_frames_before(in, t, inclusive, args.every);
      });
      frames = std::make_shared<FrameWriter<D>>(dump, std::move(format), args.every);
    }
    if (!args.events.empty()) {
      events = open_streamed(args.events, resumed, [&](std::istream& in) {
        return EventLogWriter<D>::events_before(in, t, inclusive);
      });
      if (events.tellp() == 0) events << EventLogWriter<D>::kHeader;
      event_log = std::make_shared<EventLogWriter<D>>(events);
    }
  }

  Output main;
  std::optional<Output> summary;
  std::ofstream dump, events;
  std::shared_ptr<FrameWriter<D>> frames;
  std::shared_ptr<EventLogWriter<D>> event_log;
};

// What an interrupted run says it kept.
template <std::size_t D>
std::string interruption(const Simulation<D>& simulation, const RunArguments& args) {
  std::string what = fmt::format("stopped at t = {} after {} events; ", simulation.time(),
                                 simulation.counts().events);
  what += args.checkpoint.empty()
              ? "nothing to resume from (give --checkpoint FILE to keep a run's state)"
              : fmt::format(
                    "the run so far is saved in {0}: continue it with 'carom run --resume {0} "
                    "END_TIME'",
                    args.checkpoint);
  if (!args.dump.empty()) what += fmt::format("; frames up to then are in {}", args.dump);
  if (!args.events.empty()) what += fmt::format("; events up to then are in {}", args.events);
  return what;
}

template <std::size_t D>
void run(Simulation<D>& simulation, const RunArguments& args, const Start& start, double end_time) {
  try {
    simulation.check_target(end_time);
  } catch (const RunLengthError& e) {
    throw UsageError(fmt::format("END_TIME {}", e.what()));
  }
  if (!args.dump.empty() && (end_time - simulation.time()) / args.every > 1e7) {
    throw UsageError(
        fmt::format("--every {} would write more than 10^7 frames up to {}", args.every, end_time));
  }
  if (args.equilibrate) {
    const double from = *args.equilibrate;
    if (start.resumed && from < simulation.time()) {
      throw UsageError(fmt::format(
          "--equilibrate {} is before the checkpoint's time {}: the measurement can only start "
          "from there on",
          from, simulation.time()));
    }
    // A checkpointed run may stop before its equilibration ends: the resumed run finishes it.
    if (from > end_time && args.checkpoint.empty()) {
      throw UsageError(fmt::format("--equilibrate must be between {} and END_TIME ({}), got {}",
                                   simulation.time(), end_time, from));
    }
    simulation.measure_from(from);
  }
  const bool periodic = simulation.state().box.periodic();
  if (periodic && simulation.settings().rule.rule == Rule::swap && !args.quiet) {
    std::cerr << "carom: note: the swap rule (the seed's) exchanges whole velocities, so the set "
                 "of speeds never changes and the gas never reaches Maxwell-Boltzmann; --rule "
                 "elastic is the physical one\n";
  }

  if (!args.checkpoint.empty()) {
    // Creating (and dropping) a temporary file beside it checks the path before the run.
    try {
      const AtomicFile probe(args.checkpoint);
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
  }
  RunOutputs<D> outputs(args, simulation, start.resumed);
  std::shared_ptr<TraceWriter<D>> trace;
  if (args.trace) {
    trace = std::make_shared<TraceWriter<D>>(outputs.main.stream());
    trace->start(args.input, end_time, simulation);
    simulation.add_observer(trace);
  }
  if (outputs.frames) simulation.add_observer(outputs.frames);
  if (outputs.event_log) simulation.add_observer(outputs.event_log);
  if (args.check) {
    const std::uint64_t every = args.check_every > 0
                                    ? args.check_every
                                    : std::max<std::uint64_t>(1000, simulation.state().size());
    simulation.add_observer(std::make_shared<InvariantCheck<D>>(every));
  }
  if (!args.checkpoint_every.empty()) {
    simulation.add_observer(std::make_shared<CheckpointWriter<D>>(
        args.checkpoint, start.source, checkpoint_trigger(args.checkpoint_every)));
  }
  if (Progress<D>::wanted(args.quiet)) {
    simulation.add_observer(std::make_shared<Progress<D>>(simulation.time(), end_time));
  }
  simulation.set_stop_flag(&stop_signal());

  const auto started = std::chrono::steady_clock::now();
  const RunStatus status = simulation.run_until(end_time);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  outputs.dump.flush();
  outputs.events.flush();
  if (!args.checkpoint.empty()) save_checkpoint(args.checkpoint, simulation, start.source);
  if (status == RunStatus::stopped) {
    throw Interrupted(stop_signal().load(), describe_signal(stop_signal().load()) + ": " +
                                                interruption(simulation, args));
  }

  const RunReport report{start.source, seconds};
  const System<D>& state = simulation.state();
  if (trace) {
    trace->finish(simulation);
  } else if (args.format == Format::table) {
    write_table<D>(outputs.main.stream(), simulation.snapshot(), state.records);
  } else if (args.format == Format::csv) {
    write_csv<D>(outputs.main.stream(), simulation.snapshot(), state.records);
  } else {
    write_json(outputs.main.stream(), simulation, report);
  }
  if (outputs.summary) write_json(outputs.summary->stream(), simulation, report, false);
  if (!outputs.dump.flush() || !outputs.events.flush()) {
    throw std::runtime_error("cannot write the trajectory or the event log");
  }
  outputs.main.commit();
  if (outputs.summary) outputs.summary->commit();
}

}  // namespace

CLI::App* add_run_command(CLI::App& app, RunArguments& args) {
  CLI::App* run = app.add_subcommand(
      "run", "Simulate FILE from t = 0 to END_TIME and print every particle's final state.");
  run->footer(std::string(kFormatHelp) + "\n\n" + kExamples);
  run->add_option("FILE", args.input, "Input in the classic format (see below); - reads stdin")
      ->required();
  run->add_option("END_TIME", args.end_time, "Time to simulate to (a number >= 0)")->required();
  add_choice<Format>(run, "--format", args.format,
                     "table: the seed's `particle i: (x, y) (vx, vy): t : (cwall, cpart)` lines; "
                     "csv: `x, y, cwall, cpart` lines; json: settings, counts, observables and "
                     "full state");
  run->add_flag("--trace", args.trace,
                "Print the initial state, then after every collision its time, what collided and "
                "every particle's stored state, then the final state");
  run->add_option("-o,--output", args.output,
                  "Write to this file (atomically: it appears complete or not at all) instead of "
                  "stdout");
  run->add_option(
      "--dump", args.dump,
      "Write frames of every particle at t = 0, DT, 2 DT, ... (--every DT) to this file "
      "as the run goes: .xyz (extended XYZ, for OVITO and ASE) or .lammpstrj (LAMMPS "
      "text dump). A resumed run continues the same file");
  run->add_option("--every", args.every, "Time between --dump frames");
  run->add_option(
      "--events", args.events,
      "Write every collision to this csv file as the run goes: "
      "time,kind,first,partner (kind wall or pair; partner a particle or a wall label)");
  run->add_option("--summary", args.summary,
                  "Also write the json settings, counts and observables (no particles) to this "
                  "file");
  add_choice<Rule>(run, "--rule", args.rule,
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
      ->default_str(fmt::format("{}", kDefaultTc));
  add_choice<Boundary>(run, "--boundary", args.boundary,
                       "walls: hard walls on all four sides (the seed's box); periodic: the box "
                       "repeats, no walls (sides must exceed two diameters)");
  run->add_option("--equilibrate", args.equilibrate,
                  "Measure observables only from this time on (the dynamics are unchanged); with "
                  "--resume, from this time on in the resumed run")
      ->default_str("0");
  run->add_flag(
      "--check", args.check,
      "Verify during the run that event times never decrease and, every --check-every "
      "events, that no particles overlap or leave the box; a violation stops the run (exit 1)");
  run->add_option("--check-every", args.check_every,
                  "Events between overlap checks (default: N, at least 1000)");
  run->add_flag("-q,--quiet", args.quiet,
                "No progress line (shown on stderr during long runs when it is a terminal) and "
                "no notes");
  add_choice<EngineKind>(run, "--engine", args.engine,
                         "fast: cell grid and event calendar, O(1) per event; reference: the "
                         "seed's algorithm, every pair checked after every event (O(N^2), for "
                         "checking)");
  run->add_option("--checkpoint", args.checkpoint,
                  "Save the complete state of the run to this file at the end, every "
                  "--checkpoint-every, and on SIGINT, SIGTERM or SIGHUP (then stop)");
  run->add_option("--checkpoint-every", args.checkpoint_every,
                  "How often to save: a number of events (1000000) or of seconds (600s)");
  auto* resume = run->add_flag("--resume", args.resume,
                               "FILE is a checkpoint: continue that run to END_TIME, exactly as "
                               "if it had never stopped (its rule, boundary and engine apply)");
  for (const char* fixed_by_checkpoint :
       {"--rule", "--restitution", "--tc", "--boundary", "--engine"}) {
    run->get_option(fixed_by_checkpoint)->excludes(resume);
  }
  return run;
}

void run_command(const RunArguments& args) {
  const double end_time = parse_number(args.end_time, "END_TIME");
  if (end_time < 0.0) {
    throw UsageError(fmt::format("END_TIME must not be negative, got {}", args.end_time));
  }
  check(args);
  Start start = load(args);
  std::visit([&](auto& simulation) { run(simulation, args, start, end_time); }, start.simulation);
}

}  // namespace carom::cli
