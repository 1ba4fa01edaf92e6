#include "carom/analysis/scattering.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "carom/analysis/displacements.hpp"

namespace carom {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// The particles of S(k)'s blocks: few enough that their tables of phases stay in a core's cache,
// and that their size does not grow with N.
constexpr std::size_t kParticleBlock = 128;

// The k-vectors whose phases S(k) holds at once (128 kB for a block).
constexpr std::size_t kVectorChunk = 64;

// The sums below run in this many independent partial sums over rows padded with zeros to a
// multiple of it: one running sum waits for each addition before the next (the compiler may not
// reorder floating-point sums).
constexpr std::size_t kLanes = 8;

std::size_t padded(std::size_t size) {
  return (size + kLanes - 1) / kLanes * kLanes;
}

// sum_c term(c) over c < size (a multiple of kLanes).
template <class Term>
double sum_of(std::size_t size, Term&& term) {
  std::array<double, kLanes> lanes{};
  for (std::size_t c = 0; c < size; c += kLanes) {
    for (std::size_t l = 0; l < kLanes; ++l) lanes[l] += term(c + l);
  }
  double sum = 0.0;
  for (const double lane : lanes) sum += lane;
  return sum;
}

// exp(-i k . r) = prod_k exp(-2 pi i n_k x_k / L_k) for a block of particles: a table of each
// factor, for every n_k in [-reach_k, reach_k], so that a particle and k-vector cost D - 1
// complex products instead of a sine and a cosine.
class PhaseTables {
 public:
  // `width` (at least `size`) is a row's length; entries past `size` stay 0.
  PhaseTables(std::size_t dimension, const Vec<3>& box, const std::array<int, 3>& reach,
              std::size_t width)
      : d_(dimension), box_(box), reach_(reach), width_(width) {}

  // The factors of particles 0 ... size - 1, x(i, k) their coordinate along side k. Row m (n_k
  // = m - reach) holds exp(-2 pi i n_k x / L) as the product exp(-2 pi i 16 a x / L) exp(-2 pi
  // i b x / L) (|n_k| = 16 a + b) of two values from a sine and cosine: two roundings off at
  // most, for 16 + reach / 16 sines a particle instead of 2 reach + 1. -n_k is the conjugate.
  template <class Coordinate>
  void fill(std::size_t size, Coordinate&& x) {
    constexpr int kSplit = 16;
    for (std::size_t k = 0; k < d_; ++k) {
      const auto reach = static_cast<std::size_t>(reach_[k]);
      re_[k].assign((2 * reach + 1) * width_, 0.0);
      im_[k].assign((2 * reach + 1) * width_, 0.0);
      for (std::size_t i = 0; i < size; ++i) {
        const double turn = -kTwoPi * x(i, k) / box_[k];
        std::array<double, kSplit> low_re{}, low_im{};
        for (int b = 0; b < kSplit; ++b) {
          low_re[b] = std::cos(b * turn);
          low_im[b] = std::sin(b * turn);
        }
        for (std::size_t high = 0; high <= reach; high += kSplit) {
          const double high_re = std::cos(static_cast<double>(high) * turn);
          const double high_im = std::sin(static_cast<double>(high) * turn);
          for (std::size_t b = 0; b < kSplit && high + b <= reach; ++b) {
            const double z_re = high_re * low_re[b] - high_im * low_im[b];
            const double z_im = high_re * low_im[b] + high_im * low_re[b];
            re_[k][(reach + high + b) * width_ + i] = z_re;
            im_[k][(reach + high + b) * width_ + i] = z_im;
            re_[k][(reach - high - b) * width_ + i] = z_re;
            im_[k][(reach - high - b) * width_ + i] = -z_im;
          }
        }
      }
    }
  }

