#include "compress_command.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <variant>

#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/compress_run.hpp"
#include "carom/run/run_report.hpp"
#include "carom/run/start.hpp"
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
                   fmt::format("The compressibility factor Z at which --jam stops (at most {:g}: "
                               "beyond it doubles do not resolve the gaps); particles that can "
                               "grow no more stop it too",
                               kMostJammedPressure))
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

void compress_command(CompressArguments args) {
  for (const std::string* path : {&args.output, &args.summary}) {
    if (!path->empty() && *path != "-") check_writable(*path);
  }
  check_files_apart({{"the input FILE", start_file_path(args.input)}},
                    {{"-o", args.output}, {"--summary", args.summary}});
  if (!args.jam && !(args.target > 0.0)) throw UsageError("give --phi TARGET or --jam");
  check_progress(args.progress);
  CompressionSpec spec{args.settings, args.unit_diameter, args.input};
  spec.settings.target = args.jam ? std::nullopt : std::optional<double>(args.target);
  AnySystem start = read_start_system(args.input, args.boundary);
  Output out(args.output);
  std::optional<Output> summary;
  if (!args.summary.empty()) summary.emplace(args.summary);
  CompressionResult result;
  {
    StatusLine progress(args.quiet, args.progress);
    CompressionHooks hooks;
    hooks.stop = &stop_signal();
    hooks.progress = [&](const CompressionProgress& c) {
      if (!progress.due()) return;
      progress.print(fmt::format(
          "packing fraction {:.6f}  Z = {:<10.4g}  t = {:<9.4g}  {:.3g} events", c.packing_fraction,
          c.compressibility_factor, c.time, static_cast<double>(c.events)));
    };
    result = compress(std::move(start), spec, hooks);
  }
  const CompressionSummary& s = result.summary;
  // The packing so far is a valid start, whatever stopped the compression: it is kept.
  write_start(out.stream(), result.packing, Rule::elastic);
  if (summary) write_json(summary->stream(), s);
  const int signal = stop_signal().load();
  // A stop signal keeps what was computed: commit both files before saying so.
  out.keep();
  if (summary) summary->keep();
  const std::string where = args.output.empty() ? "the output" : args.output;
  if (signal != 0) {
    throw Interrupted(signal,
                      fmt::format("{}: the packing so far (packing fraction {:.6f}) is in {}",
                                  describe_signal(signal), s.packing_fraction, where));
  }
  const std::string_view particles = s.dimension == 2 ? "disks" : "spheres";
  // The number a jamming study wants, said where it is seen (a compression short of its target
  // says so below, as an error).
  if (s.status == "jammed" && !s.target && !args.quiet) {
    std::cerr << fmt::format("carom: the {} jammed at packing fraction {:.6f} (Z = {:.3g})\n",
                             particles, s.packing_fraction, s.compressibility_factor);
  }
  if (!args.unit_diameter && !args.quiet) {
    std::cerr << fmt::format(
        "carom: note: the {} grew to a mean diameter of {:.6g}, the packing's unit of length "
        "(--unit-diameter rescales it to 1, the box with it)\n",
        particles, s.grown_diameter);
  }
  if (const std::optional<std::string> why = shortfall(s, where)) throw std::runtime_error(*why);
}

}  // namespace carom::cli
