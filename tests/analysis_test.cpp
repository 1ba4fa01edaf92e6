#include "carom/analysis/analysis.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

#include "carom/analysis/analysis_spec.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/gsd.hpp"
#include "carom/io/trajectory.hpp"

namespace carom {
namespace {

constexpr double kPi = std::numbers::pi;

// `n` points uniformly in the box (overlapping: an ideal gas), radius 0.5, between walls kept a
// radius from them.
Frame ideal_gas(int dimension, std::size_t n, Vec<3> box, bool periodic, std::uint32_t seed) {
  std::mt19937_64 random(seed);
  Frame f;
  f.dimension = dimension;
  f.box = box;
  f.periodic = periodic;
  const double margin = periodic ? 0.0 : 0.5;
  for (std::size_t i = 0; i < n; ++i) {
    Vec<3> x{};
    for (int k = 0; k < dimension; ++k) {
      const auto side = static_cast<std::size_t>(k);
      x[side] = std::uniform_real_distribution<double>(margin, box[side] - margin)(random);
    }
    f.position.push_back(x);
    f.velocity.push_back({});
    f.radius.push_back(0.5);
    f.collisions.push_back(0);
  }
  return f;
}

// A clustering gas: `n` points in a patch of side `patch` (a dense cluster) of a huge box, the
// patch straddling the periodic boundary (a corner, between walls), and a few stragglers far away.
Frame clustered(int dimension, std::size_t n, double patch, bool periodic, std::uint32_t seed) {
  const double side = 1e5;
  Vec<3> cluster_box{{patch, patch, dimension == 3 ? patch : 1.0}};
  Frame f = ideal_gas(dimension, n, cluster_box, false, seed);
  f.box = {{side, side, dimension == 3 ? side : 1.0}};
  f.periodic = periodic;
  for (Vec<3>& x : f.position) {
    for (int k = 0; k < dimension; ++k) {
      double& c = x[static_cast<std::size_t>(k)];
      c = periodic ? std::fmod(c - patch / 2.0 + side, side) : c + 1.0;
    }
  }
  for (std::size_t i = 0; i < 8; ++i) {
    for (int k = 0; k < dimension; ++k) {
      f.position[i * 7][static_cast<std::size_t>(k)] =
          side / 3.0 + 1e3 * static_cast<double>(i + k);
    }
  }
  return f;
}

// A triangular lattice of spacing a, rows of `columns` disks, filling a periodic box exactly
// (rows even), or rotated by `angle`.
Frame triangular_lattice(std::size_t columns, std::size_t rows, double a, double angle) {
  Frame f;
  f.periodic = true;
  f.box = {{a * static_cast<double>(columns), a * std::sqrt(3.0) / 2.0 * static_cast<double>(rows),
            1.0}};
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns; ++c) {
      const double x = a * (static_cast<double>(c) + 0.5 * static_cast<double>(r % 2));
      const double y = a * std::sqrt(3.0) / 2.0 * static_cast<double>(r);
      f.position.push_back({{x, y, 0.0}});
      f.velocity.push_back({});
      f.radius.push_back(0.4 * a);
      f.collisions.push_back(0);
    }
  }
  if (angle != 0.0) {  // about the origin: the lattice no longer tiles the box
    for (Vec<3>& x : f.position) {
      const double u = x[0], v = x[1];
      x = {{std::cos(angle) * u - std::sin(angle) * v, std::sin(angle) * u + std::cos(angle) * v,
            0}};
    }
  }
  return f;
}

// The pair histogram by brute force: every pair, minimum image.
std::vector<double> brute_force_histogram(const Frame& f, double bin, std::size_t bins) {
  std::vector<double> histogram(bins, 0.0);
  for (std::size_t i = 0; i < f.position.size(); ++i) {
    for (std::size_t j = i + 1; j < f.position.size(); ++j) {
      double r2 = 0.0;
      for (std::size_t k = 0; k < static_cast<std::size_t>(f.dimension); ++k) {
        double dx = f.position[j][k] - f.position[i][k];
        if (f.periodic) dx -= f.box[k] * std::nearbyint(dx / f.box[k]);
        r2 += dx * dx;
      }
      const auto b = static_cast<std::size_t>(std::sqrt(r2) / bin);
      if (std::sqrt(r2) < bin * static_cast<double>(bins) && b < bins) histogram[b] += 1.0;
    }
  }
  return histogram;
}

double ball(int dimension, double r) {
  return dimension == 2 ? kPi * r * r : 4.0 / 3.0 * kPi * r * r * r;
}

