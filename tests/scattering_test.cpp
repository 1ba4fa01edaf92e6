#include "carom/analysis/scattering.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace carom {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// A periodic frame of `dimension` sides `box` with no particle yet.
Frame empty_frame(int dimension, Vec<3> box, double time = 0.0) {
  Frame f;
  f.dimension = dimension;
  f.box = box;
  f.periodic = true;
  f.time = time;
  return f;
}

void add_particle(Frame& f, const Vec<3>& x, std::array<std::int32_t, 3> image = {}) {
  f.position.push_back(x);
  f.velocity.push_back({});
  f.radius.push_back(0.5);
  f.collisions.push_back(0);
  f.image.push_back(image);
}

// A square (2D) or simple cubic (3D) lattice of `per_side` particles a side filling a cube of
// side `side`, shifted off the origin so that the phases are not trivially 1.
Frame lattice(int dimension, int per_side, double side) {
  Frame f = empty_frame(dimension, {{side, side, dimension == 3 ? side : 1.0}});
  const double a = side / per_side;
  const int layers = dimension == 3 ? per_side : 1;
  for (int i = 0; i < per_side; ++i) {
    for (int j = 0; j < per_side; ++j) {
      for (int l = 0; l < layers; ++l) {
        add_particle(f, {{a * (i + 0.3), a * (j + 0.6), dimension == 3 ? a * (l + 0.1) : 0.0}});
      }
    }
  }
  return f;
}

// `n` points uniformly in a periodic box: an ideal gas.
Frame ideal_gas(int dimension, std::size_t n, Vec<3> box, std::mt19937_64& random) {
  Frame f = empty_frame(dimension, box);
  for (std::size_t i = 0; i < n; ++i) {
    Vec<3> x{};
    for (std::size_t k = 0; k < static_cast<std::size_t>(dimension); ++k) {
      x[k] = std::uniform_real_distribution<double>(0.0, box[k])(random);
    }
    add_particle(f, x);
  }
  return f;
}

// Every n of the grid with |n_k| <= reach, one of each n, -n (the first nonzero n_k positive).
std::vector<std::array<int, 3>> grid_up_to(int dimension, int reach) {
  std::vector<std::array<int, 3>> index;
  const int z = dimension == 3 ? reach : 0;
  for (int x = 0; x <= reach; ++x) {
    for (int y = -reach; y <= reach; ++y) {
      for (int w = -z; w <= z; ++w) {
        if (x > 0 || y > 0 || (y == 0 && w > 0)) index.push_back({x, y, w});
      }
    }
  }
  return index;
}

TEST(Scattering, LatticeIsNAtItsBraggPeaksAndZeroAtEveryOtherK) {
  for (const int dimension : {2, 3}) {
    const int per_side = dimension == 2 ? 8 : 3;
    const Frame crystal = lattice(dimension, per_side, 7.3);
    const auto n = static_cast<double>(crystal.position.size());
    const std::vector<std::array<int, 3>> index = grid_up_to(dimension, 2 * per_side + 1);
    const std::vector<double> s = structure_factor_at(crystal, index);
    std::size_t peaks = 0;
    for (std::size_t q = 0; q < index.size(); ++q) {
      const bool bragg =
          std::all_of(index[q].begin(), index[q].end(), [&](int c) { return c % per_side == 0; });
      peaks += bragg ? 1 : 0;
      if (bragg) {
        EXPECT_NEAR(s[q], n, 1e-10 * n) << index[q][0] << " " << index[q][1] << " " << index[q][2];
      } else {
        EXPECT_LT(s[q], 1e-20) << index[q][0] << " " << index[q][1] << " " << index[q][2];
      }
    }
    EXPECT_EQ(peaks, dimension == 2 ? 12u : 62u);  // (2 * 2 + 1)^D - 1 peaks, halved
    // A shell's S is N times the share of Bragg peaks among the k-vectors it keeps.
    const StructureFactor sk = structure_factor({crystal}, 20.0);
    const std::vector<WaveShell> shells = wave_shells(dimension, crystal.box, sk.k.size());
    std::size_t highest = 0;
    std::vector<double> expected;
    for (const WaveShell& shell : shells) {
      const auto bragg = std::count_if(shell.index.begin(), shell.index.end(), [&](const auto& m) {
        return std::all_of(m.begin(), m.end(), [&](int c) { return c % per_side == 0; });
      });
      expected.push_back(n * static_cast<double>(bragg) / static_cast<double>(shell.index.size()));
      if (expected.back() > expected[highest]) highest = expected.size() - 1;
    }
    ASSERT_EQ(sk.s.size(), expected.size());
    for (std::size_t m = 0; m < expected.size(); ++m) {
      EXPECT_NEAR(sk.s[m], expected[m], 1e-10 * n) << "shell " << m + 1;
    }
    EXPECT_GT(expected[highest], 1.0);
    EXPECT_DOUBLE_EQ(sk.k_peak, shells[highest].k);
  }
}

