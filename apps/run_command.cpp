#include "run_command.hpp"

#include <fmt/format.h>

#include <iostream>
#include <optional>

#include "carom/io/trajectory_kind.hpp"
#include "carom/run/run.hpp"
#include "carom/run/start.hpp"
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

// Options that only make sense together, and ranges the parser cannot check alone; the library
// checks the rest of the run (check_run_spec, Runner::check).
void check(const RunArguments& args) {
  if (args.trace && args.format != Format::table) {
    throw UsageError(
        "--trace prints the classic assignment's step-by-step table; it cannot be combined with "
        "--format csv or json");
  }
  if (!args.resume) {
    try {
      // The file is not read yet: the rule its record may name is left to load_start.
      const StartSpec& start = args.start;
      const Rule rule = start.rule.value_or(
          default_rule({}, start.boundary.value_or(Boundary::walls), start.restitution));
      check_settings({{rule, start.restitution, start.tc}, start.engine});
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  if (args.seed_given && !args.start.temperature && args.start.sampler == SamplerKind::md) {
    throw UsageError(
        "--seed needs --kT T (the velocities it draws, and Andersen's draws) or --sampler ecmc "
        "(the chains' particles it draws): alone it would seed nothing");
  }
  if (!args.checkpoint_every.empty() && args.run.checkpoint.empty()) {
    throw UsageError("--checkpoint-every needs --checkpoint FILE: where to save");
  }
  if (!args.checkpoint_every.empty()) checkpoint_cadence(args.checkpoint_every);
  check_progress(args.progress);
  // -o is the result table: written under a trajectory's name it would read as one to no one.
  if (const std::optional<TrajectoryKind> kind = trajectory_kind_of(args.output)) {
    throw UsageError(fmt::format(
        "-o writes the run's result (the classic table, --format csv or json), not a {} file: "
        "for the end state as a start file to go on from, use --final {}{}",
        extension_of(*kind), args.output,
        kind == TrajectoryKind::gsd ? "" : " (or a .gsd or .txt name: runs start from those)"));
  }
}

StartSpec start_spec(const RunArguments& args) {
  StartSpec spec = args.start;
  spec.thermostat = thermostat_request(args.thermostat, spec.temperature, args.thermostat_every,
                                       args.thermostat_rate, spec.seed, spec.sampler);
  spec.shear = shear_request(args.shear, args.velocity_profile);
  return spec;
}

RunSpec run_spec(const RunArguments& args, double end_time) {
  RunSpec spec = args.run;
  spec.end_time = end_time;
  if (!args.checkpoint_every.empty())
    spec.checkpoint_every = checkpoint_cadence(args.checkpoint_every);
  return spec;
}

// What an interrupted run says it kept.
std::string interruption(const AnySimulation& simulation, const RunSpec& spec) {
  std::string what = fmt::format("stopped at t = {} after {} events; ", simulation.time(),
                                 simulation.counts().events);
  what += spec.checkpoint.empty()
              ? "nothing to resume from (give --checkpoint FILE to keep a run's state)"
              : fmt::format(
                    "the run so far is saved in {0}: continue it with 'carom run --resume {0} "
                    "END_TIME'",
                    spec.checkpoint);
  if (!spec.dump.empty()) what += fmt::format("; frames up to then are in {}", spec.dump);
  if (!spec.events.empty()) what += fmt::format("; events up to then are in {}", spec.events);
  if (!spec.log.empty()) what += fmt::format("; the time series up to then is in {}", spec.log);
  return what;
}

// The notes a run begins with: what the start decided unasked, and a periodic box under the
// swap rule.
void print_notes(const Start& start, const AnySimulation& simulation) {
  if (!start.note.empty()) std::cerr << "carom: note: " << start.note << '\n';
  if (simulation.boundary() == Boundary::periodic &&
      simulation.settings().rule.rule == Rule::swap) {
    std::cerr << "carom: note: the swap rule (the classic assignment's) exchanges whole "
                 "velocities, so the set of speeds never changes and the gas never reaches "
                 "Maxwell-Boltzmann; --rule elastic is the physical one\n";
  }
}

}  // namespace

CLI::App* add_run_command(CLI::App& app, RunArguments& args) {
  CLI::App* run = app.add_subcommand(
      "run", "Simulate FILE from t = 0 to END_TIME and print every particle's final state.");
  run->footer(std::string(kFormatHelp) + "\n\n" + kExamples);
  run->add_option("FILE", args.start.path,
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
      "--dump", args.run.dump,
      "Write frames of every particle at t = 0, DT, 2 DT, ... (--every DT) to this file "
      "as the run goes: .xyz (extended XYZ, for OVITO and ASE), .lammpstrj (LAMMPS "
      "text dump) or .gsd (HOOMD-blue's GSD, for HOOMD, OVITO and freud). A resumed run "
      "continues the same file");
  run->add_option("--every", args.run.dump_every, "Time between --dump frames")
      ->check(finite_number());
  run->add_option(
      "--events", args.run.events,
      "Write every collision to this csv file as the run goes: "
      "time,kind,first,partner (kind wall or pair; partner a particle or a wall label)");
  run->add_option("--log", args.run.log,
                  "Write a time series to this csv file as the run goes, a row every --log-every "
                  "DT: the temperature, and the pressure, Z and collision rate over each "
                  "interval, with running means and block-average errors over the measurement "
                  "window (like LAMMPS' thermo). A resumed run continues the same file");
  run->add_option("--log-every", args.run.log_every, "Time between --log rows")
      ->check(finite_number());
  run->add_option("--summary", args.run.summary,
                  "Also write the json settings, counts and observables (no particles) to this "
                  "file");
  run->add_option("--final", args.run.final_state,
                  "When the run reaches END_TIME, write its state to this file as a start that "
                  "carom run reads back to the last bit: FILE.gsd (GSD, with carom's "
                  "double-precision copy beside HOOMD's single-precision chunks) or any other "
                  "name for carom's start format. (-o's table has six decimals: the classic "
                  "assignment's)");
  run->add_flag("--transport", args.run.transport,
                "Measure the self-diffusion coefficient, shear viscosity and thermal "
                "conductivity over the measurement window (Einstein-Helfand at a lag of 50 "
                "collision times, errors from blocks; 3D also Yeh-Hummer's finite-size correction "
                "and Enskog's values) into "
                "the summary's \"transport\" (periodic box)");
  add_choice<Rule>(run, "--rule", args.start.rule,
                   "swap: touching disks exchange whole velocities (the classic assignment's "
                   "rule); elastic: they exchange momentum along the line of centres, with "
                   "masses (real hard disks). Default: what the file records (carom init and "
                   "compress record elastic), else swap with walls and elastic in a periodic box")
      ->default_str("from the file");
  run->add_option("--restitution", args.start.restitution,
                  "Coefficient of normal restitution E in (0, 1] for --rule elastic; E < 1 makes "
                  "collisions inelastic (granular gas)")
      ->check(finite_number())
      ->default_str("1");
  run->add_option("--tc", args.start.tc,
                  "TC model against inelastic collapse: a collision of a disk that collided less "
                  "than this long ago is elastic")
      ->check(finite_number())
      ->default_str(fmt::format("{}", kDefaultTc));
  add_choice<Boundary>(run, "--boundary", args.start.boundary,
                       "walls: hard walls on every side (the classic assignment's box); periodic: "
                       "the box repeats, no walls (sides must exceed two diameters). Default: what "
                       "the file records (carom init and compress record theirs), else walls")
      ->default_str("from the file");
  run->add_option("--equilibrate", args.run.measure_from,
                  "Measure observables only from this time on (the dynamics are unchanged); with "
                  "--resume, from this time on in the resumed run")
      ->check(finite_number())
      ->default_str("0");
  run->add_flag(
      "--check", args.run.check,
      "Verify during the run that event times never decrease and, every --check-every "
      "events, that no particles overlap or leave the box; a violation stops the run (exit 1)");
  add_whole_option(run, "--check-every", args.run.check_every, std::uint64_t{1},
                   "Events between overlap checks (default: N, at least 1000)");
  run->add_flag("-q,--quiet", args.quiet,
                "No progress line (shown on stderr during long runs when it is a terminal) and "
                "no notes");
  add_progress_option(run, args.progress);
  run->add_option("--kT", args.start.temperature,
                  "Give every particle a new velocity, Maxwell-Boltzmann at this temperature "
                  "(zero total momentum, kT exact), as carom init does: for a start without "
                  "velocities, or to rethermalise one")
      ->check(finite_number());
  add_whole_option(run, "--seed", args.start.seed, std::uint64_t{0},
                   "Random seed of --kT's velocities (and Andersen's draws), or of the event "
                   "chains' particles")
      ->default_str("1")
      ->each([&args](const std::string&) { args.seed_given = true; });
  add_choice<SamplerKind>(
      run, "--sampler", args.start.sampler,
      "md: event-driven molecular dynamics; ecmc: event-chain Monte Carlo (Bernard, Krauth and "
      "Wilson 2009), equilibrium positions at kT = 1 in a periodic box, faster at high density: "
      "a unit of time moves every particle one diameter on average, and lifts take the place of "
      "collisions");
  run->add_option("--chain-length", args.start.chain_length,
                  "The displacement of each event chain, in mean diameters (default, or 0: "
                  "0.24 of the box's side, Li et al. 2022)")
      ->check(finite_number());
  add_choice<ThermostatKind>(
      run, "--thermostat", args.thermostat,
      "Hold the run at --kT: rescale (every --thermostat-every, every velocity relative to the "
      "centre of mass scaled to kT exactly) or andersen (--thermostat-rate NU: each particle a "
      "new Maxwell-Boltzmann velocity at the events of a Poisson process of rate NU; with "
      "--thermostat-every DT, all at once at DT, 2 DT, ..., each with probability "
      "1 - exp(-NU DT))");
  run->add_option("--thermostat-every", args.thermostat_every,
                  "Time between the thermostat's actions (at DT, 2 DT, ...)")
      ->check(finite_number());
  run->add_option("--thermostat-rate", args.thermostat_rate,
                  "Andersen's collision rate: resets per particle per unit time")
      ->check(finite_number());
  run->add_option("--shear", args.shear,
                  "Shear the periodic box at this rate (Lees-Edwards): the images above and "
                  "below slide along x at +-RATE Ly, the fluid streams with u_x = RATE (y - Ly/2); "
                  "the summary gives the shear stress and viscosity, the temperature relative "
                  "to the profile")
      ->check(finite_number());
  run->add_flag("--velocity-profile", args.velocity_profile,
                "Add the streaming profile of --shear to the start's velocities, so that the "
                "run begins in its steady flow rather than with a shock");
  add_choice<EngineKind>(run, "--engine", args.start.engine,
                         "fast: neighbour lists (dense systems) or a cell grid, and an event "
                         "calendar, O(1) per event; reference: the classic assignment's "
                         "algorithm, every pair checked after every event (O(N^2), for "
                         "checking)");
  run->add_option("--checkpoint", args.run.checkpoint,
                  "Save the complete state of the run to this file at the end, every "
                  "--checkpoint-every, and on SIGINT, SIGTERM or SIGHUP (then stop)");
  run->add_option("--checkpoint-every", args.checkpoint_every,
                  "How often to save: a number of events (1000000) or of seconds (600s)");
  auto* resume = run->add_flag("--resume", args.resume,
                               "FILE is a checkpoint: continue that run to END_TIME, exactly as "
                               "if it had never stopped (its rule, boundary and engine apply)");
  for (const char* fixed_by_checkpoint :
       {"--rule", "--restitution", "--tc", "--boundary", "--engine", "--kT", "--thermostat",
        "--thermostat-every", "--thermostat-rate", "--shear", "--velocity-profile", "--sampler",
        "--chain-length", "--seed"}) {
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
  const RunSpec spec = run_spec(args, end_time);
  check_run_spec(spec);
  Runner runner(args.resume ? resume_start(args.start.path) : load_start(start_spec(args)));
  const AnySimulation& simulation = runner.simulation();
  try {
    runner.check(spec, {{"-o", args.output}});
  } catch (const RunLengthError& e) {
    throw UsageError(fmt::format("END_TIME {}", e.what()));
  }
  if (!args.quiet) print_notes(runner.start(), simulation);

  Output main(args.output);
  RunHooks hooks;
  hooks.stop = &stop_signal();
  if (args.trace) hooks.trace = &main.stream();
  std::optional<RunStatusLine> status;
  if (RunStatusLine::wanted(args.quiet, args.progress)) {
    status.emplace(args.quiet, args.progress);
    hooks.progress = [&](const AnySimulation& s, const RunProgress& p) { status->show(s, p); };
  }
  RunOutcome outcome;
  try {
    outcome = runner.run(spec, hooks);
  } catch (const SavedRunError& e) {
    throw std::runtime_error(fmt::format("{}: continue it with 'carom run --resume {} END_TIME'",
                                         e.what(), e.checkpoint()));
  }
  status.reset();
  if (outcome.status == RunStatus::stopped) {
    throw Interrupted(stop_signal().load(), describe_signal(stop_signal().load()) + ": " +
                                                interruption(simulation, spec));
  }
  const RunReport& report = outcome.report;
  if (report.drift && !args.quiet) {
    if (const auto drift = report.drift->drift_warning()) {
      std::cerr << "carom: warning: " << *drift << '\n';
    }
    // Only a run that reports Z's error hears of its blocks (the classic table of a few disks
    // between walls, whose Z nobody reads, would be told of it at every run).
    const bool reports_z =
        args.format == Format::json || !spec.summary.empty() || !spec.log.empty();
    const auto blocks = report.drift->correlation_warning();
    if (reports_z && blocks) std::cerr << "carom: warning: " << *blocks << '\n';
  }
  if (!args.trace) write_result(main.stream(), simulation, args.format, report);
  main.commit();
}

}  // namespace carom::cli