// g(r) by brute force: every pair counted (minimum image), normalised independently by an ideal
// pair's chance of a separation in the shell.
std::vector<double> brute_force_rdf(const Frame& f, double bin, std::size_t bins) {
  const std::vector<double> count = brute_force_histogram(f, bin, bins);
  std::vector<double> window;
  for (int k = 0; k < f.dimension; ++k) {
    window.push_back(f.box[static_cast<std::size_t>(k)] - (f.periodic ? 0.0 : 1.0));
  }
  double volume = 1.0;
  for (const double side : window) volume *= side;
  const auto n = static_cast<double>(f.position.size());
  std::vector<double> g(bins);
  for (std::size_t b = 0; b < bins; ++b) {
    const double lo = bin * static_cast<double>(b), r = lo + 0.5 * bin;
    const double shell = ball(f.dimension, lo + bin) - ball(f.dimension, lo);
    double covariance = volume;
    if (!f.periodic && f.dimension == 2) {
      covariance = window[0] * window[1] - 2 * r * (window[0] + window[1]) / kPi + r * r / kPi;
    } else if (!f.periodic) {
      const double a = window[0], w = window[1], h = window[2];
      covariance = a * w * h - r * (a * w + a * h + w * h) / 2 +
                   2 * r * r * (a + w + h) / (3 * kPi) - r * r * r / (4 * kPi);
    }
    g[b] = count[b] / (n * (n - 1) / 2 * shell * covariance / (volume * volume));
  }
  return g;
}

// Every disk's local psi6 by brute force: its six nearest by distance, then index.
std::vector<std::complex<double>> brute_force_psi6(const Frame& f) {
  std::vector<std::complex<double>> psi;
  for (std::size_t i = 0; i < f.position.size(); ++i) {
    std::vector<std::pair<double, std::size_t>> all;
    std::vector<Vec<2>> bonds(f.position.size());
    for (std::size_t j = 0; j < f.position.size(); ++j) {
      if (j == i) continue;
      Vec<2> b;
      for (std::size_t k = 0; k < 2; ++k) {
        double dx = f.position[j][k] - f.position[i][k];
        if (f.periodic) dx -= f.box[k] * std::nearbyint(dx / f.box[k]);
        b[k] = dx;
      }
      bonds[j] = b;
      all.emplace_back(norm2(b), j);
    }
    std::sort(all.begin(), all.end());
    std::complex<double> sum = 0.0;
    for (std::size_t m = 0; m < 6; ++m) {
      const Vec<2>& b = bonds[all[m].second];
      sum += std::polar(1.0, 6.0 * std::atan2(b[1], b[0]));
    }
    psi.push_back(sum / 6.0);
  }
  return psi;
}

TEST(Rdf, TheNeighbourSearchCountsEveryPairOnceAsBruteForceDoes) {
  // Boxes of many cells, of fewer than three a side (cells wrap onto themselves), thin slabs,
  // walls, disks and spheres.
  struct Case {
    int dimension;
    Vec<3> box;
    bool periodic;
    std::size_t n;
    double r_max;
  };
  const std::vector<Case> cases = {
      {2, {{20, 20, 1}}, true, 400, 3.0}, {2, {{5, 5, 1}}, true, 60, 2.5},
      {2, {{40, 4, 1}}, true, 200, 2.0},  {2, {{12, 9, 1}}, false, 150, 4.0},
      {3, {{8, 8, 8}}, true, 300, 2.5},   {3, {{5, 6, 7}}, true, 200, 2.5},
      {3, {{30, 30, 3}}, true, 300, 1.5}, {3, {{9, 9, 9}}, false, 200, 3.0}};
  for (const Case& c : cases) {
    const Frame f = ideal_gas(c.dimension, c.n, c.box, c.periodic, 7);
    const double bin = 0.05;
    const Rdf rdf = radial_distribution({f}, {bin, c.r_max});
    ASSERT_EQ(rdf.r.size(), static_cast<std::size_t>(std::llround(c.r_max / bin)));
    const std::vector<double> expected = brute_force_rdf(f, bin, rdf.r.size());
    for (std::size_t b = 0; b < rdf.r.size(); ++b) {
      EXPECT_NEAR(rdf.g[b], expected[b], 1e-12 * expected[b]) << "box " << c.box[0] << " bin " << b;
    }
  }
}

TEST(Rdf, ClusteredFramesCountEveryPairAsBruteForceDoes) {
  // Cells sized from the mean density put a cluster in one cell (a regression: O(N^2), a minute
  // for 20,000 disks); the k-d tree does not care how the particles are spread.
  for (const int dimension : {2, 3}) {
    for (const bool periodic : {true, false}) {
      const Frame f = clustered(dimension, 1500, dimension == 2 ? 30.0 : 9.0, periodic, 5);
      const double bin = 0.05;
      const Rdf rdf = radial_distribution({f}, {bin, 3.0});
      double pairs = 0.0;
      for (double c : brute_force_histogram(f, bin, rdf.r.size())) pairs += c;
      EXPECT_GT(pairs, 1000.0);
      const std::vector<double> expected = brute_force_rdf(f, bin, rdf.r.size());
      for (std::size_t b = 0; b < rdf.r.size(); ++b) {
        EXPECT_NEAR(rdf.g[b], expected[b], 1e-12 * expected[b])
            << dimension << (periodic ? "D periodic" : "D walls") << " bin " << b;
      }
    }
  }
}