// A long trajectory's S(k) is its evenly spread kStructureFactorFrames frames' (j F / 20 of F):
// here the crystal frames at even places, never the gas between them.
TEST(Scattering, ALongTrajectorysStructureIsTakenOnEvenlySpreadFrames) {
  std::mt19937_64 random(5);
  const Frame crystal = lattice(2, 8, 7.3);
  std::vector<Frame> frames;
  for (std::size_t f = 0; f < 2 * kStructureFactorFrames; ++f) {
    frames.push_back(f % 2 == 0 ? crystal
                                : ideal_gas(2, crystal.position.size(), crystal.box, random));
  }
  const StructureFactor all = structure_factor(frames, 20.0);
  const StructureFactor one = structure_factor({crystal}, 20.0);
  ASSERT_EQ(all.s.size(), one.s.size());
  for (std::size_t m = 0; m < one.s.size(); ++m) EXPECT_NEAR(all.s[m], one.s[m], 1e-9) << m;
}

TEST(Scattering, IdealGasIsNearOneInEveryShell) {
  std::mt19937_64 random(12);
  for (const int dimension : {2, 3}) {
    const Vec<3> box{{9.0, 11.0, dimension == 3 ? 10.0 : 1.0}};
    std::vector<Frame> frames;
    for (int f = 0; f < 20; ++f) frames.push_back(ideal_gas(dimension, 500, box, random));
    const StructureFactor sk = structure_factor(frames, 8.0);
    const std::vector<WaveShell> shells = wave_shells(dimension, box, sk.k.size());
    double sum = 0.0, all_samples = 0.0;
    for (std::size_t m = 0; m < sk.s.size(); ++m) {
      // Each k-vector and frame gives an exponential variable of mean 1: the shell's mean has
      // a standard deviation of 1 / sqrt(its samples).
      const double samples = static_cast<double>(shells[m].index.size() * frames.size());
      EXPECT_NEAR(sk.s[m], 1.0, 5.0 / std::sqrt(samples)) << "shell " << m + 1;
      EXPECT_DOUBLE_EQ(sk.k[m], shells[m].k);
      sum += sk.s[m] * samples;
      all_samples += samples;
    }
    EXPECT_NEAR(sum / all_samples, 1.0, 5.0 / std::sqrt(all_samples)) << dimension;
  }
}

