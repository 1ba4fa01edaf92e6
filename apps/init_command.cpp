#include "init_command.hpp"

#include <numeric>

#include "carom/formats.hpp"
#include "carom/observables.hpp"
#include "cli_support.hpp"

namespace carom::cli {

CLI::App* add_init_command(CLI::App& app, InitArguments& args) {
  CLI::App* init = app.add_subcommand(
      "init",
      "Write a start file in the classic format: N non-overlapping disks at packing "
      "fraction PHI with Maxwell-Boltzmann velocities.");
  init->footer(
      R"(The box is square (or --aspect Lx/Ly) and sized so that the disks cover PHI of it; with
--box the box is fixed and the radius follows instead. Placement is random sequential up to
PHI = 0.4 and a triangular lattice above (which reaches close packing, 0.9069). Velocities are
Maxwell-Boltzmann at kT with zero total momentum, scaled so that sum m v^2 / 2N = kT exactly.
The same options and seed give the same file, bit for bit.

Examples:
  carom init --n 4096 --phi 0.5 -o gas.txt
  carom init --n 1000 --phi 0.3 --polydispersity 0.1 --boundary periodic --seed 7 -o poly.txt
  carom init --n 100 --phi 0.2 --box 40 20 -o sparse.txt)");
  InitialOptions& o = args.options;
  init->add_option("--n", o.n, "Number of disks")->required();
  init->add_option("--phi", o.packing_fraction, "Packing fraction: disk area / box area")
      ->required();
  auto* box = init->add_option_function<std::vector<double>>(
                      "--box",
                      [&o](const std::vector<double>& size) {
                        o.box = Vec<2>{{size[0], size[1]}};
                      },
                      "The box size Lx Ly (the radius follows)")
                  ->expected(2);
  init->add_option("--aspect", o.aspect, "Lx / Ly of a derived box")
      ->default_str("1")
      ->excludes(box);
  init->add_option_function<double>(
          "--radius", [&o](double radius) { o.radius = radius; },
          "Mean disk radius (default 0.5: diameter 1)")
      ->excludes(box);
  init->add_option("--polydispersity", o.polydispersity,
                   "Standard deviation of the radius over its mean (uniform distribution, <= 0.5)")
      ->default_str("0");
  init->add_option("--kT", o.temperature, "Temperature (masses are 1)")->default_str("1");
  init->add_option("--seed", o.seed, "Random seed")->default_str("1");
  add_choice<Boundary>(init, "--boundary", o.boundary,
                       "The box the file is meant for: with walls, disks keep R from them");
  auto* lattice = init->add_flag("--lattice", args.lattice, "Place on a triangular lattice");
  init->add_flag("--random", args.random, "Place at random (random sequential addition)")
      ->excludes(lattice);
  init->add_option("-o,--output", args.output, "Write to this file instead of stdout");
  return init;
}

void init_command(InitArguments args) {
  InitialOptions& o = args.options;
  if (args.lattice) o.placement = Placement::lattice;
  if (args.random) o.placement = Placement::random;
  Output out(args.output);
  System<2> system;
  try {
    system = make_initial(o);
  } catch (const InitialError& e) {
    throw UsageError(e.what());
  }
  // The file's R is the mean radius; disks that differ carry their own.
  double sum = 0.0;
  for (const Particle<2>& p : system.particles) sum += p.radius;
  const double mean = o.polydispersity == 0.0 ? system.particles.front().radius
                                              : sum / static_cast<double>(system.size());
  write_classic(out.stream(), system, mean);
  out.commit();
}

}  // namespace carom::cli