TEST(Analyze, AClusterOfAHundredThousandDisksTakesWhatAUniformFluidDoes) {
  // 25 minutes with cells sized from the mean density; a second now (the test's timeout is the
  // guard: performance lives in benchmarks).
  const Frame f = clustered(2, 100000, 300.0, true, 9);
  const Rdf rdf = radial_distribution({f}, {0.05, 3.0});
  EXPECT_GT(rdf.g[rdf.g.size() / 2], 0.0);
  EXPECT_EQ(local_psi6(f).size(), f.position.size());
}

// A selection of analyses: names as the JSON's, spaces around them let be; an unknown or empty
// name, or one named twice, refused; F_s without what it is taken from, or an option of an
// analysis left out, refused; what it leaves out is not computed, and an order parameter of the
// other dimension named is said to be absent.
TEST(Analyze, ComputesTheAnalysesASelectionNames) {
  AnalysisSelection psi6_and_rdf = parse_analysis_selection("psi6, rdf");
  EXPECT_TRUE(psi6_and_rdf.psi6 && psi6_and_rdf.rdf);
  EXPECT_FALSE(psi6_and_rdf.msd || psi6_and_rdf.steinhardt || psi6_and_rdf.structure_factor ||
               psi6_and_rdf.self_scattering);
  EXPECT_EQ(analysis_names(psi6_and_rdf), (std::vector<std::string>{"rdf", "psi6"}));
  EXPECT_EQ(analysis_names(AnalysisSelection{}).size(), 6u);
  for (const char* bad : {"", "psi6,", "S(k)", "psi6,psi6"}) {
    EXPECT_THROW(parse_analysis_selection(bad), std::invalid_argument) << bad;
  }
  AnalysisOptions options;
  options.only = parse_analysis_selection("self_scattering,msd");
  EXPECT_THROW(check_selection(options), std::invalid_argument);  // no peak to take k from
  options.fs_k = 6.0;
  EXPECT_NO_THROW(check_selection(options));
  options.only = parse_analysis_selection("psi6");
  EXPECT_THROW(check_selection(options), std::invalid_argument);  // fs_k would do nothing
  options = {};
  options.only = psi6_and_rdf;
  const Frame f = clustered(2, 400, 30.0, true, 3);
  const Analysis some = analyze({f, f}, "two.gsd", options);
  EXPECT_TRUE(some.rdf && some.psi6);
  EXPECT_FALSE(some.msd || some.structure_factor || some.self_scattering || some.steinhardt);
  EXPECT_EQ(some.only, analysis_names(psi6_and_rdf));
  options.only = parse_analysis_selection("steinhardt");
  const Analysis none = analyze({f}, "one.gsd", options);
  EXPECT_FALSE(none.rdf || none.psi6 || none.steinhardt);
  ASSERT_EQ(none.warnings.size(), 1u);
  EXPECT_EQ(none.warnings[0].rfind("no steinhardt: ", 0), 0u) << none.warnings[0];
  EXPECT_FALSE(analyze({f}, "one.gsd").only);  // every analysis: no selection to report
}

TEST(Rdf, AnIdealGasIsUncorrelatedInAPeriodicBoxAndBetweenWalls) {
  // g = 1 everywhere for points placed independently: between walls only if the normalisation
  // counts the pairs the walls cut off (without it g falls by 2 r (a + b) / (pi a b): 30 % at r =
  // 4).
  for (const bool periodic : {true, false}) {
    std::vector<Frame> frames;
    for (std::uint32_t seed = 1; seed <= 40; ++seed) {
      frames.push_back(ideal_gas(2, 500, {{20, 16, 1}}, periodic, seed));
    }
    const Rdf rdf = radial_distribution(frames, {0.5, 5.0});
    for (std::size_t b = 1; b < rdf.r.size(); ++b) {
      EXPECT_NEAR(rdf.g[b], 1.0, 0.05) << (periodic ? "periodic" : "walls") << " r " << rdf.r[b];
    }
  }
}

TEST(Rdf, ContactIsABinEdgeByDefault) {
  const Frame f = ideal_gas(2, 100, {{10, 10, 1}}, true, 3);
  const Rdf rdf = radial_distribution({f});
  EXPECT_DOUBLE_EQ(rdf.bin_width, 1.0 / 50.0);
  EXPECT_DOUBLE_EQ(rdf.r_max, 5.0);  // 5 d, half the box
  EXPECT_EQ(rdf.r.size(), 250u);
  EXPECT_NEAR(rdf.r[50] - 0.5 * rdf.bin_width, 1.0, 1e-12);
  const Frame small = ideal_gas(2, 100, {{6, 8, 1}}, true, 3);
  EXPECT_DOUBLE_EQ(radial_distribution({small}).r_max, 3.0);  // half the smallest side
}