  // exp(-i k . r_i) of every particle i < width at the k-vectors index[first ... last - 1]:
  // q's at re[(q - first) width + i] and im[...].
  void phases(const std::vector<std::array<int, 3>>& index, std::size_t first, std::size_t last,
              double* re, double* im) const {
    for (std::size_t q = first; q < last; ++q) {
      std::array<const double*, 3> a_re{}, a_im{};
      for (std::size_t k = 0; k < d_; ++k) {
        const auto row = static_cast<std::size_t>(index[q][k] + reach_[k]);
        a_re[k] = &re_[k][row * width_];
        a_im[k] = &im_[k][row * width_];
      }
      double* out_re = re + (q - first) * width_;
      double* out_im = im + (q - first) * width_;
      for (std::size_t i = 0; i < width_; ++i) {
        out_re[i] = a_re[0][i] * a_re[1][i] - a_im[0][i] * a_im[1][i];
        out_im[i] = a_re[0][i] * a_im[1][i] + a_im[0][i] * a_re[1][i];
      }
      if (d_ == 3) {
        for (std::size_t i = 0; i < width_; ++i) {
          const double xy_re = out_re[i];
          out_re[i] = xy_re * a_re[2][i] - out_im[i] * a_im[2][i];
          out_im[i] = xy_re * a_im[2][i] + out_im[i] * a_re[2][i];
        }
      }
    }
  }

 private:
  std::size_t d_;
  Vec<3> box_;
  std::array<int, 3> reach_;
  std::size_t width_;
  std::array<std::vector<double>, 3> re_, im_;
};

// The largest |n_k| along each side among the k-vectors `index`.
std::array<int, 3> reach_of(const std::vector<std::array<int, 3>>& index) {
  std::array<int, 3> reach{};
  for (const std::array<int, 3>& n : index) {
    for (std::size_t k = 0; k < 3; ++k) reach[k] = std::max(reach[k], std::abs(n[k]));
  }
  return reach;
}

bool upper_half(const std::array<int, 3>& n) {
  for (const int c : n) {
    if (c != 0) return c > 0;
  }
  return false;
}

}  // namespace

double wave_number_step(const Frame& frame) {
  double smallest = frame.box[0];
  for (std::size_t k = 1; k < static_cast<std::size_t>(frame.dimension); ++k) {
    smallest = std::min(smallest, frame.box[k]);
  }
  return kTwoPi / smallest;
}

std::vector<WaveShell> wave_shells(int dimension, const Vec<3>& box, std::size_t shells) {
  const auto d = static_cast<std::size_t>(dimension);
  double smallest = box[0];
  for (std::size_t k = 1; k < d; ++k) smallest = std::min(smallest, box[k]);
  // |k| / dk = sqrt(sum (n_k L_min / L_k)^2); no shell reaches beyond |k| = (shells + 1/2) dk.
  std::array<double, 3> ratio{}, most{};
  double points = 1.0;
  for (std::size_t k = 0; k < d; ++k) {
    ratio[k] = smallest / box[k];
    most[k] = std::ceil((static_cast<double>(shells) + 0.5) / ratio[k]);
    points *= 2.0 * most[k] + 1.0;
  }
  if (!(points <= 1e8)) {
    throw std::invalid_argument(fmt::format(
        "the k-grid up to k = {:g} of this box has {:g} points, more than 10^8: a smaller k",
        (static_cast<double>(shells) + 0.5) * kTwoPi / smallest, points));
  }
  std::array<int, 3> reach{};
  for (std::size_t k = 0; k < d; ++k) reach[k] = static_cast<int>(most[k]);
  const auto shell_of = [&](const std::array<int, 3>& n) {
    double q = 0.0;
    for (std::size_t k = 0; k < d; ++k) q += (n[k] * ratio[k]) * (n[k] * ratio[k]);
    const double m = std::floor(std::sqrt(q) + 0.5);
    return m <= static_cast<double>(shells) ? static_cast<std::size_t>(m) : 0;
  };
  // Every n of the upper half in lexicographic order, with its shell (0: none kept).
  const auto for_each_index = [&](auto&& f) {
    std::array<int, 3> n{};
    for (n[0] = -reach[0]; n[0] <= reach[0]; ++n[0]) {
      for (n[1] = -reach[1]; n[1] <= reach[1]; ++n[1]) {
        for (n[2] = -reach[2]; n[2] <= reach[2]; ++n[2]) {
          if (upper_half(n)) f(n, shell_of(n));
        }
      }
    }
  };
  std::vector<std::size_t> count(shells + 1, 0), seen(shells + 1, 0);
  for_each_index([&](const std::array<int, 3>&, std::size_t m) { ++count[m]; });
  std::vector<WaveShell> out(shells);
  for_each_index([&](const std::array<int, 3>& n, std::size_t m) {
    if (m == 0) return;
    WaveShell& shell = out[m - 1];
    const std::size_t position = seen[m]++, taken = shell.index.size();
    if (count[m] > kWaveVectorsPerShell &&
        (taken == kWaveVectorsPerShell || position != taken * count[m] / kWaveVectorsPerShell)) {
      return;
    }
    shell.index.push_back(n);
    double k2 = 0.0;
    for (std::size_t k = 0; k < d; ++k) k2 += (kTwoPi * n[k] / box[k]) * (kTwoPi * n[k] / box[k]);
    shell.k += std::sqrt(k2);
  });
  for (WaveShell& shell : out) shell.k /= static_cast<double>(shell.index.size());
  return out;
}

