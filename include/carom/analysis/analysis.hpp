// Analysis of a trajectory's frames (carom analyze, carom.analyze in Python): the radial
// distribution function and its contact value, the mean-square displacement, the hexatic order
// psi6 of disks and the Steinhardt bond order of spheres (bond_order.hpp), and scattering
// (scattering.hpp: S(k), F_s(k,t)). Pure functions of the frames: nothing here reads files or
// prints.
#pragma once

#include <complex>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "carom/analysis/bond_order.hpp"
#include "carom/analysis/scattering.hpp"
#include "carom/io/log_table.hpp"
#include "carom/io/trajectory_reader.hpp"

namespace carom {

// The geometry every frame of a trajectory shares, taken from its first frame.
struct TrajectoryShape {
  int dimension = 2;
  std::size_t particles = 0;
  std::vector<double> box;  // dimension sides
  bool periodic = false;
  double mean_diameter = 0.0;
  bool monodisperse = true;  // every diameter equal
  double packing_fraction = 0.0;
};
TrajectoryShape shape_of(const Frame& frame);

struct RdfOptions {
  double bin_width = 0.0;  // 0: the mean diameter / 50, so that contact is a bin edge
  double r_max = 0.0;      // 0: 5 mean diameters, at most what the box allows
};

// g(r) at bin centres, averaged over the frames.
struct Rdf {
  std::vector<double> r, g;
  double bin_width = 0.0, r_max = 0.0;
  // Frames of two types or more (Frame::type): the partial g_ab(r) of each pair of types a <= b
  // (in type order), named "A-B", each 1 at every r for an ideal mixture, and each pair's share
  // of all pairs, N_a (N_a - 1) / (N (N - 1)) for a = b and 2 N_a N_b / (N (N - 1)) for a != b
  // (x_a x_b counted both ways, for N particles), so that g = sum of share x g_ab exactly. Empty
  // for one type.
  std::vector<std::string> partial_names;
  std::vector<std::vector<double>> partial;
  std::vector<double> partial_weights;
};

// The radial distribution function of every pair of particles within r_max, found through a cell
// grid (O(N) a frame), by minimum image in a periodic box. The ideal-gas normalisation is the
// shell's volume over the box's in a periodic box (r_max at most half the smallest side); between
// walls it is the isotropic set covariance of the box the centres can reach (the sides less a
// mean diameter), so that g is not biased low near the walls' cut-off pairs. Throws
// std::invalid_argument for a bin or range the box cannot have.
Rdf radial_distribution(const std::vector<Frame>& frames, const RdfOptions& options = {});

// g at contact, extrapolated from the bins within `width` above contact (a least-squares
// quadratic in r - d), and the equation of state's Z = 1 + 2^(D-1) eta g(d+) (Z = 1 + 2 eta g in
// 2D, 1 + 4 eta g in 3D) for a monodisperse fluid. Nullopt when fewer than three bins lie there.
struct ContactValue {
  double r = 0.0, g = 0.0, z = 0.0;
};
std::optional<ContactValue> contact_value(const Rdf& rdf, double diameter, int dimension,
                                          double packing_fraction, double width);

// The mean-square displacement of the unwrapped positions (position + image x box in a periodic
// box), averaged over every particle and every time origin, at lags of whole frames: every lag
// up to 200 frames, beyond that about 100 lags evenly spaced in log. The centre of mass's motion
// is in it unless `from_centre_of_mass` (dynamics keeps it still; event chains do not). Throws
// std::invalid_argument when the frames are not evenly spaced in time, or a periodic trajectory
// has no image flags.
struct Msd {
  std::vector<double> t, msd;
  double centre_of_mass_shift = 0.0;  // how far the centre of mass moved, first frame to last
};
Msd mean_square_displacement(const std::vector<Frame>& frames, bool from_centre_of_mass = false);

// The self-diffusion coefficient an MSD shows in `dimension` dimensions: its growth rate between
// the lags T / 4 and T / 2 (T the longest lag: every lag up to T / 2 has at least half the frames
// as origins), over 2 d (Einstein; the short-time curvature cancels). Nullopt with fewer than 5
// lags.
std::optional<double> self_diffusion(const Msd& msd, std::size_t dimension);

// The local hexatic order of each disk of a 2D frame: psi6_j = (1/6) sum over its six nearest
// neighbours k (minimum image; ties by index) of exp(6 i theta_jk), theta_jk the angle of the bond
// j -> k to the x axis. Throws std::invalid_argument for spheres or fewer than 7 disks.
std::vector<std::complex<double>> local_psi6(const Frame& frame);

// Per frame: |(1/N) sum_j psi6_j| (global), (1/N) sum_j |psi6_j| (the mean local order) and
// the orientation of the global order, arg((1/N) sum_j psi6_j) / 6 in degrees, in (-30, 30]:
// the angle of the bonds of the dominant hexatic order to the x axis, modulo 60 degrees. In a
// periodic box it is how the order sits in the box, a variable a large ordered system changes
// only slowly.
struct Psi6Series {
  std::vector<double> t, global, local_mean, orientation;
};
Psi6Series psi6_series(const std::vector<Frame>& frames);

// Which analyses to compute, by their names in the JSON (rdf, msd, psi6, steinhardt,
// structure_factor, self_scattering): every one that applies by default. Those not selected are
// not computed (at large N some take long: S(k) and F_s(k,t) seconds a frame at 65536 disks)
// and are null in the JSON.
struct AnalysisSelection {
  bool rdf = true, msd = true, psi6 = true, steinhardt = true, structure_factor = true,
       self_scattering = true;
  friend bool operator==(const AnalysisSelection&, const AnalysisSelection&) = default;
};
// The analyses `list` names, separated by commas ("psi6,structure_factor", or "psi6, rdf"):
// those alone. std::invalid_argument for a name that is none of them (an empty one too), or one
// named twice.
AnalysisSelection parse_analysis_selection(std::string_view list);
// The names of the analyses a selection holds, in the order above.
std::vector<std::string> analysis_names(const AnalysisSelection& selection);

struct AnalysisOptions;
// F_s(k,t) is taken at the MSD's lags and at S(k)'s main peak (unless fs_k names k): a selection
// of self_scattering without msd, or without structure_factor and fs_k, is refused
// (std::invalid_argument), before any frame is read; so is an option of an analysis the
// selection leaves out (fs_k without self_scattering, say), which would be ignored.
void check_selection(const AnalysisOptions& options);

struct AnalysisOptions {
  AnalysisSelection only;  // every analysis by default
  RdfOptions rdf;
  double contact_width = 0.0;  // the range above contact g(d+) is fitted on; 0: a tenth of d
  double from_time = -1e300;   // frames before this time are left out (equilibration)
  double k_max = 0.0;          // how far S(k) reaches; 0: 20 / the mean diameter
  double fs_k = 0.0;           // the wave number of F_s(k,t); 0: the main peak of S(k)
  BondOrderOptions bond_order;
  // The MSD and F_s(k,t) from displacements relative to the centre of mass (--com).
  bool from_centre_of_mass = false;
};

// Everything carom analyze computes, for its JSON and its report page. An analysis that does
// not apply is absent: psi6 of spheres and the bond order of disks silently (each is defined for
// the other dimension only), the MSD and F_s without image flags, the contact value of a
// polydisperse or walled system, S(k) between walls, and the bond order in a box too small for
// its cutoff with the reason in `warnings`.
struct Analysis {
  std::string trajectory;
  TrajectoryShape shape;
  std::size_t frames_in_file = 0;
  std::vector<double> time;  // of the frames analysed
  // The analyses selected (AnalysisOptions::only), by name; absent where every one was.
  std::optional<std::vector<std::string>> only;
  std::optional<Rdf> rdf;  // absent only where not selected
  std::optional<ContactValue> contact;
  std::optional<Msd> msd;
  bool from_centre_of_mass = false;  // the MSD's and F_s's displacements (--com)
  std::optional<Psi6Series> psi6;
  std::optional<StructureFactor> structure_factor;
  std::optional<SelfScattering> self_scattering;
  std::optional<BondOrderSeries> steinhardt;        // spheres only
  Frame snapshot;                                   // the last frame analysed
  std::vector<std::complex<double>> snapshot_psi6;  // its local psi6 (disks only)
  std::optional<LogTable> log;
  std::vector<std::string> warnings;
};

// Analyses the frames of the trajectory named `name` from options.from_time on (a frame within a
// billionth of that time counts as at it). Throws std::invalid_argument when no frame is left,
// when the frames do not share one box, or for options the trajectory cannot have (a bond-order
// cutoff given that the box cannot have; the default one is only warned about), or a selection
// that leaves out what a selected analysis needs (check_selection).
Analysis analyze(std::vector<Frame> frames, const std::string& name,
                 const AnalysisOptions& options = {});

// The analysis as one JSON document: carom_version, trajectory, dimension, particles, box,
// periodic, packing_fraction, diameter, monodisperse, frames {count, first_time, last_time},
// time, only (the analyses selected, or null for every one), rdf {r, g, bin_width, r_max,
// contact {r, g, Z} or null} or null, msd {t, msd} or null, psi6 {t, global, local_mean,
// orientation, bonds} or null, structure_factor {k, s, k_peak} or null, self_scattering
// {k, t, fs, alpha2, tau_alpha} or null, steinhardt {cutoff, bonds, t, q4, q6, w4, w6, q4_bar,
// q6_bar, w4_bar, w6_bar (frame means), solid_like, largest_cluster, cluster_sizes, last_frame
// {time, neighbours, q4, ..., w6_bar, solid_bonds, solid_like, cluster} (per particle)} or null,
// snapshot {time, position, radius, psi6_modulus, psi6_phase}, log {file, columns, rows} or null,
// warnings.
void write_analysis_json(std::ostream& out, const Analysis& analysis);

// The report: one self-contained HTML page (no network) with the summary and plots of g(r), the
// MSD, psi6(t), q6 and the largest solid-like cluster (t), S(k), F_s(k,t) and alpha2(t), the
// log's Z, and a snapshot coloured by the phase of the local psi6.
void write_report_html(std::ostream& out, const Analysis& analysis);

}  // namespace carom
