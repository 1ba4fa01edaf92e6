#include "analyze_command.hpp"

#include <fmt/format.h>

#include <iostream>

#include "carom/analysis/analysis_spec.hpp"
#include "cli_support.hpp"

namespace carom::cli {

CLI::App* add_analyze_command(CLI::App& app, AnalyzeArguments& args) {
  CLI::App* analyze = app.add_subcommand(
      "analyze",
      "Analyse a trajectory (.gsd or .xyz from carom run --dump): g(r) and Z from its contact "
      "value, the mean-square displacement, the hexatic order psi6 (disks), the Steinhardt bond "
      "order and solid-like clusters (spheres), the structure factor S(k), the self-intermediate "
      "scattering function F_s(k,t); as JSON and as a report page.");
  analyze->footer(
      R"(What it computes, each under its name in the JSON and in --only (2D and 3D; psi6 for disks
only, the bond order for spheres only):
  rdf    g(r) over every frame, minimum image in a periodic box, bins of d/50 up to 5 d (d the
         mean diameter), so contact is a bin edge; for a monodisperse periodic fluid, g(d+) from a
         least-squares quadratic over the bins within d/10 of contact and Z = 1 + 2 eta g(d+)
         (disks) or 1 + 4 eta g(d+) (spheres)
  msd    mean-square displacement of the unwrapped positions (image flags), averaged over every
         particle and time origin; frames must be evenly spaced in time
  psi6   |<psi6>| per frame and the mean local |psi6_j|, psi6_j = (1/6) sum of exp(6 i theta_jk)
         over the 6 nearest neighbours k of disk j, and the orientation arg<psi6> / 6 in degrees
         in (-30, 30] (the bonds' angle to x, modulo 60; noise where |<psi6>| is near 0)
  steinhardt
         per frame, the means over the spheres of q4, q6, w4, w6 (Steinhardt) and of their
         Lechner-Dellago averages over each sphere and its neighbours, the neighbours of a sphere
         being every other one closer than 1.5 d (--order-cutoff), minimum image; the solid-like
         spheres (7 or more bonds whose normalised q6 product exceeds 0.7, ten Wolde et al.) and
         their clusters over neighbour bonds: their count and the largest cluster's size
  structure_factor
         S(k) = |sum_j exp(-i k.r_j)|^2 / N on the periodic box's k-grid, k = 2 pi (n_x/L_x,
         n_y/L_y, ...), over the frames and over shells of |k| of width 2 pi / L_min, up to
         k = 20 / d; at most 100 k-vectors a shell (an even, fixed choice), one of each k, -k
  self_scattering
         F_s(k,t) = <cos(k.(r_j(t0+t) - r_j(t0)))> over particles, time origins and the
         k-vectors of S(k)'s main peak shell, at the MSD's lags; alpha2(t) = d <dr^4> /
         ((d+2) <dr^2>^2) - 1; tau_alpha where F_s first falls below 1/e
An analysis that does not apply is left out with the reason on standard error. A summary goes to
standard output, the whole result to -o FILE.json, the report page to --html FILE.html.

Example (a fluid of disks at packing 0.5, its Z near 4.1):
  carom init --n 1000 --phi 0.5 --boundary periodic --seed 1 -o gas.txt
  carom run gas.txt 40 --rule elastic --boundary periodic --dump run.gsd --every 0.5 \
      --log run.csv --log-every 0.5 -o end.txt
  carom analyze run.gsd --equilibrate 10 --log run.csv -o analysis.json --html report.html)");
  analyze->add_option("TRAJECTORY", args.trajectory, "A .gsd or extended .xyz trajectory")
      ->required()
      ->type_name("FILE");
  analyze->add_option("-o,--output", args.output, "Write the analysis as JSON here ('-': stdout)")
      ->type_name("FILE");
  analyze
      ->add_option("--html", args.html,
                   "Write the report page here: plots and a snapshot coloured by local psi6")
      ->type_name("FILE");
  analyze->add_option("--log", args.log, "A time-series log of the run (carom run --log) to plot")
      ->type_name("FILE");
  analyze
      ->add_option("--equilibrate", args.from_time,
                   "Analyse only the frames from this time on (as carom run --equilibrate)")
      ->type_name("T");
  analyze->add_option("--bin", args.bin_width, "The width of g(r)'s bins (default: d / 50)")
      ->type_name("WIDTH");
  analyze
      ->add_option("--r-max", args.r_max,
                   "How far g(r) reaches (default: 5 d, at most half the box)")
      ->type_name("R");
  analyze
      ->add_option("--contact-width", args.contact_width,
                   "The range above contact g(d+) is fitted on (default: d / 10)")
      ->type_name("WIDTH");
  analyze->add_option("--k-max", args.k_max, "How far S(k) reaches (default: 20 / d)")
      ->type_name("K");
  analyze
      ->add_option("--fs-k", args.fs_k,
                   "The wave number of F_s(k,t) and tau_alpha (default: S(k)'s main peak)")
      ->type_name("K");
  analyze->add_flag("--com", args.from_centre_of_mass,
                    "Take the MSD's and F_s(k,t)'s displacements from the centre of mass (event "
                    "chains move it; dynamics does not)");
  analyze
      ->add_option("--order-cutoff", args.order_cutoff,
                   "The neighbour distance of the Steinhardt bond order (default: 1.5 d)")
      ->type_name("R");
  analyze
      ->add_option_function<std::string>(
          "--only", [&args](const std::string& list) { args.only = list; },
          "Compute only these analyses, by their JSON names: rdf, msd, psi6, steinhardt, "
          "structure_factor, self_scattering, separated by commas (default: every one; S(k) and "
          "F_s(k,t) take seconds a frame at 65536 disks)")
      ->type_name("LIST");
  return analyze;
}