std::vector<double> structure_factor_at(const Frame& frame,
                                        const std::vector<std::array<int, 3>>& index) {
  const auto d = static_cast<std::size_t>(frame.dimension);
  const std::size_t n = frame.position.size(), width = padded(std::min(kParticleBlock, n));
  PhaseTables tables(d, frame.box, reach_of(index), width);
  std::vector<double> re(kVectorChunk * width), im(kVectorChunk * width);
  std::vector<double> sum_re(index.size(), 0.0), sum_im(index.size(), 0.0);
  for (std::size_t first = 0; first < n; first += kParticleBlock) {
    tables.fill(std::min(kParticleBlock, n - first),
                [&](std::size_t i, std::size_t k) { return frame.position[first + i][k]; });
    for (std::size_t chunk = 0; chunk < index.size(); chunk += kVectorChunk) {
      const std::size_t last = std::min(chunk + kVectorChunk, index.size());
      tables.phases(index, chunk, last, re.data(), im.data());
      for (std::size_t q = chunk; q < last; ++q) {
        const double* z_re = &re[(q - chunk) * width];
        const double* z_im = &im[(q - chunk) * width];
        sum_re[q] += sum_of(width, [&](std::size_t i) { return z_re[i]; });
        sum_im[q] += sum_of(width, [&](std::size_t i) { return z_im[i]; });
      }
    }
  }
  std::vector<double> s(index.size());
  for (std::size_t q = 0; q < index.size(); ++q) {
    s[q] = (sum_re[q] * sum_re[q] + sum_im[q] * sum_im[q]) / static_cast<double>(n);
  }
  return s;
}

StructureFactor structure_factor(const std::vector<Frame>& frames, double k_max) {
  if (frames.empty()) throw std::invalid_argument("S(k) needs at least one frame");
  const Frame& first = frames.front();
  if (!first.periodic) {
    throw std::invalid_argument("S(k) is taken on a periodic box's k-grid, and this box has walls");
  }
  const double step = wave_number_step(first);
  const double shells = std::floor(k_max / step * (1.0 + 1e-12));
  if (!(shells >= 1.0)) {
    throw std::invalid_argument(fmt::format(
        "S(k) starts at k = 2 pi / L_min = {:g} in this box, beyond k_max = {:g}", step, k_max));
  }
  const std::vector<WaveShell> grid =
      wave_shells(first.dimension, first.box, static_cast<std::size_t>(shells));
  std::vector<std::array<int, 3>> index;
  for (const WaveShell& shell : grid)
    index.insert(index.end(), shell.index.begin(), shell.index.end());
  std::vector<double> total(index.size(), 0.0);
  const std::size_t used = std::min(frames.size(), kStructureFactorFrames);
  for (std::size_t j = 0; j < used; ++j) {
    const std::vector<double> s = structure_factor_at(frames[j * frames.size() / used], index);
    for (std::size_t q = 0; q < index.size(); ++q) total[q] += s[q];
  }
  StructureFactor out;
  std::size_t q = 0;
  for (const WaveShell& shell : grid) {
    double sum = 0.0;
    for (std::size_t v = 0; v < shell.index.size(); ++v) sum += total[q++];
    out.k.push_back(shell.k);
    out.s.push_back(sum / static_cast<double>(shell.index.size() * used));
  }
  out.k_peak =
      out.k[static_cast<std::size_t>(std::max_element(out.s.begin(), out.s.end()) - out.s.begin())];
  return out;
}

