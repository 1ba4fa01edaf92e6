#include "carom/analysis/analysis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>

#include "carom/analysis/displacements.hpp"
#include "analysis/neighbours.hpp"

namespace carom {

namespace {

constexpr double kPi = std::numbers::pi;

double ball_volume(int dimension, double r) {
  return dimension == 2 ? kPi * r * r : 4.0 / 3.0 * kPi * r * r * r;
}

// The volume two copies of a box of sides `a` share, one shifted by a distance r in a uniformly
// random direction (the isotropic set covariance; exact for r up to the smallest side).
double set_covariance(const std::vector<double>& a, double r) {
  if (a.size() == 2) return a[0] * a[1] - 2.0 * r * (a[0] + a[1]) / kPi + r * r / kPi;
  return a[0] * a[1] * a[2] - r * (a[0] * a[1] + a[0] * a[2] + a[1] * a[2]) / 2.0 +
         2.0 * r * r * (a[0] + a[1] + a[2]) / (3.0 * kPi) - r * r * r / (4.0 * kPi);
}

// `pair_of[a * types + b]` is the partial histogram a pair of types a and b adds to, when the
// frame has types (`partials` not empty).
template <std::size_t D>
void count_pairs(const Frame& frame, double bin_width, double r_max,
                 std::vector<double>& histogram, std::vector<std::vector<double>>& partials,
                 const std::vector<std::size_t>& pair_of, std::size_t types) {
  Neighbours<D> neighbours(frame);
  const bool typed = !partials.empty();
  const double reach2 = r_max * r_max;
  for (std::size_t i = 0; i < neighbours.size(); ++i) {
    // Each pair is counted from its lower index.
    neighbours.for_each_candidate(i, r_max, [&](std::size_t j) {
      if (j <= i) return;
      const double r2 = norm2(neighbours.separation(i, j));
      if (r2 >= reach2) return;
      const auto bin = static_cast<std::size_t>(std::sqrt(r2) / bin_width);
      if (bin < histogram.size()) {
        histogram[bin] += 1.0;
        if (typed) partials[pair_of[frame.type[i] * types + frame.type[j]]][bin] += 1.0;
      }
    });
  }
}

template <std::size_t D>
std::vector<std::complex<double>> local_psi6_in(const Frame& frame) {
  Neighbours<D> neighbours(frame);
  const std::size_t n = neighbours.size();
  std::vector<std::complex<double>> psi(n);
  struct Candidate {
    double r2;
    std::size_t j;
    Vec<D> bond;
    bool operator<(const Candidate& o) const { return r2 < o.r2 || (r2 == o.r2 && j < o.j); }
  };
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < n; ++i) {
    // Every particle as near as the sixth nearest, ties included: the six nearest by distance
    // and then index, whatever order the tree finds them in.
    candidates.clear();
    neighbours.for_each_candidate(i, neighbours.reach_of_nearest(i, 6), [&](std::size_t j) {
      const Vec<D> bond = neighbours.separation(i, j);
      candidates.push_back({norm2(bond), j, bond});
    });
    std::partial_sort(candidates.begin(), candidates.begin() + 6, candidates.end());
    std::complex<double> sum = 0.0;
    for (std::size_t m = 0; m < 6; ++m) {
      const Vec<D>& b = candidates[m].bond;
      sum += std::polar(1.0, 6.0 * std::atan2(b[1], b[0]));
    }
    psi[i] = sum / 6.0;
  }
  return psi;
}

}  // namespace

TrajectoryShape shape_of(const Frame& frame) {
  TrajectoryShape shape;
  shape.dimension = frame.dimension;
  shape.particles = frame.radius.size();
  shape.periodic = frame.periodic;
  double volume = 1.0, filled = 0.0, diameters = 0.0;
  for (int k = 0; k < frame.dimension; ++k) {
    shape.box.push_back(frame.box[static_cast<std::size_t>(k)]);
    volume *= frame.box[static_cast<std::size_t>(k)];
  }
  for (const double r : frame.radius) {
    filled += ball_volume(frame.dimension, r);
    diameters += 2.0 * r;
    shape.monodisperse = shape.monodisperse && r == frame.radius.front();
  }
  shape.mean_diameter = diameters / static_cast<double>(frame.radius.size());
  shape.packing_fraction = filled / volume;
  return shape;
}