TEST(Scattering, ShellsHoldTheGridsVectorsOfTheirWaveNumberAtMostAHundredEvenlyChosen) {
  const Vec<3> box{{6.0, 8.3, 1.0}};
  const std::vector<WaveShell> shells = wave_shells(2, box, 60);
  const double step = kTwoPi / 6.0;
  const std::vector<std::array<int, 3>> all = grid_up_to(2, 100);
  for (std::size_t m = 1; m <= shells.size(); ++m) {
    std::vector<std::array<int, 3>> members;  // lexicographic, as all is
    for (const std::array<int, 3>& n : all) {
      const double k = kTwoPi * std::hypot(n[0] / box[0], n[1] / box[1]);
      if (k >= (m - 0.5) * step && k < (m + 0.5) * step) members.push_back(n);
    }
    const WaveShell& shell = shells[m - 1];
    ASSERT_FALSE(members.empty());
    if (members.size() <= kWaveVectorsPerShell) {
      EXPECT_EQ(shell.index, members) << "shell " << m;
    } else {
      ASSERT_EQ(shell.index.size(), kWaveVectorsPerShell) << "shell " << m;
      for (std::size_t j = 0; j < kWaveVectorsPerShell; ++j) {
        EXPECT_EQ(shell.index[j], members[j * members.size() / kWaveVectorsPerShell]);
      }
    }
    double k = 0.0;
    for (const std::array<int, 3>& n : shell.index) {
      k += kTwoPi * std::hypot(n[0] / box[0], n[1] / box[1]);
    }
    EXPECT_NEAR(shell.k, k / static_cast<double>(shell.index.size()), 1e-12) << "shell " << m;
  }
  EXPECT_EQ(shells.back().index.size(), kWaveVectorsPerShell);  // the cap is reached
}

// Frames 0.5 apart of a gas moved rigidly by `a` a frame, wrapped into the box with image flags.
std::vector<Frame> translated_gas(int dimension, const Vec<3>& a, int count) {
  std::mt19937_64 random(3);
  const Vec<3> box{{7.0, 7.5, dimension == 3 ? 8.0 : 1.0}};
  const Frame start = ideal_gas(dimension, 40, box, random);
  std::vector<Frame> frames;
  for (int f = 0; f < count; ++f) {
    Frame frame = empty_frame(dimension, box, 0.5 * f);
    for (const Vec<3>& x0 : start.position) {
      Vec<3> x = x0 + static_cast<double>(f) * a;
      std::array<std::int32_t, 3> image{};
      for (std::size_t k = 0; k < static_cast<std::size_t>(dimension); ++k) {
        image[k] = static_cast<std::int32_t>(std::floor(x[k] / box[k]));
        x[k] -= image[k] * box[k];
      }
      add_particle(frame, x, image);
    }
    frames.push_back(frame);
  }
  return frames;
}

TEST(Scattering, RigidTranslationGivesTheShellMeanOfCosKDotA) {
  for (const int dimension : {2, 3}) {
    const Vec<3> a{{0.37, -0.81, dimension == 3 ? 1.3 : 0.0}};
    const std::vector<Frame> frames = translated_gas(dimension, a, 12);
    const SelfScattering fs = self_scattering(frames, 5.0);
    const double step = kTwoPi / 7.0;
    const WaveShell shell =
        wave_shells(dimension, frames[0].box, static_cast<std::size_t>(std::round(5.0 / step)))
            .back();
    EXPECT_DOUBLE_EQ(fs.k, shell.k);
    ASSERT_EQ(fs.t.size(), 12u);
    for (std::size_t lag = 0; lag < fs.t.size(); ++lag) {
      double expected = 0.0;
      for (const std::array<int, 3>& n : shell.index) {
        double phase = 0.0;
        for (std::size_t k = 0; k < static_cast<std::size_t>(dimension); ++k) {
          phase += kTwoPi * n[k] / frames[0].box[k] * a[k] * static_cast<double>(lag);
        }
        expected += std::cos(phase) / static_cast<double>(shell.index.size());
      }
      EXPECT_DOUBLE_EQ(fs.t[lag], 0.5 * static_cast<double>(lag));
      EXPECT_NEAR(fs.fs[lag], expected, 1e-12) << "lag " << lag;
      // Every displacement of one length: <dr^4> = <dr^2>^2, alpha2 = D / (D + 2) - 1.
      if (lag > 0) {
        EXPECT_NEAR(fs.alpha2[lag], -2.0 / (dimension + 2.0), 1e-12);
      }
    }
    EXPECT_NEAR(fs.fs[0], 1.0, 1e-14);
    EXPECT_TRUE(std::isnan(fs.alpha2[0]));  // no particle has moved yet
  }
}