TEST(Rdf, PeriodicPositionsOutsideTheBoxCountAsTheirImages) {
  // A centred box (HOOMD's), or unwrapped coordinates: the same pairs as in [0, L).
  Frame f = ideal_gas(2, 400, {{20, 20, 1}}, true, 9), shifted = f;
  for (std::size_t i = 0; i < f.position.size(); ++i) {
    shifted.position[i][0] -= 10.0 + 20.0 * static_cast<double>(i % 3);
    shifted.position[i][1] += 20.0 * static_cast<double>(i % 5);
  }
  const Rdf a = radial_distribution({f}, {0.1, 5.0}),
            b = radial_distribution({shifted}, {0.1, 5.0});
  for (std::size_t bin = 0; bin < a.g.size(); ++bin) {
    // Shifted positions round differently: a pair at a bin's edge may change bins.
    EXPECT_NEAR(a.g[bin], b.g[bin], 0.05 * a.g[bin] + 1e-3) << "bin " << bin;
  }
}

TEST(Rdf, NeedsTwoParticles) {
  EXPECT_THROW(radial_distribution({ideal_gas(2, 1, {{10, 10, 1}}, true, 3)}),
               std::invalid_argument);
}

TEST(Rdf, ARangeBeyondHalfTheBoxIsRefused) {
  const Frame f = ideal_gas(2, 100, {{10, 10, 1}}, true, 3);
  EXPECT_THROW(radial_distribution({f}, {0.02, 6.0}), std::invalid_argument);
  EXPECT_THROW(radial_distribution({f}, {1e-9, 5.0}), std::invalid_argument);   // 5e9 bins
  EXPECT_THROW(radial_distribution({f}, {1e-30, 5.0}), std::invalid_argument);  // 5e30 bins
  const Frame walled = ideal_gas(2, 100, {{10, 10, 1}}, false, 3);
  EXPECT_THROW(radial_distribution({walled}, {0.02, 4.6}), std::invalid_argument);
}

TEST(Contact, TheFitRecoversAQuadraticAtContact) {
  Rdf rdf;
  rdf.bin_width = 0.02;
  for (int b = 0; b < 100; ++b) {
    const double r = 0.02 * b + 0.01;
    rdf.r.push_back(r);
    const double x = r - 1.0;
    rdf.g.push_back(r < 1.0 ? 0.0 : 3.25 - 5.0 * x + 7.0 * x * x);
  }
  const auto disks = contact_value(rdf, 1.0, 2, 0.5, 0.1);
  ASSERT_TRUE(disks);
  EXPECT_NEAR(disks->g, 3.25, 1e-9);
  EXPECT_NEAR(disks->z, 1.0 + 2.0 * 0.5 * 3.25, 1e-9);
  const auto spheres = contact_value(rdf, 1.0, 3, 0.3, 0.1);
  EXPECT_NEAR(spheres->z, 1.0 + 4.0 * 0.3 * 3.25, 1e-9);
  // Fewer than three bins in range: no value.
  EXPECT_FALSE(contact_value(rdf, 1.0, 2, 0.5, 0.05));
}

namespace {

// 30 frames (t = 2, 2.5, ...) of disks at constant velocities from (1, 2), wrapped into a periodic
// 4 x 5 box with image flags.
std::vector<Frame> ballistic_frames(const std::vector<Vec<3>>& velocity) {
  std::vector<Frame> frames;
  for (int f = 0; f < 30; ++f) {
    Frame frame;
    frame.time = 2.0 + 0.5 * f;
    frame.box = {{4, 5, 1}};
    frame.periodic = true;
    for (const Vec<3>& v : velocity) {
      Vec<3> x = {{1.0 + v[0] * frame.time, 2.0 + v[1] * frame.time, 0}};
      std::array<std::int32_t, 3> image{};
      for (std::size_t k = 0; k < 2; ++k) {
        image[k] = static_cast<std::int32_t>(std::floor(x[k] / frame.box[k]));
        x[k] -= image[k] * frame.box[k];
      }
      frame.position.push_back(x);
      frame.image.push_back(image);
    }
    frames.push_back(frame);
  }
  return frames;
}

}  // namespace

TEST(Msd, BallisticMotionThroughAPeriodicBoxGrowsAsTSquared) {
  // Particles at constant velocity, wrapped with image flags: MSD(t) = <v^2> t^2.
  const std::vector<Vec<3>> velocity = {{{1.5, -0.5, 0}}, {{-2.0, 0.25, 0}}, {{0.1, 3.0, 0}}};
  double v2 = 0.0;
  for (const Vec<3>& v : velocity) v2 += norm2(v) / 3.0;
  const std::vector<Frame> frames = ballistic_frames(velocity);
  const Msd msd = mean_square_displacement(frames);
  ASSERT_EQ(msd.t.size(), 30u);
  for (std::size_t lag = 0; lag < 30; ++lag) {
    EXPECT_DOUBLE_EQ(msd.t[lag], 0.5 * static_cast<double>(lag));
    EXPECT_NEAR(msd.msd[lag], v2 * msd.t[lag] * msd.t[lag], 1e-9 * (1 + msd.msd[lag]));
  }
  // Without image flags the periodic MSD is refused, as are uneven frames.
  std::vector<Frame> no_images = frames;
  no_images[3].image.clear();
  EXPECT_THROW(mean_square_displacement(no_images), std::invalid_argument);
  std::vector<Frame> uneven = frames;
  uneven[5].time += 0.1;
  EXPECT_THROW(mean_square_displacement(uneven), std::invalid_argument);
}