Rdf radial_distribution(const std::vector<Frame>& frames, const RdfOptions& options) {
  if (frames.empty()) throw std::invalid_argument("g(r) needs at least one frame");
  const TrajectoryShape shape = shape_of(frames.front());
  if (shape.particles < 2) throw std::invalid_argument("g(r) needs two particles or more");
  const double d = shape.mean_diameter;
  // Where pair centres can be: the whole box when periodic, the box less a diameter between walls.
  std::vector<double> window = shape.box;
  if (!shape.periodic) {
    for (double& side : window) side -= d;
  }
  const double smallest = *std::min_element(window.begin(), window.end());
  // Minimum image sees every pair up to half the smallest side; the set covariance holds up to
  // the smallest side, and half of it keeps the correction small.
  const double most = 0.5 * smallest;
  Rdf rdf;
  rdf.bin_width = options.bin_width > 0.0 ? options.bin_width : d / 50.0;
  double r_max = options.r_max > 0.0 ? options.r_max : std::min(5.0 * d, most);
  if (!(most > 0.0) || r_max > most * (1.0 + 1e-12)) {
    throw std::invalid_argument(fmt::format(
        "g(r) reaches r = {:g} at most in this box (half its smallest side{}), not {:g}", most,
        shape.periodic ? "" : " less a diameter", r_max));
  }
  const double bin_count = std::floor(r_max / rdf.bin_width * (1.0 + 1e-12));
  if (!(bin_count >= 1.0 && bin_count <= 1e7)) {
    throw std::invalid_argument(
        fmt::format("a bin width of {:g} gives {:g} bins up to r = {:g} "
                    "(1 to 10^7)",
                    rdf.bin_width, bin_count, r_max));
  }
  const auto bins = static_cast<std::size_t>(bin_count);
  rdf.r_max = static_cast<double>(bins) * rdf.bin_width;
  std::vector<double> histogram(bins, 0.0);
  // The types of the first frame, which every frame must share.
  const Frame& first = frames.front();
  const std::size_t types = first.type.empty() ? 1 : first.type_names.size();
  std::vector<std::vector<double>> partials;
  std::vector<std::size_t> pair_of(types * types);
  std::vector<double> type_count(types, 0.0);
  if (types > 1) {
    for (const std::uint32_t t : first.type) type_count[t] += 1.0;
    for (std::size_t a = 0; a < types; ++a) {
      for (std::size_t b = a; b < types; ++b) {
        pair_of[a * types + b] = pair_of[b * types + a] = rdf.partial_names.size();
        rdf.partial_names.push_back(first.type_names[a] + "-" + first.type_names[b]);
      }
    }
    partials.assign(rdf.partial_names.size(), std::vector<double>(bins, 0.0));
    for (const Frame& frame : frames) {
      if (frame.type != first.type || frame.type_names != first.type_names) {
        throw std::invalid_argument(
            "the particles' types change between frames: partial g(r) needs the same types in "
            "every frame");
      }
    }
  }
  for (const Frame& frame : frames) {
    if (shape.dimension == 2) {
      count_pairs<2>(frame, rdf.bin_width, rdf.r_max, histogram, partials, pair_of, types);
    } else {
      count_pairs<3>(frame, rdf.bin_width, rdf.r_max, histogram, partials, pair_of, types);
    }
  }
  const auto n = static_cast<double>(shape.particles);
  double window_volume = 1.0;
  for (const double side : window) window_volume *= side;
  const double pairs = static_cast<double>(frames.size()) * n * (n - 1.0) / 2.0;
  for (std::size_t b = 0; b < bins; ++b) {
    const double lo = static_cast<double>(b) * rdf.bin_width, hi = lo + rdf.bin_width;
    const double r = lo + 0.5 * rdf.bin_width;
    const double shell = ball_volume(shape.dimension, hi) - ball_volume(shape.dimension, lo);
    // The chance that an ideal pair's separation falls in the shell.
    const double share = shape.periodic
                             ? shell / window_volume
                             : shell * set_covariance(window, r) / (window_volume * window_volume);
    rdf.r.push_back(r);
    rdf.g.push_back(histogram[b] / (pairs * share));
  }
  // Each partial over its own pairs: N_a (N_a - 1) / 2 of a type with itself, N_a N_b of two.
  rdf.partial.resize(partials.size());
  for (std::size_t a = 0; a < types && types > 1; ++a) {
    for (std::size_t b = a; b < types; ++b) {
      const std::size_t k = pair_of[a * types + b];
      const double own = a == b ? type_count[a] * (type_count[a] - 1.0) / 2.0
                                : type_count[a] * type_count[b];
      rdf.partial_weights.push_back(own / (n * (n - 1.0) / 2.0));
      const double own_pairs = static_cast<double>(frames.size()) * own;
      for (std::size_t bin = 0; bin < bins; ++bin) {
        const double lo = static_cast<double>(bin) * rdf.bin_width, hi = lo + rdf.bin_width;
        const double shell = ball_volume(shape.dimension, hi) - ball_volume(shape.dimension, lo);
        const double ideal =
            shape.periodic
                ? shell / window_volume
                : shell * set_covariance(window, rdf.r[bin]) / (window_volume * window_volume);
        rdf.partial[k].push_back(own_pairs > 0.0 ? partials[k][bin] / (own_pairs * ideal) : 0.0);
      }
    }
  }
  return rdf;
}