namespace {

// What a terminal user reads first.
void print_summary(std::ostream& out, const Analysis& a) {
  const TrajectoryShape& s = a.shape;
  std::string box;
  for (const double side : s.box) box += (box.empty() ? "" : " x ") + fmt::format("{:g}", side);
  out << fmt::format("{}: {} {}, {} box {}, packing fraction {:.4f}\n", a.trajectory, s.particles,
                     s.dimension == 2 ? "disks" : "spheres", s.periodic ? "periodic" : "walled",
                     box, s.packing_fraction);
  out << fmt::format("frames: {} of {}, t = {:g} to {:g}\n", a.time.size(), a.frames_in_file,
                     a.time.front(), a.time.back());
  if (a.rdf) {
    out << fmt::format("g(r): bins of {:g} to r = {:g}", a.rdf->bin_width, a.rdf->r_max);
    if (a.contact)
      out << fmt::format("; contact g(d+) = {:.4f}, Z = {:.4f}", a.contact->g, a.contact->z);
    out << '\n';
  }
  if (a.msd && a.msd->t.size() > 1) {
    out << fmt::format("MSD: {} lags, {:.6g} at t = {:g}\n", a.msd->t.size(), a.msd->msd.back(),
                       a.msd->t.back());
  }
  if (a.psi6) {
    double global = 0.0, local = 0.0;
    for (std::size_t f = 0; f < a.psi6->t.size(); ++f) {
      global += a.psi6->global[f];
      local += a.psi6->local_mean[f];
    }
    const auto frames = static_cast<double>(a.psi6->t.size());
    out << fmt::format(
        "psi6: global {:.4f}, mean local {:.4f} (averaged over frames); orientation {:.2f} "
        "degrees (the last frame)\n",
        global / frames, local / frames, a.psi6->orientation.back());
  }
  if (a.structure_factor) {
    const StructureFactor& sk = *a.structure_factor;
    out << fmt::format("S(k): {} shells to k = {:.4g}, main peak at k = {:.4g}\n", sk.k.size(),
                       sk.k.back(), sk.k_peak);
  }
  if (a.self_scattering) {
    const SelfScattering& fs = *a.self_scattering;
    out << fmt::format("F_s(k = {:.4g}, t): {:.4f} at t = {:g}", fs.k, fs.fs.back(), fs.t.back());
    if (fs.tau_alpha) out << fmt::format("; tau_alpha = {:.4g}", *fs.tau_alpha);
    out << '\n';
  }
  if (a.steinhardt && !a.steinhardt->t.empty()) {
    const BondOrderSeries& order = *a.steinhardt;
    out << fmt::format(
        "bond order (last frame, neighbours within {:g}): q4 {:.4f}, q6 {:.4f}, w6 {:.5f}; "
        "{} solid-like, largest cluster {}\n",
        order.cutoff, order.degree(4).q.back(), order.degree(6).q.back(), order.degree(6).w.back(),
        order.solid_like.back(), order.largest_cluster.back());
  }
}

double option_number(const std::string& text, const char* what, double otherwise) {
  if (text.empty()) return otherwise;
  const double value = parse_number(text, what);
  if (!(value > 0.0) && std::string_view(what) != "--equilibrate") {
    throw UsageError(fmt::format("{} must be greater than 0, not {}", what, text));
  }
  return value;
}

}  // namespace

void analyze_command(const AnalyzeArguments& args) {
  // Where results go is checked before the work.
  for (const std::string* path : {&args.output, &args.html}) {
    if (!path->empty() && *path != "-") check_writable(*path);
  }
  if (args.output == "-" && args.html == "-") {
    throw UsageError("-o and --html cannot both write to standard output");
  }
  AnalysisSpec spec;
  spec.trajectory.path = args.trajectory;
  spec.log.path = args.log;
  // "-" is standard output, written here once the library has written the files.
  spec.json.path = args.output == "-" ? "" : args.output;
  spec.html.path = args.html == "-" ? "" : args.html;
  AnalysisOptions& options = spec.options;
  options.from_time = option_number(args.from_time, "--equilibrate", options.from_time);
  options.rdf.bin_width = option_number(args.bin_width, "--bin", 0.0);
  options.rdf.r_max = option_number(args.r_max, "--r-max", 0.0);
  options.contact_width = option_number(args.contact_width, "--contact-width", 0.0);
  options.k_max = option_number(args.k_max, "--k-max", 0.0);
  options.fs_k = option_number(args.fs_k, "--fs-k", 0.0);
  options.bond_order.cutoff = option_number(args.order_cutoff, "--order-cutoff", 0.0);
  options.from_centre_of_mass = args.from_centre_of_mass;
  if (args.only) {
    try {
      options.only = parse_analysis_selection(*args.only);
    } catch (const std::invalid_argument& e) {
      throw UsageError(fmt::format("--only: {}", e.what()));
    }
  }
  Analysis analysis;
  try {
    analysis = analyze(spec);
  } catch (const AnalysisError& e) {
    throw UsageError(fmt::format("cannot analyse {}: {}", args.trajectory, e.what()));
  }
  for (const std::string& warning : analysis.warnings)
    std::cerr << "carom: note: " << warning << '\n';
  if (args.output == "-") {
    Output out(args.output);
    write_analysis_json(out.stream(), analysis);
    out.commit();
  } else if (args.html == "-") {
    Output out(args.html);
    write_report_html(out.stream(), analysis);
    out.commit();
  } else {
    print_summary(std::cout, analysis);  // kept out of a result written to standard output
  }
}

}  // namespace carom::cli