// Event chains move the centre of mass (along +x, +y); --com measures displacements from it.
// Ballistic particles whose mean velocity is u: from the centre of mass, MSD(t) = <|v - u|^2> t^2,
// and the centre of mass moved |u| (t_last - t_first).
TEST(Msd, FromTheCentreOfMassItsMotionIsTakenOut) {
  // 40 disks flowing at about (1, 1), each with a velocity of its own around that.
  constexpr std::size_t kDisks = 40;
  std::vector<Vec<3>> velocity;
  for (std::size_t i = 0; i < kDisks; ++i) {
    const auto angle = static_cast<double>(i);
    velocity.push_back({{1.0 + 0.5 * std::cos(angle), 1.0 + 0.5 * std::sin(angle), 0}});
  }
  Vec<3> mean{};
  for (const Vec<3>& v : velocity) mean = mean + (1.0 / kDisks) * v;
  double relative2 = 0.0;
  for (const Vec<3>& v : velocity) relative2 += norm2(v - mean) / kDisks;
  std::vector<Frame> frames = ballistic_frames(velocity);
  const Msd moved = mean_square_displacement(frames);
  const Msd relative = mean_square_displacement(frames, true);
  const double elapsed = frames.back().time - frames.front().time;
  EXPECT_NEAR(moved.centre_of_mass_shift, std::sqrt(norm2(mean)) * elapsed, 1e-12);
  EXPECT_EQ(relative.centre_of_mass_shift, moved.centre_of_mass_shift);
  for (std::size_t lag = 0; lag < relative.t.size(); ++lag) {
    EXPECT_NEAR(relative.msd[lag], relative2 * relative.t[lag] * relative.t[lag],
                1e-9 * (1 + relative.msd[lag]));
  }
  EXPECT_GT(moved.msd.back(), relative.msd.back() * 1.01);
  // The report warns of the flow, and not once it is taken out.
  const auto flow_warned = [&](bool from_centre_of_mass) {
    AnalysisOptions options;
    options.from_centre_of_mass = from_centre_of_mass;
    for (Frame& frame : frames) {
      frame.radius.assign(kDisks, 0.01);
      frame.velocity.assign(kDisks, Vec<3>{});
      frame.collisions.assign(kDisks, 0);
    }
    const Analysis a = analyze(frames, "drifting", options);
    EXPECT_EQ(a.from_centre_of_mass, from_centre_of_mass);
    return std::ranges::any_of(a.warnings, [](const std::string& w) {
      return w.find("the centre of mass moved by") != std::string::npos;
    });
  };
  EXPECT_TRUE(flow_warned(false));
  EXPECT_FALSE(flow_warned(true));
}

// A sheared run's frame (the images one box up shifted along x): a pair that touches across the
// sheared boundary is at contact, seen from either particle, and not where the rectangular box's
// images would put it.
TEST(Rdf, PairsAcrossTheShearedBoundaryAreSeenThroughTheSlidingImages) {
  Frame f;
  f.dimension = 2;
  f.box = {10.0, 10.0, 1.0};
  f.periodic = true;
  f.shear_shift = 3.0;
  // The image of the second one box down lies at (8 - 3, 9.8 - 10) = (5, -0.2): 0.5 from the first.
  f.position = {{5.0, 0.3, 0.0}, {8.0, 9.8, 0.0}};
  f.radius = {0.25, 0.25};
  f.velocity.assign(2, Vec<3>{});
  f.collisions.assign(2, 0);
  const Rdf rdf = radial_distribution({f}, {0.1, 2.0});
  double pairs_below_contact = 0.0, pairs_at_contact = 0.0;
  for (std::size_t m = 0; m < rdf.r.size(); ++m) {
    (rdf.r[m] < 0.5 ? pairs_below_contact : pairs_at_contact) += rdf.g[m];
    if (rdf.r[m] > 0.6) {
      EXPECT_EQ(rdf.g[m], 0.0) << "r = " << rdf.r[m];
    }
  }
  EXPECT_EQ(pairs_below_contact, 0.0);
  EXPECT_GT(pairs_at_contact, 0.0);
}

TEST(Msd, EveryLagUpTo200FramesThenLogSpacedLags) {
  std::vector<Frame> frames(1000);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    frames[f].time = static_cast<double>(f);
    frames[f].position = {{{0.01 * static_cast<double>(f), 0, 0}}};
  }
  const Msd msd = mean_square_displacement(frames);
  ASSERT_GT(msd.t.size(), 250u);
  EXPECT_LE(msd.t.size(), 301u);
  for (std::size_t lag = 0; lag <= 200; ++lag) EXPECT_EQ(msd.t[lag], static_cast<double>(lag));
  EXPECT_EQ(msd.t.back(), 999.0);
  for (std::size_t m = 0; m < msd.t.size(); ++m) {
    EXPECT_NEAR(msd.msd[m], 1e-4 * msd.t[m] * msd.t[m], 1e-9);
    if (m > 0) {
      EXPECT_GT(msd.t[m], msd.t[m - 1]);
    }
  }
}

