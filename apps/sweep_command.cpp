#include "sweep_command.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <thread>

#include "carom/sweep/sweep.hpp"
#include "cli_support.hpp"
#include "progress.hpp"
#ifdef CAROM_HAVE_MPI
#include "carom/sweep/mpi_sweep.hpp"
#endif

namespace carom::cli {

namespace {

constexpr const char* kPlanHelp = R"(A plan is a TOML file:
  [start]     carom init's options (n, phi, dim, boundary, seed, ...), or file = "START"
  [run]       carom run's options: end_time, equilibrate, rule, log_every, dump, every, ...
  or [compress]  carom compress's: phi or jam = true, rate, ...
  or both     each run from its start compressed (init, compress, run: a fluid start)
  [sweep]     axes: lists of values of any of those keys; every combination is a task
Option names lose their dashes and write '-' as '_' (--log-every is log_every). A swept key that
is an option of carom init goes to the start, else to the run; after carom init, kT is the
compression's; with [compress] and [run], a swept phi (and rate, jam_pressure, unit_diameter) is
the compression's, and a run starts only from a compression that reached it (compression.json
says so). A swept boundary or kT that a later command sets again is refused. A task's seed also
seeds carom run's draws (kT, Andersen's) when [run] has no seed of its own; a plan whose swept
seed would leave its replicas one run is refused. Each task runs in DIR/<task>/ (its
name is its swept values: phi=0.3,seed=1), exactly as the commands of --dry-run would alone, and
keeps there its start, summary.json, log.csv (a row every log_every, by default a 200th of the
measured time), its checkpoint (every checkpoint_every, by default "600s") and any dump.
DIR/results.csv has a row a task (the swept keys, status, Z, Z_error, pressure, ...);
DIR/summary.csv a row a state point (every axis but seed: means and standard errors over the
seeds); DIR/report.html plots them, with the equation of state of hard disks or spheres beside Z.

Running the same command again skips the tasks that are done and continues the others from their
checkpoints: a sweep killed by a batch system's time limit is continued by resubmitting it.
SIGINT or SIGTERM saves every running task and stops. Under mpirun (or srun), rank 0 hands the
tasks out one at a time to the other ranks: mpirun -n 17 carom sweep runs 16 tasks at a time.
A second sweep in a folder one is running in is refused (DIR/sweep.lock), as are outputs that
would overwrite an input or another of the sweep's files (--html PLAN, say).
Exit status: 0 every task done; 100 + K when K tasks failed (their errors are in results.csv);
2 a bad plan or option, a refused output or a busy folder (nothing ran); 128 + N stopped by
signal N.

Example (eos.toml):
  [start]
  n = 256
  dim = 2
  boundary = "periodic"

  [run]
  end_time = 40
  equilibrate = 10
  rule = "elastic"

  [sweep]
  phi = [0.3, 0.5]
  seed = [1, 2]

  carom sweep eos.toml --dry-run
  carom sweep eos.toml -o eos
  mpirun -n 5 carom sweep eos.toml -o eos)";

