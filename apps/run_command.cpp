#include "run_command.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "carom/checkpoint.hpp"
#include "carom/classic_input.hpp"
#include "carom/gsd.hpp"
#include "carom/initial.hpp"
#include "carom/observables.hpp"
#include "carom/overlap.hpp"
#include "carom/simulation.hpp"
#include "carom/time_series.hpp"
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
walls, -5 back (z = 0) and -6 front (z = Lz); every output then carries z.
Comment lines start with #. Files carom writes (init, compress) begin with one that records how
they are meant to be run, `# carom: boundary=periodic rule=elastic`: the run takes those unless
--boundary or --rule say otherwise. A plain file runs with walls and the swap rule, as the classic
assignment's do (with --boundary periodic, the elastic rule).)";

constexpr const char* kExamples = R"(Examples:
  carom run examples/walls_only.txt 20            final state, the classic assignment's table
  carom run examples/normal.txt 20 --format csv   x, y, wall and disk collision counts
  carom run examples/normal.txt 20 --trace        every collision, step by step
  carom run examples/normal.txt 100 --format json -o result.json
  carom run gas.txt 200 --equilibrate 50 --format json     (gas.txt from carom init)
  carom run gas.txt 1e4 --checkpoint run.ckpt --dump movie.xyz --every 10
  carom run --resume run.ckpt 2e4 --equilibrate 1e4 --dump movie.xyz --every 10 --format json
  carom run spheres.txt 100 --format json                  (carom init --dim 3))";

// --checkpoint-every: a number of events (1000000) or of seconds (600s).
Trigger checkpoint_trigger(const std::string& every) {
  const bool seconds = !every.empty() && every.back() == 's';
  const double value =
      parse_number(seconds ? every.substr(0, every.size() - 1) : every, "--checkpoint-every");
  if (!(value > 0.0)) throw UsageError("--checkpoint-every must be greater than 0");
  if (seconds) return Trigger::every_seconds(value);
  if (value < 1.0 || value != std::floor(value)) {
    throw UsageError("--checkpoint-every counts events: a whole number, or seconds as 600s");
  }
  // Beyond this a double no longer holds every whole number, and no run has so many events.
  constexpr double kMostEvents = 9007199254740992.0;  // 2^53
  if (value > kMostEvents) {
    throw UsageError(
        fmt::format("--checkpoint-every {} is more events than a run can have (at most 2^53 = {})",
                    every, kMostEvents));
  }
  return Trigger::every_events(static_cast<std::uint64_t>(value));
}

// Whether two paths name one file: the same file if both exist (hard links, symlinks and
// other spellings included), else the same absolute path once symbolic links are resolved.
bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) return fs::equivalent(a, b, error);
  const fs::path pa = fs::weakly_canonical(fs::absolute(a, error), error);
  const fs::path pb = fs::weakly_canonical(fs::absolute(b, error), error);
  return pa == pb;
}

// Refuses two outputs (or an output and the input) that are one file: one would overwrite the
// other. A resumed run may save its checkpoint where it read it.
void check_distinct_outputs(const RunArguments& args) {
  std::vector<std::pair<std::string, std::string>> files;  // what, path
  if (args.input != "-") files.emplace_back("the input FILE", args.input);
  for (const auto& [flag, path] : {std::pair<const char*, const std::string&>{"-o", args.output},
                                   {"--summary", args.summary},
                                   {"--checkpoint", args.checkpoint},
                                   {"--dump", args.dump},
                                   {"--events", args.events},
                                   {"--log", args.log}}) {
    if (!path.empty() && path != "-") files.emplace_back(flag, path);
  }
  for (std::size_t i = 0; i < files.size(); ++i) {
    for (std::size_t j = i + 1; j < files.size(); ++j) {
      const bool continued = args.resume && i == 0 && files[j].first == "--checkpoint";
      if (!continued && same_file(files[i].second, files[j].second)) {
        throw UsageError(
            fmt::format("{} and {} name the same file ({} and {}): one would "
                        "overwrite the other",
                        files[i].first, files[j].first, files[i].second, files[j].second));
      }
    }
  }
}