TEST(Scattering, NonGaussianParameterOfAFewDisplacementsByHand) {
  // Displacements of lengths 1, 1, 1 and 3: <dr^2> = 12 / 4 = 3, <dr^4> = 84 / 4 = 21, so
  // alpha2 = 2 21 / (4 9) - 1 = 1/6 in 2D and 3 21 / (5 9) - 1 = 2/5 in 3D.
  for (const int dimension : {2, 3}) {
    const Vec<3> box{{10.0, 10.0, dimension == 3 ? 10.0 : 1.0}};
    Frame before = empty_frame(dimension, box, 0.0), after = empty_frame(dimension, box, 1.0);
    const std::vector<Vec<3>> from = {{{1, 1, 1}}, {{5, 5, 5}}, {{8, 2, 3}}, {{2, 5, 5}}};
    const std::vector<Vec<3>> step = {{{1, 0, 0}}, {{0, -1, 0}}, {{0.6, 0.8, 0}}, {{0, 0, 3}}};
    for (std::size_t i = 0; i < from.size(); ++i) {
      Vec<3> moved = step[i];
      if (dimension == 2) moved = {{moved[0], moved[1] + moved[2], 0.0}};  // the 3 along y
      add_particle(before, {{from[i][0], from[i][1], dimension == 3 ? from[i][2] : 0.0}});
      add_particle(after, {{from[i][0] + moved[0], from[i][1] + moved[1],
                            dimension == 3 ? from[i][2] + moved[2] : 0.0}});
    }
    const SelfScattering fs = self_scattering({before, after}, 3.0);
    ASSERT_EQ(fs.alpha2.size(), 2u);
    EXPECT_NEAR(fs.alpha2[1], dimension == 2 ? 1.0 / 6.0 : 0.4, 1e-12);
  }
}

TEST(Scattering, RelaxationTimeIsInterpolatedWhereFirstBelowOneOverE) {
  const double level = std::exp(-1.0);
  const std::optional<double> tau = relaxation_time({0, 1, 2, 3, 4}, {1, 0.5, 0.3, 0.5, 0.1});
  ASSERT_TRUE(tau);
  EXPECT_NEAR(*tau, 1.0 + (0.5 - level) / 0.2, 1e-14);
  EXPECT_FALSE(relaxation_time({0, 1, 2}, {1.0, 0.6, 0.4}));
  // A slow drift: F_s stays near 1, so there is no tau_alpha.
  const std::vector<Frame> frames = translated_gas(2, {{0.05, 0.02, 0}}, 3);
  EXPECT_FALSE(self_scattering(frames, 1.0).tau_alpha);
}

TEST(Scattering, RefusesWhatTheBoxCannotHave) {
  std::mt19937_64 random(5);
  Frame walled = ideal_gas(2, 20, {{5.0, 5.0, 1.0}}, random);
  walled.periodic = false;
  EXPECT_THROW(structure_factor({walled}, 10.0), std::invalid_argument);
  const Frame gas = ideal_gas(2, 20, {{5.0, 5.0, 1.0}}, random);
  EXPECT_THROW(structure_factor({gas}, 1.0), std::invalid_argument);  // below 2 pi / 5
  EXPECT_THROW(self_scattering({gas}, 0.5), std::invalid_argument);   // below pi / 5
  EXPECT_THROW(structure_factor({gas}, 1e6), std::invalid_argument);  // 10^12 grid points
  Frame no_images = gas;
  no_images.image.clear();
  no_images.time = 1.0;
  EXPECT_THROW(self_scattering({gas, no_images}, 3.0), std::invalid_argument);
}

}  // namespace
}  // namespace carom
