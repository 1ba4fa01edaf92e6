// carom analyze's results: running every analysis that applies, and writing them as JSON or as
// the report page.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>

#include "carom/analysis/analysis.hpp"
#include "carom/report_html.hpp"
#include "carom/version.hpp"
#include "io/json_text.hpp"

namespace carom {

namespace {

// Whether g(r) counts pairs clearly closer than contact (bins wholly below 0.98 d): soft
// particles, or a diameter the file does not give.
bool overlapping(const Rdf& rdf, double diameter) {
  for (std::size_t b = 0; b < rdf.r.size(); ++b) {
    if (rdf.r[b] + 0.5 * rdf.bin_width <= 0.98 * diameter && rdf.g[b] > 0.0) return true;
  }
  return false;
}

// A trajectory whose centre of mass moved further than the particles' own scatter can move it
// (the square of its shift above 10 / N of the MSD over the whole trajectory, and above 1 %): its
// MSD and F_s(k,t) hold a flow, as event chains' do (they move it along +x and +y), unless the
// analysis takes displacements from the centre of mass.
void warn_of_flow(Analysis& analysis, const AnalysisOptions& options) {
  const Msd& msd = *analysis.msd;
  if (options.from_centre_of_mass || msd.msd.size() < 2) return;
  const double shift = msd.centre_of_mass_shift, whole = msd.msd.back();
  const double particles = static_cast<double>(analysis.shape.particles);
  if (!(shift * shift > std::max(0.01, 10.0 / particles) * whole)) return;
  analysis.warnings.push_back(fmt::format(
      "the centre of mass moved by {:.3g} from the first frame to the last, {:.0f} % of the "
      "particles' root mean square displacement: the MSD, self_diffusion, F_s(k,t) and tau_alpha "
      "hold that flow (event chains move it along +x and +y); --com takes displacements from the "
      "centre of mass",
      shift, 100.0 * shift / std::sqrt(whole)));
}

// g(r) over the frames and, where it says Z, its contact value.
void add_rdf(Analysis& analysis, const std::vector<Frame>& frames, const AnalysisOptions& options) {
  const TrajectoryShape& shape = analysis.shape;
  analysis.rdf = radial_distribution(frames, options.rdf);
  const double d = shape.mean_diameter;
  if (!shape.monodisperse) {
    analysis.warnings.emplace_back(
        "no contact value: the particles' diameters differ (g(r) mixes every pair of sizes)");
  } else if (overlapping(*analysis.rdf, shape.mean_diameter)) {
    analysis.warnings.emplace_back(
        "no contact value: pairs closer than a diameter (by more than 2 %) are counted, so these "
        "are not hard particles of that diameter");
  } else if (!shape.periodic) {
    analysis.warnings.emplace_back(
        "no Z from the contact value: between walls the fluid is not uniform, so Z = 1 + 2^(D-1) "
        "eta g(d+) does not hold");
  } else {
    analysis.contact = contact_value(*analysis.rdf, d, shape.dimension, shape.packing_fraction,
                                     options.contact_width > 0.0 ? options.contact_width : 0.1 * d);
    if (!analysis.contact) {
      analysis.warnings.emplace_back(
          "no contact value: fewer than three g(r) bins lie within the fitted range above contact "
          "(a smaller --bin or a larger --contact-width)");
    }
  }
}

// S(k) on a periodic box's k-grid, and F_s(k,t) and alpha2(t) at its main peak (or at
// options.fs_k). A k the options ask for and the box cannot have is an error; the defaults'
// S(k) too large to take is left out with a warning instead.
void add_scattering(Analysis& analysis, const std::vector<Frame>& frames,
                    const AnalysisOptions& options) {
  const TrajectoryShape& shape = analysis.shape;
  const bool sheared = std::any_of(frames.begin(), frames.end(),
                                   [](const Frame& frame) { return frame.shear_shift != 0.0; });
  if (options.only.structure_factor) {
    if (!shape.periodic) {
      analysis.warnings.emplace_back(
          "no S(k): it is taken on a periodic box's k-grid, and this box has walls");
    } else if (sheared) {
      analysis.warnings.emplace_back("no S(k): a sheared box's k-grid turns with the shear");
    } else {
      try {
        analysis.structure_factor = structure_factor(
            frames, options.k_max > 0.0 ? options.k_max : 20.0 / shape.mean_diameter);
      } catch (const std::invalid_argument& e) {
        if (options.k_max > 0.0) throw;
        analysis.warnings.push_back(std::string("no S(k): ") + e.what());
      }
    }
  }
  if (!options.only.self_scattering) return;
  const double k = options.fs_k > 0.0          ? options.fs_k
                   : analysis.structure_factor ? analysis.structure_factor->k_peak
                                               : 0.0;
  if (!analysis.msd) {
    analysis.warnings.emplace_back(
        "no F_s(k,t): like the MSD, it needs image flags and frames evenly spaced in time");
  } else if (!(k > 0.0)) {
    analysis.warnings.emplace_back(
        "no F_s(k,t): no S(k) to take k from its main peak (--fs-k gives k)");
  } else {
    analysis.self_scattering = self_scattering(frames, k, options.from_centre_of_mass);
    if (!analysis.self_scattering->tau_alpha) {
      analysis.warnings.push_back(
          fmt::format("no tau_alpha: F_s(k,t) stays above 1/e up to t = {:g}",
                      analysis.self_scattering->t.back()));
    }
  }
}

// Each analysis's name and its flag in a selection.
constexpr std::array<std::pair<std::string_view, bool AnalysisSelection::*>, 6> kAnalyses{{
    {"rdf", &AnalysisSelection::rdf},
    {"msd", &AnalysisSelection::msd},
    {"psi6", &AnalysisSelection::psi6},
    {"steinhardt", &AnalysisSelection::steinhardt},
    {"structure_factor", &AnalysisSelection::structure_factor},
    {"self_scattering", &AnalysisSelection::self_scattering},
}};

}  // namespace

AnalysisSelection parse_analysis_selection(std::string_view list) {
  AnalysisSelection chosen;
  for (const auto& [name, flag] : kAnalyses) chosen.*flag = false;
  std::string_view rest = list;
  while (true) {
    const std::size_t comma = rest.find(',');
    std::string_view name = rest.substr(0, comma);
    // "psi6, rdf" as "psi6,rdf"
    while (!name.empty() && name.front() == ' ') name.remove_prefix(1);
    while (!name.empty() && name.back() == ' ') name.remove_suffix(1);
    const auto* const found = std::find_if(kAnalyses.begin(), kAnalyses.end(),
                                           [&](const auto& a) { return a.first == name; });
    if (found == kAnalyses.end()) {
      throw std::invalid_argument(
          fmt::format("'{}' is not an analysis: the analyses are {}, separated by commas", name,
                      fmt::join(analysis_names(AnalysisSelection{}), ", ")));
    }
    if (chosen.*(found->second)) {
      throw std::invalid_argument(fmt::format("'{}' is named twice", name));
    }
    chosen.*(found->second) = true;
    if (comma == std::string_view::npos) break;
    rest = rest.substr(comma + 1);
  }
  return chosen;
}

std::vector<std::string> analysis_names(const AnalysisSelection& selection) {
  std::vector<std::string> names;
  for (const auto& [name, flag] : kAnalyses) {
    if (selection.*flag) names.emplace_back(name);
  }
  return names;
}

void check_selection(const AnalysisOptions& options) {
  const AnalysisSelection& only = options.only;
  // An option of an analysis left out would be ignored: refused, as the analysis's name.
  const struct {
    bool given;
    const char* option;
    bool AnalysisSelection::*of;
  } settings[] = {
      {options.rdf.bin_width > 0.0, "bin (--bin)", &AnalysisSelection::rdf},
      {options.rdf.r_max > 0.0, "r_max (--r-max)", &AnalysisSelection::rdf},
      {options.contact_width > 0.0, "contact_width (--contact-width)", &AnalysisSelection::rdf},
      {options.k_max > 0.0, "k_max (--k-max)", &AnalysisSelection::structure_factor},
      {options.fs_k > 0.0, "fs_k (--fs-k)", &AnalysisSelection::self_scattering},
      {options.bond_order.cutoff > 0.0, "order_cutoff (--order-cutoff)",
       &AnalysisSelection::steinhardt},
  };
  for (const auto& setting : settings) {
    if (setting.given && !(only.*setting.of)) {
      const auto* const of = std::find_if(kAnalyses.begin(), kAnalyses.end(),
                                          [&](const auto& a) { return a.second == setting.of; });
      throw std::invalid_argument(fmt::format(
          "{} is an option of {}, which the selection leaves out", setting.option, of->first));
    }
  }
  if (options.from_centre_of_mass && !only.msd && !only.self_scattering) {
    throw std::invalid_argument(
        "com (--com) is an option of msd and self_scattering, which the selection leaves out");
  }
  if (!only.self_scattering) return;
  if (!only.msd) {
    throw std::invalid_argument(
        "self_scattering needs msd too: F_s(k,t) is taken at the MSD's lags");
  }
  if (!only.structure_factor && !(options.fs_k > 0.0)) {
    throw std::invalid_argument(
        "self_scattering needs structure_factor too, for its main peak, or a wave number (fs_k, "
        "--fs-k)");
  }
}

Analysis analyze(std::vector<Frame> frames, const std::string& name,
                 const AnalysisOptions& options) {
  check_selection(options);
  if (frames.empty()) throw std::invalid_argument("the trajectory has no frames");
  // Every frame must share the first one's box: g(r) and the MSD are normalised by it.
  const Frame& first = frames.front();
  for (std::size_t f = 1; f < frames.size(); ++f) {
    const Frame& frame = frames[f];
    bool same = frame.periodic == first.periodic && frame.dimension == first.dimension &&
                frame.radius.size() == first.radius.size();
    for (int k = 0; k < first.dimension; ++k) {
      same =
          same && frame.box[static_cast<std::size_t>(k)] == first.box[static_cast<std::size_t>(k)];
    }
    if (!same) {
      throw std::invalid_argument(fmt::format(
          "frame {} (t = {:g}) has another box than frame 0: carom analyze needs a fixed box", f,
          frame.time));
    }
  }
  const std::size_t in_file = frames.size();
  const double last_time = frames.back().time;
  // A frame written at the time asked for may carry it with a rounding (0.8999999999999999
  // for 0.9): within a billionth of the time it counts as at it.
  const double from = options.from_time - 1e-9 * std::max(1.0, std::abs(options.from_time));
  std::erase_if(frames, [&](const Frame& frame) { return frame.time < from; });
  if (frames.empty()) {
    throw std::invalid_argument(fmt::format(
        "no frame at or after t = {:g} (the last is at t = {:g})", options.from_time, last_time));
  }
  Analysis analysis;
  analysis.trajectory = name;
  if (options.only != AnalysisSelection{}) analysis.only = analysis_names(options.only);
  analysis.shape = shape_of(frames.front());
  analysis.frames_in_file = in_file;
  for (const Frame& frame : frames) analysis.time.push_back(frame.time);
  const TrajectoryShape& shape = analysis.shape;

  const AnalysisSelection& only = options.only;
  if (only.rdf) add_rdf(analysis, frames, options);
  if (only.msd) {
    try {
      analysis.msd = mean_square_displacement(frames, options.from_centre_of_mass);
      analysis.from_centre_of_mass = options.from_centre_of_mass;
      warn_of_flow(analysis, options);
    } catch (const std::invalid_argument& e) {
      analysis.warnings.push_back(std::string("no MSD: ") + e.what());
    }
  }
  analysis.snapshot = frames.back();
  // Each order parameter is of one dimension: left out of the other's analysis silently, unless
  // a selection names it.
  const bool named = only != AnalysisSelection{};
  if (only.psi6 && shape.dimension == 2) {
    try {
      analysis.psi6 = psi6_series(frames);
      analysis.snapshot_psi6 = local_psi6(frames.back());
    } catch (const std::invalid_argument& e) {
      analysis.warnings.push_back(std::string("no psi6: ") + e.what());
    }
  } else if (only.psi6 && named) {
    analysis.warnings.emplace_back(
        "no psi6: the hexatic order psi6 is of disks, and these are spheres (steinhardt is "
        "theirs)");
  }
  if (only.steinhardt && shape.dimension == 3) {
    try {
      analysis.steinhardt = bond_order_series(frames, options.bond_order);
    } catch (const std::invalid_argument& e) {
      // A cutoff asked for is refused as --r-max is; the default one gives way to a small box.
      if (options.bond_order.cutoff > 0.0) throw;
      analysis.warnings.push_back(std::string("no Steinhardt bond order: ") + e.what());
    }
  } else if (only.steinhardt && named) {
    analysis.warnings.emplace_back(
        "no steinhardt: the Steinhardt bond order is of spheres, and these are disks (psi6 is "
        "theirs)");
  }
  add_scattering(analysis, frames, options);
  return analysis;
}

namespace {

// A number, or null for what is not one (JSON has no NaN).
nlohmann::json number(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

// The invariants of each degree under their names: q4, w4, q4_bar, w4_bar, q6, ...
void add_invariants(nlohmann::json& out, const std::array<SteinhardtInvariants, 2>& invariants) {
  for (const SteinhardtInvariants& of : invariants) {
    const std::string l = std::to_string(of.l);
    out["q" + l] = of.q;
    out["w" + l] = of.w;
    out["q" + l + "_bar"] = of.q_bar;
    out["w" + l + "_bar"] = of.w_bar;
  }
}

nlohmann::json to_json(const BondOrderSeries& s, double last_time) {
  using nlohmann::json;
  json out = {{"cutoff", s.cutoff},
              {"bonds", "every particle within the cutoff (minimum image)"},
              {"t", s.t},
              {"solid_like", s.solid_like},
              {"largest_cluster", s.largest_cluster},
              {"cluster_sizes", s.cluster_sizes}};
  add_invariants(out, s.means);
  const BondOrder& last = s.last_frame;
  json particles = {{"time", last_time},
                    {"neighbours", last.neighbours},
                    {"solid_bonds", last.solid_bonds},
                    {"solid_like", last.solid_like},
                    {"cluster", last.cluster}};
  add_invariants(particles, last.invariants);
  out["last_frame"] = particles;
  return out;
}

nlohmann::json to_json(const Analysis& a) {
  using nlohmann::json;
  const TrajectoryShape& shape = a.shape;
  json out = {
      {"carom_version", kVersion},
      {"trajectory", a.trajectory},
      {"dimension", shape.dimension},
      {"particles", shape.particles},
      {"box", shape.box},
      {"periodic", shape.periodic},
      {"packing_fraction", shape.packing_fraction},
      {"diameter", shape.mean_diameter},
      {"monodisperse", shape.monodisperse},
      {"frames",
       {{"count", a.time.size()},
        {"in_file", a.frames_in_file},
        {"first_time", a.time.front()},
        {"last_time", a.time.back()}}},
      {"time", a.time},
      {"only", a.only ? json(*a.only) : json(nullptr)},
  };
  out["rdf"] = nullptr;
  if (a.rdf) {
    const Rdf& rdf = *a.rdf;
    out["rdf"] = {
        {"r", rdf.r},
        {"g", rdf.g},
        {"bin_width", rdf.bin_width},
        {"r_max", rdf.r_max},
        {"contact", a.contact ? json{{"r", a.contact->r}, {"g", a.contact->g}, {"Z", a.contact->z}}
                              : json(nullptr)}};
    // A mixture's partial g_ab(r), and each pair's share of all pairs (sum share g_ab = g).
    if (!rdf.partial.empty()) {
      json partial = json::object(), weights = json::object();
      for (std::size_t k = 0; k < rdf.partial.size(); ++k) {
        partial[rdf.partial_names[k]] = rdf.partial[k];
        weights[rdf.partial_names[k]] = rdf.partial_weights[k];
      }
      out["rdf"]["partial"] = partial;
      out["rdf"]["partial_weights"] = weights;
    }
  }
  if (a.msd) {
    const std::optional<double> d =
        self_diffusion(*a.msd, static_cast<std::size_t>(a.snapshot.dimension));
    out["msd"] = json{{"t", a.msd->t},
                      {"msd", a.msd->msd},
                      {"self_diffusion", d ? json(*d) : json(nullptr)},
                      {"centre_of_mass_shift", a.msd->centre_of_mass_shift},
                      {"from_centre_of_mass", a.from_centre_of_mass}};
  } else {
    out["msd"] = nullptr;
  }
  out["psi6"] = a.psi6 ? json{{"t", a.psi6->t},
                              {"global", a.psi6->global},
                              {"local_mean", a.psi6->local_mean},
                              {"orientation", a.psi6->orientation},
                              {"bonds", "6 nearest neighbours"}}
                       : json(nullptr);
  const auto& sk = a.structure_factor;
  out["structure_factor"] =
      sk ? json{{"k", sk->k}, {"s", sk->s}, {"k_peak", sk->k_peak}} : json(nullptr);
  const auto& fs = a.self_scattering;
  if (fs) {
    json alpha2 = json::array();  // NaN at t = 0, where no particle has moved: null
    for (const double value : fs->alpha2) alpha2.push_back(number(value));
    out["self_scattering"] = {{"k", fs->k},
                              {"t", fs->t},
                              {"fs", fs->fs},
                              {"alpha2", alpha2},
                              {"tau_alpha", fs->tau_alpha ? json(*fs->tau_alpha) : json(nullptr)}};
  } else {
    out["self_scattering"] = nullptr;
  }
  out["steinhardt"] = a.steinhardt ? to_json(*a.steinhardt, a.time.back()) : json(nullptr);
  json position = json::array(), radius = json::array();
  for (std::size_t i = 0; i < a.snapshot.position.size(); ++i) {
    for (int k = 0; k < shape.dimension; ++k) {
      position.push_back(a.snapshot.position[i][static_cast<std::size_t>(k)]);
    }
    radius.push_back(a.snapshot.radius[i]);
  }
  json modulus = nullptr, phase = nullptr;
  if (!a.snapshot_psi6.empty()) {
    modulus = json::array();
    phase = json::array();
    for (const std::complex<double>& p : a.snapshot_psi6) {
      modulus.push_back(std::abs(p));
      phase.push_back(std::arg(p));
    }
  }
  out["snapshot"] = {{"time", a.snapshot.time},
                     {"position", position},
                     {"radius", radius},
                     {"psi6_modulus", modulus},
                     {"psi6_phase", phase}};
  if (a.log) {
    json rows = json::array();
    for (const std::vector<double>& row : a.log->rows) {
      json values = json::array();
      for (const double v : row) values.push_back(number(v));
      rows.push_back(values);
    }
    out["log"] = {{"file", a.log->file}, {"columns", a.log->columns}, {"rows", rows}};
  } else {
    out["log"] = nullptr;
  }
  out["warnings"] = a.warnings;
  return out;
}

}  // namespace

// A name that is not UTF-8 (a file name in Latin-1, say) is written as json_text.hpp says.
void write_analysis_json(std::ostream& out, const Analysis& analysis) {
  out << dump_json(to_json(analysis), 1) << '\n';
}

void write_report_html(std::ostream& out, const Analysis& analysis) {
  constexpr std::string_view kSlot = "/*CAROM_DATA*/";
  const std::size_t slot = kReportHtml.find(kSlot);
  // No "<" reaches the page as such: a file name holding "</script>" or "<!--" would otherwise
  // end or derail the page's script. JSON reads \u003c as "<".
  const std::string json = dump_json(to_json(analysis));
  std::string data;
  data.reserve(json.size());
  for (const char c : json) {
    if (c == '<') {
      data += "\\u003c";
    } else {
      data += c;
    }
  }
  out << kReportHtml.substr(0, slot) << data << kReportHtml.substr(slot + kSlot.size());
}

}  // namespace carom