TEST(Psi6, ATriangularLatticeIsPerfectlyHexatic) {
  const Frame lattice = triangular_lattice(20, 24, 1.1, 0.0);
  for (const auto& p : local_psi6(lattice)) {
    EXPECT_NEAR(std::abs(p), 1.0, 1e-12);
    EXPECT_NEAR(std::arg(p), 0.0, 1e-9);
  }
  const Psi6Series series = psi6_series({lattice});
  EXPECT_NEAR(series.global[0], 1.0, 1e-12);
  EXPECT_NEAR(series.local_mean[0], 1.0, 1e-12);
}

// A patch of `sites` x `sites` of triangular lattice turned by `angle` about the origin, moved
// to the middle of a box with walls of side `side`.
Frame rotated_patch(std::size_t sites, double angle, double side) {
  Frame patch = triangular_lattice(sites, sites, 1.0, angle);
  patch.periodic = false;
  patch.box = {{side, side, 1}};
  for (Vec<3>& x : patch.position) {
    x[0] += side / 2.0;
    x[1] += side / 2.0;
  }
  return patch;
}

TEST(Psi6, TheLocalPhaseTurnsSixTimesAsFastAsTheLattice) {
  // A rotated patch of lattice in a big box with walls: the inner disks' phase is 6 x angle.
  for (const double angle : {0.05, 0.2, -0.4}) {
    const auto psi = local_psi6(rotated_patch(12, angle, 40.0));
    const std::size_t centre = 6 * 12 + 6;
    EXPECT_NEAR(std::abs(psi[centre]), 1.0, 1e-12);
    EXPECT_NEAR(std::arg(psi[centre]), 6.0 * angle, 1e-9);
  }
}

TEST(Psi6, TheOrientationIsTheLatticesAngleModuloSixtyDegrees) {
  // The rotated patch above: its bonds make `angle` with the x axis, so its global order does;
  // 0.6 rad (34.4 degrees) is the same lattice as 34.4 - 60 degrees.
  for (const double angle : {0.0, 0.05, 0.2, -0.4, 0.6}) {
    const Frame patch = rotated_patch(16, angle, 50.0);
    const double degrees = angle * 180.0 / kPi;
    const double expected = degrees > 30.0 ? degrees - 60.0 : degrees;
    const Psi6Series series = psi6_series({patch});
    ASSERT_EQ(series.orientation.size(), 1u);
    EXPECT_NEAR(series.orientation[0], expected, 0.5) << "angle " << angle;
    EXPECT_GT(series.orientation[0], -30.0);
    EXPECT_LE(series.orientation[0], 30.0);
  }
}

TEST(Psi6, TheNearestSixAreFoundAsBruteForceFindsThem) {
  for (const bool periodic : {true, false}) {
    for (const Vec<3> box : {Vec<3>{{30, 30, 1}}, Vec<3>{{4, 5, 1}}, Vec<3>{{60, 3, 1}}}) {
      const Frame f = ideal_gas(2, periodic ? 300 : 200, box, periodic, 11);
      EXPECT_EQ(local_psi6(f), brute_force_psi6(f)) << "box " << box[0];
    }
  }
}

TEST(Psi6, ClusteredFramesFindTheNearestSixAsBruteForceDoes) {
  for (const bool periodic : {true, false}) {
    const Frame f = clustered(2, 600, 25.0, periodic, 13);
    EXPECT_EQ(local_psi6(f), brute_force_psi6(f)) << (periodic ? "periodic" : "walls");
  }
}

TEST(Psi6, IsForDisksAndNeedsSevenOfThem) {
  EXPECT_THROW(local_psi6(ideal_gas(3, 50, {{5, 5, 5}}, true, 1)), std::invalid_argument);
  EXPECT_THROW(local_psi6(ideal_gas(2, 6, {{5, 5, 1}}, true, 1)), std::invalid_argument);
  EXPECT_NO_THROW(local_psi6(ideal_gas(2, 7, {{5, 5, 1}}, true, 1)));
}

// An elastic run of `start` to `end` with a frame every `every` written to `path` (its ending
// names the format).
void dump_run(const System<2>& start, const std::string& path, double every, double end) {
  std::ofstream out(path, std::ios::binary);
  Simulation<2> simulation(start, Settings{{Rule::elastic}});
  simulation.add_observer(
      std::make_shared<FrameWriter<2>>(out, trajectory_format_for<2>(path), every));
  simulation.run_until(end);
}

// 60 disks at packing 0.4 in a periodic box: a short run's start.
System<2> small_gas() {
  InitialOptions init;
  init.n = 60;
  init.packing_fraction = 0.4;
  init.boundary = Boundary::periodic;
  return make_initial<2>(init);
}