SelfScattering self_scattering(const std::vector<Frame>& frames, double k,
                               bool from_centre_of_mass) {
  UnwrappedTrajectory trajectory = unwrap(frames, "F_s(k,t)");
  if (from_centre_of_mass) remove_centre_of_mass_motion(trajectory);
  const Frame& first = frames.front();
  const double step = wave_number_step(first);
  const double shell = std::floor(k / step + 0.5);
  if (!(shell >= 1.0)) {
    throw std::invalid_argument(fmt::format(
        "F_s(k,t) needs k of at least {:g} (half the step 2 pi / L_min = {:g} of the box's "
        "k-grid), not {:g}",
        0.5 * step, step, k));
  }
  const WaveShell wave =
      wave_shells(first.dimension, first.box, static_cast<std::size_t>(shell)).back();
  const std::size_t count = trajectory.frames, n = trajectory.particles, d = trajectory.dimension,
                    vectors = wave.index.size();
  const DisplacementMoments moments = displacement_moments(trajectory);
  // cos(k . (r2 - r1)) = cos(k . r2) cos(k . r1) + sin(k . r2) sin(k . r1): per block of
  // particles, each frame's exp(-i k . r) of every particle and k-vector as one row (real parts,
  // then imaginary), so that a lag and origin cost a dot product of two rows instead of a cosine
  // each. A block is as many particles as keep the rows of every frame within 32 MB; the dot
  // products run over pieces of the rows short enough that every frame's piece stays in a
  // core's cache (1 MB) while the lags and origins go over it.
  const std::size_t block = std::max<std::size_t>(1, (std::size_t{1} << 21) / (count * vectors));
  const std::size_t piece = padded(std::max<std::size_t>(1, (std::size_t{1} << 17) / count));
  std::vector<double> rows, correlation(moments.lags.size(), 0.0);
  for (std::size_t begin = 0; begin < n; begin += block) {
    const std::size_t size = std::min(block, n - begin), width = padded(2 * size * vectors);
    PhaseTables tables(d, first.box, reach_of(wave.index), size);
    rows.assign(count * width, 0.0);  // the padding: zeros, which add nothing
    for (std::size_t f = 0; f < count; ++f) {
      const double* x = trajectory.frame(f);
      tables.fill(size, [&](std::size_t i, std::size_t k) { return x[(begin + i) * d + k]; });
      double* row = &rows[f * width];
      tables.phases(wave.index, 0, vectors, row, row + size * vectors);
    }
    for (std::size_t from = 0; from < width; from += piece) {
      const std::size_t length = std::min(piece, width - from);
      for (std::size_t l = 0; l < moments.lags.size(); ++l) {
        const std::size_t lag = moments.lags[l];
        for (std::size_t f = 0; f + lag < count; ++f) {
          const double* before = &rows[f * width + from];
          const double* after = &rows[(f + lag) * width + from];
          correlation[l] += sum_of(length, [&](std::size_t c) { return before[c] * after[c]; });
        }
      }
    }
  }
  SelfScattering out;
  out.k = wave.k;
  out.t = moments.t;
  const auto dimension = static_cast<double>(d);
  for (std::size_t l = 0; l < moments.lags.size(); ++l) {
    const double samples = static_cast<double>((count - moments.lags[l]) * n * vectors);
    out.fs.push_back(correlation[l] / samples);
    const double r2 = moments.r2[l];
    out.alpha2.push_back(r2 > 0.0 ? dimension * moments.r4[l] / ((dimension + 2.0) * r2 * r2) - 1.0
                                  : std::numeric_limits<double>::quiet_NaN());
  }
  out.tau_alpha = relaxation_time(out.t, out.fs);
  return out;
}

std::optional<double> relaxation_time(const std::vector<double>& t, const std::vector<double>& f) {
  const double level = std::exp(-1.0);
  for (std::size_t l = 0; l < f.size(); ++l) {
    if (f[l] >= level) continue;
    if (l == 0) return t[0];
    return t[l - 1] + (level - f[l - 1]) * (t[l] - t[l - 1]) / (f[l] - f[l - 1]);
  }
  return std::nullopt;
}

}  // namespace carom
