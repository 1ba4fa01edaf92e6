#include "init_command.hpp"

#include <fmt/format.h>

#include <numeric>

#include "carom/core/observables.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/run_report.hpp"
#include "cli_support.hpp"

namespace carom::cli {

CLI::App* add_init_command(CLI::App& app, InitArguments& args) {
  CLI::App* init = app.add_subcommand(
      "init",
      "Write a start file in the classic format: N non-overlapping disks (or spheres, --dim 3) at "
      "packing fraction PHI with Maxwell-Boltzmann velocities.");
  init->footer(
      R"(The box is square or cubic (or --aspect Lx/Ly) and sized so that the particles fill PHI of
it; with --box the box is fixed and the radius follows instead. Placement is random sequential up
to PHI = 0.4 for disks (0.25 for spheres) and a lattice above: triangular for disks (up to close
packing, 0.9069), face-centred cubic for spheres (up to 0.7405 when N = 4 n^3 in a cube, which
fills whole cells; other N leave vacancies spread evenly). Velocities are Maxwell-Boltzmann at kT
with zero total momentum, scaled so that the kinetic temperature is kT exactly (D N degrees of
freedom with walls, D (N - 1) in a periodic box). The same options and seed give the same file,
bit for bit. --species makes a mixture (types A, B, ... in the file; see docs/command-line.md):
the lattice is sized for the largest diameter, so a dense mixture is placed at random at a low
PHI and brought up with carom compress --phi.

Examples:
  carom init --n 4096 --phi 0.5 -o gas.txt
  carom init --n 1000 --phi 0.3 --polydispersity 0.1 --boundary periodic --seed 7 -o poly.txt
  carom init --n 100 --phi 0.2 --box 40 20 -o sparse.txt
  carom init --n 1000 --phi 0.3 --species A:0.5:1.0,B:0.5:1.4 --seed 3 -o binary.txt
  carom init --dim 3 --n 4000 --phi 0.45 --boundary periodic -o spheres.txt)");
  InitialOptions& o = args.spec.options;
  add_whole_option(init, "--dim", args.spec.dimension, 2, "2: disks; 3: spheres", std::optional(3))
      ->default_str(std::to_string(args.spec.dimension));
  add_whole_option(init, "--n", o.n, std::uint64_t{1}, "Number of particles")->required();
  init->add_option("--phi", o.packing_fraction,
                   "Packing fraction: particle area (volume) / box area (volume)")
      ->check(finite_number())
      ->required();
  auto* box = init->add_option("--box", o.box, "The box's sides Lx Ly [Lz] (the radius follows)")
                  ->check(finite_number())
                  ->expected(2, 3);
  init->add_option("--aspect", o.aspect, "Lx / Ly of a derived box (in 3D Lz = Ly)")
      ->check(finite_number())
      ->default_str("1")
      ->excludes(box);
  init->add_option_function<double>(
          "--radius", [&o](double radius) { o.radius = radius; },
          "Mean radius (default 0.5: diameter 1)")
      ->check(finite_number())
      ->excludes(box);
  auto* polydispersity =
      init->add_option("--polydispersity", o.polydispersity,
                       "Standard deviation of the radius over its mean (uniform distribution, "
                       "<= 0.5)")
          ->check(finite_number())
          ->default_str("0");
  init->add_option(
          "--species", args.species,
          "A mixture: NAME:FRACTION:DIAMETER,... (as A:0.5:1.0,B:0.5:1.4): number fractions "
          "summing to 1, counts by largest remainder, types shuffled by the seed")
      ->excludes(polydispersity)
      ->excludes(init->get_option("--radius"));
  init->add_option("--kT", o.temperature, "Temperature (masses are 1)")
      ->check(finite_number())
      ->default_str("1");
  add_whole_option(init, "--seed", o.seed, std::uint64_t{0}, "Random seed")->default_str("1");
  add_choice<Boundary>(init, "--boundary", o.boundary,
                       "The box the file is meant for: periodic (the bulk), or walls, from which "
                       "particles keep R");
  auto* lattice =
      init->add_flag("--lattice", args.lattice, "Place on a lattice (triangular; FCC in 3D)");
  init->add_flag("--random", args.random, "Place at random (random sequential addition)")
      ->excludes(lattice);
  init->add_option("-o,--output", args.output, "Write to this file instead of stdout");
  return init;
}

namespace {

// Makes the start, then writes it: the output file is created only once there is something to
// put in it, so a stop during the work (init installs no signal handler) leaves nothing behind.
template <std::size_t D>
void write_initial(const InitSpec& spec, const std::string& path) {
  System<D> system;
  try {
    system = make_initial<D>(spec.options);
  } catch (const InitialError& e) {
    throw UsageError(e.what());
  }
  Output out(path);
  write_start(out.stream(), system, spec.rule);
  out.commit();
}

}  // namespace

void init_command(InitArguments args) {
  InitialOptions& o = args.spec.options;
  if (args.lattice) o.placement = Placement::lattice;
  if (args.random) o.placement = Placement::random;
  if (!args.species.empty()) {
    try {
      o.species = parse_species(args.species);
    } catch (const InitialError& e) {
      throw UsageError(e.what());
    }
  }
  if (!args.output.empty() && args.output != "-") check_writable(args.output);
  if (args.spec.dimension == 3) {
    write_initial<3>(args.spec, args.output);
  } else {
    write_initial<2>(args.spec, args.output);
  }
}

}  // namespace carom::cli
