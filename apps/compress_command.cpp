#include "compress_command.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <variant>

#include "carom/formats.hpp"
#include "carom/gsd.hpp"
#include "carom/initial.hpp"
#include "carom/version.hpp"
#include "cli_support.hpp"
#include "progress.hpp"

namespace carom::cli {

CLI::App* add_compress_command(CLI::App& app, CompressArguments& args) {
  CLI::App* compress = app.add_subcommand(
      "compress",
      "Grow the disks or spheres of a start file to a packing fraction (--phi) or until they jam "
      "(--jam), as Lubachevsky and Stillinger: dense fluids, glasses, jammed packings.");
  compress->footer(fmt::format(
      R"(Every radius grows as r(t) = r(0) (1 + RATE t), size ratios kept, while the particles
move and collide (elastically in the frame of their growing surfaces); the velocities are
rescaled to kT every N collisions. --phi stops exactly at the target packing fraction; --jam
grows until the compressibility factor Z = PV/NkT passes {:g} and reports the jamming packing
fraction. The output is a classic start file (radii in a column when they differ) that
'carom run' takes as it is. Slower rates give denser packings: equal spheres crystallise when
compressed slowly, and jam near random close packing (0.64) at the default rate.

Examples:
  carom init --dim 3 --n 4000 --phi 0.3 --boundary periodic -o gas.txt
  carom compress gas.txt --jam --boundary periodic -o jammed.txt --summary jammed.json
  carom init --n 2000 --phi 0.3 --polydispersity 0.1 --boundary periodic -o poly.txt
  carom compress poly.txt --phi 0.78 --boundary periodic -o dense.txt)",
      kJammedPressure));
  compress->add_option("FILE", args.input, "A start file (classic format, or FILE.gsd[:K])")
      ->required();
  auto* phi = compress->add_option("--phi", args.target, "The packing fraction to stop at")
                  ->check(finite_number());
  auto* jam = compress->add_flag("--jam", args.jam, "Grow until the packing jams")->excludes(phi);
  phi->excludes(jam);
  compress
      ->add_option("--rate", args.settings.rate,
                   "How fast every diameter grows, per unit time, over its diameter at the "
                   "start (thermal speed 1)")
      ->check(finite_number())
      ->default_str(fmt::format("{:g}", kDefaultGrowthRate));
  add_choice<Boundary>(compress, "--boundary", args.boundary,
                       "The box of the start file (default: what the file records, else walls)")
      ->default_str("from the file");
  compress->add_option("--kT", args.settings.temperature, "The temperature velocities are kept at")
      ->check(finite_number())
      ->default_str("1");
  compress
      ->add_option("--jam-pressure", args.settings.jammed_pressure,
                   "The compressibility factor Z at which --jam stops")
      ->check(finite_number())
      ->default_str(fmt::format("{:g}", kJammedPressure));
  add_choice<EngineKind>(compress, "--engine", args.settings.engine,
                         "fast, or reference (O(N^2) an event: for checking)");
  compress->add_option("-o,--output", args.output,
                       "Write the packing to this file (default: stdout)");
  compress->add_option(
      "--summary", args.summary,
      "Also write the packing fraction, compressibility factor, rate and events (json)");
  compress->add_flag("--unit-diameter", args.unit_diameter,
                     "Rescale the packing to a mean diameter of 1 (the box shrinks with it; the "
                     "packing fraction and Z are unchanged); otherwise lengths keep the start's "
                     "unit and the diameters end larger");
  compress->add_flag("-q,--quiet", args.quiet, "No progress line on a terminal, and no notes");
  add_progress_option(compress, args.progress);
  return compress;
}