// Options that only make sense together, and ranges the parser cannot check alone.
void check(const RunArguments& args) {
  if (args.trace && args.format != Format::table) {
    throw UsageError(
        "--trace prints the classic assignment's step-by-step table; it cannot be combined with "
        "--format csv or json");
  }
  if (!(args.restitution > 0.0 && args.restitution <= 1.0)) {
    throw UsageError(fmt::format("--restitution must be in (0, 1], got {}", args.restitution));
  }
  if (args.restitution < 1.0 && args.rule == Rule::swap) {
    throw UsageError(
        "--restitution below 1 needs --rule elastic (the swap rule has no restitution)");
  }
  if (!(args.tc >= 0.0)) throw UsageError(fmt::format("--tc must be >= 0, got {}", args.tc));
  if (!args.dump.empty() && !(args.every > 0.0 && std::isfinite(args.every))) {
    throw UsageError("--dump needs --every DT > 0: the time between frames");
  }
  if (args.dump.empty() && args.every != 0.0) throw UsageError("--every needs --dump FILE");
  if (!args.log.empty() && !(args.log_every > 0.0 && std::isfinite(args.log_every))) {
    throw UsageError("--log needs --log-every DT > 0: the time between rows");
  }
  if (args.log.empty() && args.log_every != 0.0) throw UsageError("--log-every needs --log FILE");
  if (!args.checkpoint_every.empty() && args.checkpoint.empty()) {
    throw UsageError("--checkpoint-every needs --checkpoint FILE: where to save");
  }
  if (!args.checkpoint_every.empty()) checkpoint_trigger(args.checkpoint_every);
  check_distinct_outputs(args);
  if (args.equilibrate && !(*args.equilibrate >= 0.0)) {
    throw UsageError(fmt::format("--equilibrate must be >= 0, got {}", *args.equilibrate));
  }
  check_progress(args.progress);
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
  std::string note;  // what the start's reading decided without being asked, and why
};

// Says which of the run's boundary and rule were not asked for and are not the classic
// assignment's (walls, swap), and where they came from: the file's record, or the physical rule
// of a periodic box. Nothing when the run is the classic assignment's or was asked for whole.
std::string describe_defaults(const RunArguments& args, const StartRecord& record,
                              Boundary boundary, Rule rule) {
  const bool periodic = !args.boundary && boundary == Boundary::periodic;
  const bool elastic = !args.rule && rule == Rule::elastic && args.restitution == 1.0;
  if (!periodic && !elastic) return "";
  const std::string taken = periodic && elastic ? "periodic boundary and elastic rule"
                            : periodic          ? "periodic boundary"
                                                : "elastic rule";
  if (record.boundary || record.rule) {
    return fmt::format("{}, as {} records ({} choose{} otherwise)", taken, args.input,
                       periodic && elastic ? "--boundary and --rule"
                       : periodic          ? "--boundary"
                                           : "--rule",
                       periodic && elastic ? "" : "s");
  }
  return "elastic rule, the physical one in a periodic box (--rule swap is the classic "
         "assignment's)";
}