// A short run of disks dumped as .gsd and .xyz: the frames read back agree.
TEST(TrajectoryReader, GsdAndXyzFramesOfOneRunAgree) {
  const auto folder = std::filesystem::temp_directory_path() / "carom_analysis_test";
  std::filesystem::create_directories(folder);
  const System<2> start = small_gas();
  std::vector<std::string> paths;
  for (const char* ending : {".gsd", ".xyz"}) {
    const std::string path = (folder / (std::string("run") + ending)).string();
    dump_run(start, path, 0.25, 5.0);
    paths.push_back(path);
  }
  const std::vector<Frame> gsd = read_trajectory_frames(paths[0]);
  const std::vector<Frame> xyz = read_trajectory_frames(paths[1]);
  ASSERT_EQ(gsd.size(), 21u);
  ASSERT_EQ(gsd.size(), xyz.size());
  for (std::size_t f = 0; f < gsd.size(); ++f) {
    EXPECT_DOUBLE_EQ(gsd[f].time, xyz[f].time);
    EXPECT_EQ(gsd[f].dimension, 2);
    EXPECT_TRUE(gsd[f].periodic);
    ASSERT_EQ(gsd[f].image.size(), 60u);
    EXPECT_EQ(gsd[f].image, xyz[f].image);
    for (std::size_t i = 0; i < 60; ++i) {
      for (std::size_t k = 0; k < 2; ++k) {
        // float32 in GSD
        EXPECT_NEAR(gsd[f].position[i][k], xyz[f].position[i][k], 1e-5);
        EXPECT_NEAR(gsd[f].velocity[i][k], xyz[f].velocity[i][k], 1e-5);
      }
      EXPECT_NEAR(gsd[f].radius[i], xyz[f].radius[i], 1e-7);
    }
  }
  std::filesystem::remove_all(folder);
}

