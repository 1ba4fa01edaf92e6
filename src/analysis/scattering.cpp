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

// The particles whose phases are held at once: small enough that the tables of exp(-i k x) stay
// in a core's cache, and that their size does not grow with N.
constexpr std::size_t kParticleBlock = 256;

// The sums below run in this many independent partial sums over rows padded with zeros to a
// multiple of it: a single running sum waits for each addition before the next (the compiler
// may not reorder floating-point sums), which made S(k) and F_s four times slower.
constexpr std::size_t kLanes = 8;

std::size_t padded(std::size_t size) { return (size + kLanes - 1) / kLanes * kLanes; }

double sum_of(const std::array<double, kLanes>& lanes) {
  double sum = 0.0;
  for (const double lane : lanes) sum += lane;
  return sum;
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
  const std::size_t n = frame.position.size();
  std::array<int, 3> reach{};
  for (const std::array<int, 3>& m : index) {
    for (std::size_t k = 0; k < d; ++k) reach[k] = std::max(reach[k], std::abs(m[k]));
  }
  // exp(-i k . r) = prod_k exp(-2 pi i n_k x_k / L_k): per block of particles, a table of each
  // factor for every n_k in [-reach, reach] (real and imaginary parts apart, so that the sums
  // below vectorise), then a product of D table entries a particle and k-vector, not a sine.
  // A row of a table holds a block's particles padded with zeros (which add nothing).
  std::array<std::vector<double>, 3> re, im;
  std::vector<double> sum_re(index.size(), 0.0), sum_im(index.size(), 0.0);
  for (std::size_t first = 0; first < n; first += kParticleBlock) {
    const std::size_t size = std::min(kParticleBlock, n - first), width = padded(size);
    for (std::size_t k = 0; k < d; ++k) {
      const std::size_t rows = 2 * static_cast<std::size_t>(reach[k]) + 1;
      re[k].assign(rows * width, 0.0);
      im[k].assign(rows * width, 0.0);
      for (std::size_t row = 0; row < rows; ++row) {
        const double wave = kTwoPi * (static_cast<double>(row) - reach[k]) / frame.box[k];
        for (std::size_t i = 0; i < size; ++i) {
          const double phase = -wave * frame.position[first + i][k];
          re[k][row * width + i] = std::cos(phase);
          im[k][row * width + i] = std::sin(phase);
        }
      }
    }
    for (std::size_t q = 0; q < index.size(); ++q) {
      std::array<const double*, 3> a_re{}, a_im{};
      for (std::size_t k = 0; k < d; ++k) {
        const auto row = static_cast<std::size_t>(index[q][k] + reach[k]);
        a_re[k] = &re[k][row * width];
        a_im[k] = &im[k][row * width];
      }
      std::array<double, kLanes> s_re{}, s_im{};
      for (std::size_t i = 0; i < width; i += kLanes) {
        for (std::size_t l = 0; l < kLanes; ++l) {
          const std::size_t j = i + l;
          double z_re = a_re[0][j] * a_re[1][j] - a_im[0][j] * a_im[1][j];
          double z_im = a_re[0][j] * a_im[1][j] + a_im[0][j] * a_re[1][j];
          if (d == 3) {
            const double xy_re = z_re;
            z_re = xy_re * a_re[2][j] - z_im * a_im[2][j];
            z_im = xy_re * a_im[2][j] + z_im * a_re[2][j];
          }
          s_re[l] += z_re;
          s_im[l] += z_im;
        }
      }
      sum_re[q] += sum_of(s_re);
      sum_im[q] += sum_of(s_im);
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
  for (const WaveShell& shell : grid) index.insert(index.end(), shell.index.begin(), shell.index.end());
  std::vector<double> total(index.size(), 0.0);
  for (const Frame& frame : frames) {
    const std::vector<double> s = structure_factor_at(frame, index);
    for (std::size_t q = 0; q < index.size(); ++q) total[q] += s[q];
  }
  StructureFactor out;
  std::size_t q = 0;
  for (const WaveShell& shell : grid) {
    double sum = 0.0;
    for (std::size_t v = 0; v < shell.index.size(); ++v) sum += total[q++];
    out.k.push_back(shell.k);
    out.s.push_back(sum / static_cast<double>(shell.index.size() * frames.size()));
  }
  out.k_peak = out.k[static_cast<std::size_t>(std::max_element(out.s.begin(), out.s.end()) -
                                              out.s.begin())];
  return out;
}

SelfScattering self_scattering(const std::vector<Frame>& frames, double k) {
  const UnwrappedTrajectory trajectory = unwrap(frames, "F_s(k,t)");
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
  const std::size_t count = trajectory.frames, n = trajectory.particles,
                    d = trajectory.dimension, vectors = wave.index.size();
  std::vector<std::array<double, 3>> wave_vector(vectors);
  for (std::size_t q = 0; q < vectors; ++q) {
    for (std::size_t c = 0; c < d; ++c) wave_vector[q][c] = kTwoPi * wave.index[q][c] / first.box[c];
  }
  const DisplacementMoments moments = displacement_moments(trajectory);
  // cos(k . (r2 - r1)) = cos(k . r2) cos(k . r1) + sin(k . r2) sin(k . r1): per block of
  // particles, each frame's (cos, sin) of every particle and k-vector as one row, so that a
  // lag and origin cost a dot product of two rows instead of a cosine each. The block is as
  // many particles as keep the rows of every frame within 32 MB.
  const std::size_t block = std::max<std::size_t>(1, (std::size_t{1} << 22) / (count * vectors * 2));
  std::vector<double> rows, correlation(moments.lags.size(), 0.0);
  for (std::size_t begin = 0; begin < n; begin += block) {
    const std::size_t size = std::min(block, n - begin), width = padded(2 * size * vectors);
    rows.assign(count * width, 0.0);  // the padding: zeros, which add nothing
    for (std::size_t f = 0; f < count; ++f) {
      const double* x = trajectory.frame(f);
      for (std::size_t i = 0; i < size; ++i) {
        for (std::size_t q = 0; q < vectors; ++q) {
          double phase = 0.0;
          for (std::size_t c = 0; c < d; ++c) phase += wave_vector[q][c] * x[(begin + i) * d + c];
          rows[f * width + 2 * (i * vectors + q)] = std::cos(phase);
          rows[f * width + 2 * (i * vectors + q) + 1] = std::sin(phase);
        }
      }
    }
    for (std::size_t l = 0; l < moments.lags.size(); ++l) {
      const std::size_t lag = moments.lags[l];
      std::array<double, kLanes> sum{};
      for (std::size_t f = 0; f + lag < count; ++f) {
        const double* from = &rows[f * width];
        const double* to = &rows[(f + lag) * width];
        for (std::size_t c = 0; c < width; c += kLanes) {
          for (std::size_t j = 0; j < kLanes; ++j) sum[j] += from[c + j] * to[c + j];
        }
      }
      correlation[l] += sum_of(sum);
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