Start load(const RunArguments& args) {
  if (args.resume) {
    std::ifstream file = open_input(args.input);
    return std::visit(
        [&](const auto& checkpoint) {
          using Sim = SimulationFor<decltype(checkpoint)>;
          return Start{AnySimulation(std::in_place_type<Sim>, checkpoint), checkpoint.source, true,
                       ""};
        },
        read_checkpoint(file, args.input));
  }
  return std::visit(
      [&](auto&& input) {
        using Sim = SimulationFor<decltype(input)>;
        const Boundary boundary = input.system.box.boundary;
        const Rule rule =
            args.rule.value_or(default_rule(input.record, boundary, args.restitution));
        const Settings settings{{rule, args.restitution, args.tc}, args.engine};
        std::string note = describe_defaults(args, input.record, boundary, rule);
        if (args.temperature) {
          try {
            draw_velocities(input.system, *args.temperature, args.seed);
          } catch (const std::invalid_argument& e) {
            throw UsageError(fmt::format("--kT: {}", e.what()));
          }
        } else if (kinetic_energy(input.system) == 0.0) {
          note += std::string(note.empty() ? "" : "; ") +
                  "every particle is at rest (kT = 0), so nothing will happen: --kT T draws "
                  "Maxwell-Boltzmann velocities";
        }
        // Only for the reader's messages: not held while the engine is made (a move frees it;
        // `= {}` would keep its capacity).
        input.line_of = std::vector<std::size_t>();
        return Start{AnySimulation(std::in_place_type<Sim>, std::move(input.system), settings),
                     args.input, false, std::move(note)};
      },
      read_any_start_file(args.input, args.boundary));
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

// The format --dump names by its ending; an unknown ending is a usage error.
template <std::size_t D>
std::unique_ptr<TrajectoryFormat<D>> dump_format(const std::string& path) {
  try {
    return trajectory_format_for<D>(path);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

// Every file a run writes. The result (-o) and the summary appear whole at the end or not at all;
// frames and the event log are written as the run goes.
template <std::size_t D>
struct RunOutputs {
  RunOutputs(const RunArguments& args, const Simulation<D>& simulation, bool resumed)
      : main(args.output) {
    for (const std::string& streamed : {args.dump, args.events, args.log}) {
      if (!streamed.empty()) check_writable(streamed);
    }
    if (!args.summary.empty()) summary.emplace(args.summary);
    const double t = simulation.time();
    const bool inclusive = simulation.settled();
    if (!args.dump.empty()) {
      std::unique_ptr<TrajectoryFormat<D>> format = dump_format<D>(args.dump);
      dump = open_streamed(args.dump, resumed, [&](std::istream& in) {
        try {
          return format->whole_frames_before(in, t, inclusive, args.every);
        } catch (const std::invalid_argument& e) {  // a format that cannot be continued
          throw UsageError(e.what());
        }
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
    if (!args.log.empty()) {
      time_series = std::make_shared<TimeSeriesWriter<D>>(log, args.log_every);
      log = open_streamed(args.log, resumed, [&](std::istream& in) {
        return time_series->resume(in, t, inclusive, simulation);
      });
      if (log.tellp() == 0) log << TimeSeriesWriter<D>::kHeader;
    }
  }

  Output main;
  std::optional<Output> summary;
  std::ofstream dump, events, log;
  std::shared_ptr<FrameWriter<D>> frames;
  std::shared_ptr<EventLogWriter<D>> event_log;
  std::shared_ptr<TimeSeriesWriter<D>> time_series;
};

// Refuses a dump that would not fit on its disk: the frames still to come times the size of one
// (measured on up to 1000 particles and scaled to all of them), against the free space.
template <std::size_t D>
void check_dump_fits(const Simulation<D>& simulation, const RunArguments& args, double end_time) {
  namespace fs = std::filesystem;
  const System<D>& state = simulation.state();
  System<D> sample;
  sample.box = state.box;
  sample.epoch = state.epoch;
  const std::size_t taken = std::min<std::size_t>(state.size(), 1000);
  sample.particles.assign(state.particles.begin(), state.particles.begin() + taken);
  sample.records.assign(state.records.begin(), state.records.begin() + taken);
  std::ostringstream one;
  dump_format<D>(args.dump)->frame(one, 0, simulation.time(), sample);
  const double frame_bytes = static_cast<double>(one.tellp()) * static_cast<double>(state.size()) /
                             static_cast<double>(taken);
  const double frames =
      std::floor(end_time / args.every) - std::floor(simulation.time() / args.every) + 1.0;
  fs::path folder = fs::absolute(args.dump).parent_path();
  std::error_code error;
  const fs::space_info space = fs::space(folder, error);
  if (error) return;  // nothing known of the disk: the write itself will tell
  if (frames * frame_bytes > static_cast<double>(space.available)) {
    throw UsageError(fmt::format(
        "--dump {} would take about {:.3g} GB ({:.0f} frames of {:.3g} MB) but {} has {:.3g} GB "
        "free: raise --every or lower END_TIME",
        args.dump, frames * frame_bytes / 1e9, frames, frame_bytes / 1e6, folder.string(),
        static_cast<double>(space.available) / 1e9));
  }
}

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
  if (!args.log.empty()) what += fmt::format("; the time series up to then is in {}", args.log);
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
  if (!args.dump.empty()) check_dump_fits(simulation, args, end_time);
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
  if (!start.note.empty() && !args.quiet) {
    std::cerr << "carom: note: " << start.note << '\n';
  }
  const bool periodic = simulation.state().box.periodic();
  if (periodic && simulation.settings().rule.rule == Rule::swap && !args.quiet) {
    std::cerr << "carom: note: the swap rule (the classic assignment's) exchanges whole "
                 "velocities, so the set of speeds never changes and the gas never reaches "
                 "Maxwell-Boltzmann; --rule elastic is the physical one\n";
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
  if (outputs.frames) {
    // A dump that begins here (not one a resumed run continues) starts with a frame now, when
    // now is on its grid.
    simulation.add_observer(outputs.frames, outputs.dump.tellp() == 0
                                                ? Simulation<D>::FirstLook::now
                                                : Simulation<D>::FirstLook::next);
  }
  if (outputs.event_log) simulation.add_observer(outputs.event_log);
  if (outputs.time_series) simulation.add_observer(outputs.time_series);
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
  // Z over 20 intervals of the measurement window, first half against second.
  std::shared_ptr<ZDrift<D>> drift;
  const double window_start =
      simulation.pending_measurement().value_or(simulation.measurement().start_time);
  if (end_time > window_start) {
    drift = std::make_shared<ZDrift<D>>((end_time - window_start) / ZDrift<D>::kIntervals);
    simulation.add_observer(drift);
  }
  if (Progress<D>::wanted(args.quiet, args.progress)) {
    simulation.add_observer(
        std::make_shared<Progress<D>>(simulation.time(), end_time, args.quiet, args.progress));
  }
  simulation.set_stop_flag(&stop_signal());

  const auto started = std::chrono::steady_clock::now();
  const std::uint64_t events_before = simulation.counts().events;
  RunStatus status = RunStatus::reached;
  try {
    status = simulation.run_until(end_time);
  } catch (const std::runtime_error& e) {
    // A write that failed as the run went (a full disk): the state the run has reached is sound
    // and worth keeping when there is somewhere to keep it. A jam or a broken invariant is not.
    const bool broken = dynamic_cast<const JamError*>(&e) != nullptr ||
                        dynamic_cast<const InvariantError*>(&e) != nullptr;
    if (args.checkpoint.empty() || broken) throw;
    save_checkpoint(args.checkpoint, simulation, start.source);
    throw std::runtime_error(fmt::format(
        "{}; the run so far (t = {}) is saved in {}: continue it with 'carom run --resume {} "
        "END_TIME'",
        e.what(), simulation.time(), args.checkpoint, args.checkpoint));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  // The streamed files are complete (or the failure is known) before any result is written.
  const bool streamed_ok = static_cast<bool>(outputs.dump.flush()) && outputs.events.flush();
  if (!args.checkpoint.empty()) save_checkpoint(args.checkpoint, simulation, start.source);
  if (!streamed_ok) {
    throw std::runtime_error(
        fmt::format("cannot write the trajectory or the event log (is the disk full?){}",
                    args.checkpoint.empty()
                        ? std::string()
                        : fmt::format("; the run's end state is saved in {}", args.checkpoint)));
  }
  if (status == RunStatus::stopped) {
    throw Interrupted(stop_signal().load(), describe_signal(stop_signal().load()) + ": " +
                                                interruption(simulation, args));
  }

  RunReport report;
  report.input = start.source;
  report.wall_seconds = seconds;
  report.events = simulation.counts().events - events_before;
  if (args.temperature) report.seed = args.seed;
  report.drift = drift ? drift->verdict() : std::nullopt;
  if (report.drift && report.drift->drifted() && !args.quiet) {
    std::cerr << fmt::format(
        "carom: warning: Z drifted from {:.6g} (first half of the measurement window) to {:.6g} "
        "(second half), {:.1f} standard errors: the system was still changing while measured "
        "(equilibrate longer: --equilibrate)\n",
        report.drift->first, report.drift->second, report.drift->sigmas);
  }
  if (trace) {
    trace->finish(simulation);
  } else if (args.format == Format::table) {
    write_table(outputs.main.stream(), simulation);
  } else if (args.format == Format::csv) {
    write_csv(outputs.main.stream(), simulation);
  } else {
    write_json(outputs.main.stream(), simulation, report);
  }
  if (outputs.summary) write_json(outputs.summary->stream(), simulation, report, false);
  outputs.main.commit();
  if (outputs.summary) outputs.summary->commit();
}

}  // namespace

CLI::App* add_run_command(CLI::App& app, RunArguments& args) {
  CLI::App* run = app.add_subcommand(
      "run", "Simulate FILE from t = 0 to END_TIME and print every particle's final state.");
  run->footer(std::string(kFormatHelp) + "\n\n" + kExamples);
  run->add_option("FILE", args.input,
                  "Input in the classic format (see below); - reads stdin; FILE.gsd or "
                  "FILE.gsd:K starts from the last frame or frame K of a GSD file (periodic)")
      ->required();
  run->add_option("END_TIME", args.end_time, "Time to simulate to (a number >= 0)")->required();
  add_choice<Format>(
      run, "--format", args.format,
      "table: the classic assignment's `particle i: (x, y) (vx, vy): t : (cwall, cpart)` lines; "
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
      "as the run goes: .xyz (extended XYZ, for OVITO and ASE), .lammpstrj (LAMMPS "
      "text dump) or .gsd (HOOMD-blue's GSD, for HOOMD, OVITO and freud). A resumed run "
      "continues the same .xyz or .lammpstrj file");
  run->add_option("--every", args.every, "Time between --dump frames")->check(finite_number());
  run->add_option(
      "--events", args.events,
      "Write every collision to this csv file as the run goes: "
      "time,kind,first,partner (kind wall or pair; partner a particle or a wall label)");
  run->add_option("--log", args.log,
                  "Write a time series to this csv file as the run goes, a row every --log-every "
                  "DT: the temperature, and the pressure, Z and collision rate over each "
                  "interval, with running means and block-average errors over the measurement "
                  "window (like LAMMPS' thermo). A resumed run continues the same file");
  run->add_option("--log-every", args.log_every, "Time between --log rows")->check(finite_number());
  run->add_option("--summary", args.summary,
                  "Also write the json settings, counts and observables (no particles) to this "
                  "file");
  add_choice<Rule>(run, "--rule", args.rule,
                   "swap: touching disks exchange whole velocities (the classic assignment's "
                   "rule); elastic: they exchange momentum along the line of centres, with "
                   "masses (real hard disks). Default: what the file records (carom init and "
                   "compress record elastic), else swap with walls and elastic in a periodic box")
      ->default_str("from the file");
  run->add_option("--restitution", args.restitution,
                  "Coefficient of normal restitution E in (0, 1] for --rule elastic; E < 1 makes "
                  "collisions inelastic (granular gas)")
      ->check(finite_number())
      ->default_str("1");
  run->add_option("--tc", args.tc,
                  "TC model against inelastic collapse: a collision of a disk that collided less "
                  "than this long ago is elastic")
      ->check(finite_number())
      ->default_str(fmt::format("{}", kDefaultTc));
  add_choice<Boundary>(run, "--boundary", args.boundary,
                       "walls: hard walls on every side (the classic assignment's box); periodic: "
                       "the box repeats, no walls (sides must exceed two diameters). Default: what "
                       "the file records (carom init and compress record theirs), else walls")
      ->default_str("from the file");
  run->add_option("--equilibrate", args.equilibrate,
                  "Measure observables only from this time on (the dynamics are unchanged); with "
                  "--resume, from this time on in the resumed run")
      ->check(finite_number())
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
  add_progress_option(run, args.progress);
  run->add_option("--kT", args.temperature,
                  "Give every particle a new velocity, Maxwell-Boltzmann at this temperature "
                  "(zero total momentum, kT exact), as carom init does: for a start without "
                  "velocities, or to rethermalise one")
      ->check(finite_number());
  run->add_option("--seed", args.seed, "Random seed of --kT's velocities")->default_str("1");
  add_choice<EngineKind>(run, "--engine", args.engine,
                         "fast: neighbour lists (dense systems) or a cell grid, and an event "
                         "calendar, O(1) per event; reference: the classic assignment's "
                         "algorithm, every pair checked after every event (O(N^2), for "
                         "checking)");
  run->add_option("--checkpoint", args.checkpoint,
                  "Save the complete state of the run to this file at the end, every "
                  "--checkpoint-every, and on SIGINT, SIGTERM or SIGHUP (then stop)");
  run->add_option("--checkpoint-every", args.checkpoint_every,
                  "How often to save: a number of events (1000000) or of seconds (600s)");
  auto* resume = run->add_flag("--resume", args.resume,
                               "FILE is a checkpoint: continue that run to END_TIME, exactly as "
                               "if it had never stopped (its rule, boundary and engine apply)");
  run->get_option("--seed")->needs(run->get_option("--kT"));
  for (const char* fixed_by_checkpoint :
       {"--rule", "--restitution", "--tc", "--boundary", "--engine", "--kT"}) {
    run->get_option(fixed_by_checkpoint)->excludes(resume);
  }
  return run;
}

void run_command(const RunArguments& args) {
  // + 0.0 makes -0 a plain 0, which is what the results then print.
  const double end_time = parse_number(args.end_time, "END_TIME") + 0.0;
  if (end_time < 0.0) {
    throw UsageError(fmt::format("END_TIME must not be negative, got {}", args.end_time));
  }
  check(args);
  Start start = load(args);
  std::visit([&](auto& simulation) { run(simulation, args, start, end_time); }, start.simulation);
}

}  // namespace carom::cli