// carom analyze whole: what analyze(AnalysisSpec) writes is what it returns, and it refuses an
// output that is an input before any work, apart from frames it cannot analyse.
TEST(AnalysisSpec, WritesTheJsonAndThePageOfWhatItReturns) {
  const auto folder = std::filesystem::temp_directory_path() / "carom_analysis_spec_test";
  std::filesystem::create_directories(folder);
  AnalysisSpec spec;
  spec.trajectory.path = (folder / "run.gsd").string();
  dump_run(small_gas(), spec.trajectory.path, 0.25, 5.0);
  spec.json.path = (folder / "analysis.json").string();
  spec.html.path = (folder / "report.html").string();
  spec.options.from_time = 1.0;
  const Analysis analysis = analyze(spec);
  EXPECT_EQ(analysis.time.front(), 1.0);
  EXPECT_EQ(analysis.frames_in_file, 21u);
  const auto read = [](const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  };
  std::ostringstream json, page;
  write_analysis_json(json, analysis);
  write_report_html(page, analysis);
  EXPECT_EQ(read(spec.json.path), json.str());
  EXPECT_EQ(read(spec.html.path), page.str());

  spec.options.from_time = 100.0;
  EXPECT_THROW(analyze(spec), AnalysisError);
  spec.html.path = spec.trajectory.path;
  try {
    analyze(spec);
    ADD_FAILURE() << "the page would overwrite the trajectory";
  } catch (const RequestError& e) {
    EXPECT_NE(std::string(e.what()).find("the input TRAJECTORY and --html"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(folder);
}

TEST(TrajectoryReader, AGsdDumpOfAWalledRunIsReadWithWalls) {
  const auto folder = std::filesystem::temp_directory_path() / "carom_walled_gsd_test";
  std::filesystem::create_directories(folder);
  InitialOptions init;
  init.n = 30;
  init.packing_fraction = 0.3;
  init.boundary = Boundary::walls;
  const System<2> start = make_initial<2>(init);
  const std::string path = (folder / "walls.gsd").string();
  dump_run(start, path, 0.5, 2.0);
  const std::vector<Frame> frames = read_gsd_frames(path);
  ASSERT_EQ(frames.size(), 5u);
  for (const Frame& f : frames) EXPECT_FALSE(f.periodic);
  const AnyClassicInput again = read_gsd_start(path, 0);
  EXPECT_EQ(std::get<ClassicInput<2>>(again).system.box.boundary, Boundary::walls);
  // Walls: no Z from the contact value, said why.
  const Analysis analysis = analyze(frames, "walls.gsd");
  EXPECT_FALSE(analysis.contact);
  EXPECT_NE(analysis.warnings.front().find("between walls"), std::string::npos);
  std::filesystem::remove_all(folder);
}

TEST(Analyze, RefusesFramesOfDifferentBoxes) {
  Frame big = ideal_gas(2, 50, {{40, 40, 1}}, true, 1),
        small = ideal_gas(2, 50, {{20, 20, 1}}, true, 2);
  small.time = 1.0;
  EXPECT_THROW(analyze({big, small}, "npt.gsd"), std::invalid_argument);
  Frame walls = big;
  walls.periodic = false;
  walls.time = 1.0;
  EXPECT_THROW(analyze({big, walls}, "mixed.xyz"), std::invalid_argument);
}

TEST(Analyze, AFrameWrittenAtTheEquilibrationTimeWithARoundingCounts) {
  std::vector<Frame> frames;
  for (int f = 0; f < 4; ++f) {
    frames.push_back(ideal_gas(2, 20, {{10, 10, 1}}, true, static_cast<std::uint32_t>(f)));
    frames.back().time = 0.3 * f;  // 0.8999999999999999 for f = 3
  }
  AnalysisOptions options;
  options.from_time = 0.9;
  ASSERT_LT(frames[3].time, 0.9);
  EXPECT_EQ(analyze(frames, "x.gsd", options).time.size(), 1u);
  options.from_time = 0.6;
  EXPECT_EQ(analyze(frames, "x.gsd", options).time.size(), 2u);
}

TEST(Analyze, OverlappingParticlesGetNoContactValue) {
  // An ideal gas of particles of diameter 1 overlaps: not hard particles.
  const Analysis analysis = analyze({ideal_gas(2, 400, {{20, 20, 1}}, true, 4)}, "soft.gsd");
  EXPECT_FALSE(analysis.contact);
  EXPECT_NE(analysis.warnings.front().find("not hard particles"), std::string::npos);
}

TEST(Analyze, AnyNameIsSafeInTheJsonAndThePage) {
  Analysis analysis =
      analyze({ideal_gas(2, 40, {{10, 10, 1}}, true, 4)}, "caf\xe9</script><!--<script>.gsd");
  std::ostringstream json, html;
  EXPECT_NO_THROW(write_analysis_json(json, analysis));
  write_report_html(html, analysis);
  const std::string page = html.str();
  // The data holds no "<": the name's markup cannot end or derail the page's script.
  const std::size_t at = page.find("caf");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(page.find("</script><!--", at), std::string::npos);
  EXPECT_NE(page.find("\\u003c/script>\\u003c!--", at), std::string::npos);
}

TEST(TrajectoryReader, XyzWithoutTimeCountsFramesAndPbcMustBeABox) {
  const std::string frame = "2\nLattice=\"4 0 0 0 4 0 0 0 1\" pbc=\"T T F\"\nH 1 1 0\nH 2 2 0\n";
  std::istringstream two(frame + frame);
  const std::vector<Frame> frames = read_xyz_frames(two, "t.xyz");
  EXPECT_EQ(frames[0].time, 0.0);
  EXPECT_EQ(frames[1].time, 1.0);
  EXPECT_TRUE(frames[0].periodic);
  std::istringstream slab("2\nLattice=\"4 0 0 0 4 0 0 0 1\" pbc=\"T F F\"\nH 1 1 0\nH 2 2 0\n");
  EXPECT_THROW(read_xyz_frames(slab, "slab.xyz"), InputError);
  std::istringstream spheres("2\nLattice=\"4 0 0 0 4 0 0 0 4\" pbc=\"T T F\"\nH 1 1 1\nH 2 2 2\n");
  EXPECT_THROW(read_xyz_frames(spheres, "spheres.xyz"), InputError);
}

TEST(LogTable, ReadsACaromLogAndNamesTheLineOfAnError) {
  const auto folder = std::filesystem::temp_directory_path() / "carom_log_table_test";
  std::filesystem::create_directories(folder);
  const auto write = [&](const std::string& name, const std::string& text) {
    const std::string path = (folder / name).string();
    std::ofstream(path) << text;
    return path;
  };
  const LogTable table =
      read_log_table(write("good.csv", "time,Z,Z_mean\n0,,\n0.5,3.5,\n1,4,3.75\n"));
  EXPECT_EQ(table.columns, (std::vector<std::string>{"time", "Z", "Z_mean"}));
  ASSERT_EQ(table.rows.size(), 3u);
  EXPECT_TRUE(std::isnan(table.rows[0][1]));
  EXPECT_EQ(table.rows[2][2], 3.75);
  const auto error_of = [&](const std::string& text) {
    try {
      read_log_table(write("bad.csv", text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("x,y\n1,2\n").find("bad.csv:1:"), std::string::npos);
  EXPECT_NE(error_of("time,Z\n1,2\n3\n").find("bad.csv:3: expected 2 fields, found 1"),
            std::string::npos);
  EXPECT_NE(error_of("time,Z\n1,abc\n").find("bad.csv:2:"), std::string::npos);
  EXPECT_NE(error_of("").find("empty"), std::string::npos);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace carom

namespace carom {
namespace {

TEST(Analysis, SelfDiffusionIsTheMsdsLateSlopeOverTwoD) {
  // Ballistic at first, then diffusive with D = 0.3 in 3D: msd = 6 D t + offset past t = 1.
  Msd msd;
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.25 * k;
    msd.t.push_back(t);
    msd.msd.push_back(t < 1.0 ? 3.0 * t * t : 6.0 * 0.3 * t + 0.5);
  }
  ASSERT_TRUE(self_diffusion(msd, 3).has_value());
  EXPECT_NEAR(*self_diffusion(msd, 3), 0.3, 1e-12);
  EXPECT_NEAR(*self_diffusion(msd, 2), 0.45, 1e-12);
  msd.t.resize(3);
  msd.msd.resize(3);
  EXPECT_FALSE(self_diffusion(msd, 3).has_value());
}

}  // namespace
}  // namespace carom