// Whether an MPI launcher (mpirun, mpiexec, srun) started this process: its environment says.
bool launched_by_mpi_launcher() {
  for (const char* variable :
       {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"}) {
    if (std::getenv(variable) != nullptr) return true;
  }
  return false;
}

std::string output_folder(const SweepArguments& args) {
  if (!args.output.empty()) return args.output;
  return std::filesystem::path(args.plan).stem().string();
}

void print_dry_run(const SweepPlan& plan, const std::string& folder) {
  std::string shape;
  for (const std::string& axis : plan.axes()) shape += (shape.empty() ? "" : " x ") + axis;
  std::cout << fmt::format("{}: {} task{}{}\n", plan.name(), plan.tasks().size(),
                           plan.tasks().size() == 1 ? "" : "s",
                           shape.empty() ? "" : " (" + shape + ")");
  for (std::size_t i = 0; i < plan.tasks().size(); ++i) {
    const std::string task_folder = (std::filesystem::path(folder) / plan.tasks()[i].name).string();
    std::cout << plan.tasks()[i].name << '\n';
    for (const std::string& command : task_commands(plan, i, task_folder)) {
      std::cout << "  " << command << '\n';
    }
  }
}

std::string status_text(const SweepProgress& p) {
  const double left = p.fraction > 0.0 ? p.wall_seconds * (1.0 - p.fraction) / p.fraction : 0.0;
  return fmt::format("sweep: {} of {} done, {} running, {} failed ({:4.1f}%)  {} left", p.done,
                     p.total, p.running, p.failed, 100.0 * p.fraction,
                     p.fraction > 0.0 ? clock_time(left) : std::string("?"));
}

int finish(const SweepArguments& args, const SweepPlan& plan, const std::string& folder,
           const std::vector<TaskResult>& results, double seconds) {
  std::size_t done = 0, failed = 0, drifting = 0, correlated = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (results[i].status == TaskStatus::done) {
      ++done;
      const bool drift = drifted(results[i]);
      drifting += drift ? 1 : 0;
      correlated += !drift && blocks_correlated(results[i]) ? 1 : 0;
      const auto unsettled = unsettled_warning(results[i]);
      if (unsettled && !args.quiet) {
        std::cerr << fmt::format("carom: warning: task {}: {}\n", plan.tasks()[i].name,
                                 *unsettled);
      }
    }
    if (results[i].status == TaskStatus::failed) {
      ++failed;
      std::cerr << fmt::format("carom: task {} failed: {}\n", plan.tasks()[i].name,
                               results[i].error);
    }
  }
  if (const int signal = stop_signal().load(); signal != 0) {
    throw Interrupted(signal, fmt::format("{}: {} of {} tasks done, the running ones saved in "
                                          "their checkpoints; run the same command again to "
                                          "go on",
                                          describe_signal(signal), done, results.size()));
  }
  if (!args.quiet) {
    std::cerr << fmt::format(
        "carom: {} of {} tasks done{}{}{} in {}: {}/results.csv, summary.csv; {}\n", done,
        results.size(), failed > 0 ? fmt::format(", {} failed", failed) : "",
        drifting > 0 ? fmt::format(", {} with Z drifting (column {})", drifting, kDriftMeasure)
                     : "",
        correlated > 0
            ? fmt::format(", {} with Z's blocks correlated (column {})", correlated,
                          kCorrelationMeasure)
            : "",
        clock_time(seconds), folder, "report " + sweep_report_page(folder, args.html));
  }
  constexpr std::size_t kMostCounted = 27;  // 100 + 27 = 127, below the signals' 128 + N
  return failed == 0 ? 0 : 100 + static_cast<int>(std::min(failed, kMostCounted));
}

}  // namespace

CLI::App* add_sweep_command(CLI::App& app, SweepArguments& args) {
  CLI::App* sweep = app.add_subcommand(
      "sweep",
      "Run every task of a PLAN (state points x seeds: an equation of state, a set of jammed "
      "packings) on this machine's cores or on MPI ranks, resumably, into one folder of results.");
  sweep->footer(kPlanHelp);
  sweep->add_option("PLAN", args.plan, "The plan (TOML), see below")->required();
  sweep->add_option("-o,--output", args.output,
                    "The folder of the tasks and the results (default: PLAN's name without .toml)");
  sweep->add_flag("--dry-run", args.dry_run,
                  "List the tasks and the carom commands each is, and run nothing");
  add_whole_option(sweep, "-j,--jobs", args.jobs, 1u,
                   "Tasks at a time on this machine (default: every core); under MPI, one a rank")
      ->default_str("cores");
  sweep->add_option("--html", args.html, "Write the report to this page (default DIR/report.html)");
  sweep->add_flag("-q,--quiet", args.quiet, "No progress line and no closing line");
  add_progress_option(sweep, args.progress);
  return sweep;
}

std::string sweep_version_note() {
#ifdef CAROM_HAVE_MPI
  return "sweep: MPI (" + mpi_library_version() + ")";
#else
  return "sweep: this machine only (built without MPI)";
#endif
}

int sweep_command(const SweepArguments& args) {
  check_progress(args.progress);
  const SweepPlan plan = SweepPlan::read(args.plan);
  const std::string folder = output_folder(args);
  if (args.dry_run) {
    print_dry_run(plan, folder);
    return 0;
  }
  const unsigned jobs =
      args.jobs > 0 ? args.jobs : std::max(1u, std::thread::hardware_concurrency());
  StatusLine line(args.quiet, args.progress);
  SweepHooks hooks;
  hooks.stop = &stop_signal();
  hooks.progress = [&](const SweepProgress& p) {
    if (line.due()) line.print(status_text(p));
  };
  if (launched_by_mpi_launcher()) {
#ifdef CAROM_HAVE_MPI
    const MpiSweepOutcome outcome = run_sweep_mpi(plan, folder, jobs, hooks, args.html);
    if (outcome.rank != 0) return 0;
    return finish(args, plan, folder, outcome.results, line.elapsed());
#else
    throw UsageError(
        "this carom was built without MPI, so under mpirun every rank would run every task: "
        "run carom sweep without mpirun (it uses this machine's cores), or build carom where "
        "MPI is installed (Debian: libopenmpi-dev openmpi-bin)");
#endif
  }
  const std::vector<TaskResult> results = run_sweep(plan, folder, jobs, hooks, args.html);
  return finish(args, plan, folder, results, line.elapsed());
}

}  // namespace carom::cli