std::optional<ContactValue> contact_value(const Rdf& rdf, double diameter, int dimension,
                                          double packing_fraction, double width) {
  // Least squares for g = c0 + c1 x + c2 x^2, x = r - d, over the bins wholly in [d, d + width].
  std::array<std::array<double, 4>, 3> normal{};  // the normal equations, augmented
  std::size_t used = 0;
  for (std::size_t b = 0; b < rdf.r.size(); ++b) {
    const double lo = rdf.r[b] - 0.5 * rdf.bin_width, hi = rdf.r[b] + 0.5 * rdf.bin_width;
    if (lo < diameter * (1.0 - 1e-9) || hi > (diameter + width) * (1.0 + 1e-9)) continue;
    const double x = rdf.r[b] - diameter;
    const std::array<double, 3> basis = {1.0, x, x * x};
    for (std::size_t p = 0; p < 3; ++p) {
      for (std::size_t q = 0; q < 3; ++q) normal[p][q] += basis[p] * basis[q];
      normal[p][3] += basis[p] * rdf.g[b];
    }
    ++used;
  }
  if (used < 3) return std::nullopt;
  // Gaussian elimination with partial pivoting, then back substitution.
  for (std::size_t p = 0; p < 3; ++p) {
    std::size_t pivot = p;
    for (std::size_t q = p + 1; q < 3; ++q) {
      if (std::abs(normal[q][p]) > std::abs(normal[pivot][p])) pivot = q;
    }
    std::swap(normal[p], normal[pivot]);
    for (std::size_t q = p + 1; q < 3; ++q) {
      const double factor = normal[q][p] / normal[p][p];
      for (std::size_t c = p; c < 4; ++c) normal[q][c] -= factor * normal[p][c];
    }
  }
  std::array<double, 3> c{};
  for (std::size_t p = 3; p-- > 0;) {
    double rest = normal[p][3];
    for (std::size_t q = p + 1; q < 3; ++q) rest -= normal[p][q] * c[q];
    c[p] = rest / normal[p][p];
  }
  ContactValue contact;
  contact.r = diameter;
  contact.g = c[0];
  contact.z = 1.0 + (dimension == 2 ? 2.0 : 4.0) * packing_fraction * contact.g;
  return contact;
}

Msd mean_square_displacement(const std::vector<Frame>& frames, bool from_centre_of_mass) {
  UnwrappedTrajectory trajectory = unwrap(frames, "the MSD");
  const double shift = std::sqrt(centre_of_mass_shift_squared(trajectory));
  if (from_centre_of_mass) remove_centre_of_mass_motion(trajectory);
  const DisplacementMoments moments = displacement_moments(trajectory);
  return {moments.t, moments.r2, shift};
}

std::optional<double> self_diffusion(const Msd& msd, std::size_t dimension) {
  if (msd.t.size() < 5) return std::nullopt;
  // The lag nearest to `t` (the lags are increasing).
  const auto nearest = [&](double t) {
    std::size_t best = 0;
    for (std::size_t k = 1; k < msd.t.size(); ++k) {
      if (std::abs(msd.t[k] - t) < std::abs(msd.t[best] - t)) best = k;
    }
    return best;
  };
  const std::size_t upper = nearest(0.5 * msd.t.back()), lower = nearest(0.25 * msd.t.back());
  if (upper <= lower) return std::nullopt;
  return (msd.msd[upper] - msd.msd[lower]) /
         (2.0 * static_cast<double>(dimension) * (msd.t[upper] - msd.t[lower]));
}

std::vector<std::complex<double>> local_psi6(const Frame& frame) {
  if (frame.dimension != 2) {
    throw std::invalid_argument("psi6, the hexatic order, is defined for disks (2D)");
  }
  if (frame.position.size() < 7) {
    throw std::invalid_argument(fmt::format(
        "psi6 needs six neighbours a disk: 7 disks or more, not {}", frame.position.size()));
  }
  return local_psi6_in<2>(frame);
}

namespace {

// arg(psi) / 6 in degrees, in (-30, 30]: arg is in (-pi, pi], and a bond order of six-fold
// symmetry turns by 60 degrees of bonds as its phase turns by 360.
double bond_orientation_degrees(std::complex<double> psi) {
  return std::arg(psi) / 6.0 * 180.0 / std::numbers::pi;
}

}  // namespace

Psi6Series psi6_series(const std::vector<Frame>& frames) {
  Psi6Series series;
  for (const Frame& frame : frames) {
    const std::vector<std::complex<double>> psi = local_psi6(frame);
    std::complex<double> sum = 0.0;
    double moduli = 0.0;
    for (const std::complex<double>& p : psi) {
      sum += p;
      moduli += std::abs(p);
    }
    const auto n = static_cast<double>(psi.size());
    series.t.push_back(frame.time);
    series.global.push_back(std::abs(sum) / n);
    series.local_mean.push_back(moduli / n);
    series.orientation.push_back(bond_orientation_degrees(sum));
  }
  return series;
}

}  // namespace carom