namespace {

std::string_view status_name(CompressionStatus status) {
  switch (status) {
    case CompressionStatus::reached_target:
      return "reached_target";
    case CompressionStatus::jammed:
      return "jammed";
    default:
      return "interrupted";
  }
}

template <std::size_t D>
void compress(const CompressArguments& args, System<D> start) {
  CompressionSettings settings = args.settings;
  if (!args.jam) settings.target = args.target;
  const auto began = std::chrono::steady_clock::now();
  std::optional<Compression<D>> compression;
  try {
    compression.emplace(std::move(start), settings);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("cannot compress {}: {}", args.input, e.what()));
  }
  Output out(args.output);
  std::optional<Output> summary;
  if (!args.summary.empty()) summary.emplace(args.summary);
  {
    StatusLine progress(args.quiet, args.progress);
    while (compression->status() == CompressionStatus::running && stop_signal().load() == 0) {
      compression->run(compression->system().size());
      if (progress.due()) {
        const Compression<D>& c = *compression;
        progress.print(
            fmt::format("packing fraction {:.6f}  Z = {:<10.4g}  t = {:<9.4g}  {:.3g} events",
                        c.packing_fraction(), c.compressibility_factor(), c.time(),
                        static_cast<double>(c.events())));
      }
    }
  }
  const Compression<D>& c = *compression;
  // The packing so far is a valid start, whatever stopped the compression: it is kept.
  System<D> system = c.system();
  const double grown_diameter = mean_diameter(system);
  if (args.unit_diameter) scale_lengths(system, 1.0 / grown_diameter);
  write_start(out.stream(), system, Rule::elastic);
  const int signal = stop_signal().load();
  if (summary) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    const nlohmann::json json = {
        {"carom_version", kVersion},
        {"input", args.input},
        {"dimension", D},
        {"n", system.size()},
        {"boundary", name_of(system.box.boundary)},
        {"status", status_name(c.status())},
        {"target", settings.target ? nlohmann::json(*settings.target) : nlohmann::json(nullptr)},
        {"packing_fraction", c.packing_fraction()},
        {"compressibility_factor", c.compressibility_factor()},
        {"rate", settings.rate},
        {"kT", settings.temperature},
        {"jam_pressure", settings.jammed_pressure},
        {"time", c.time()},
        {"events", c.events()},
        {"mean_diameter", mean_diameter(system)},
        {"unit_diameter", args.unit_diameter},
        {"box", system.box.size.c},
        {"wall_seconds", seconds}};
    summary->stream() << json.dump(2) << '\n';
  }
  // A stop signal keeps what was computed: commit both files before saying so.
  const auto commit = [&] {
    out.keep();
    if (summary) summary->keep();
  };
  commit();
  if (signal != 0) {
    throw Interrupted(signal,
                      fmt::format("{}: the packing so far (packing fraction {:.6f}) is in {}",
                                  describe_signal(signal), c.packing_fraction(),
                                  args.output.empty() ? "the output" : args.output));
  }
  if (!args.unit_diameter && !args.quiet) {
    std::cerr << fmt::format(
        "carom: note: the {} grew to a mean diameter of {:.6g}, the packing's unit of length "
        "(--unit-diameter rescales it to 1, the box with it)\n",
        kParticlesName<D>, grown_diameter);
  }
  if (settings.target && c.status() == CompressionStatus::jammed) {
    throw std::runtime_error(fmt::format(
        "the {} jammed at packing fraction {:.6f} (Z = {:.3g}) before reaching {}; the jammed "
        "packing is in {}",
        kParticlesName<D>, c.packing_fraction(), c.compressibility_factor(), *settings.target,
        args.output.empty() ? "the output" : args.output));
  }
}

}  // namespace

void compress_command(CompressArguments args) {
  for (const std::string* path : {&args.output, &args.summary}) {
    if (!path->empty() && *path != "-") check_writable(*path);
  }
  if (!args.jam && !(args.target > 0.0)) throw UsageError("give --phi TARGET or --jam");
  check_progress(args.progress);
  AnyClassicInput input = read_any_start_file(args.input, args.boundary);
  std::visit([&](auto& in) { compress(args, std::move(in.system)); }, input);
}

}  // namespace carom::cli
