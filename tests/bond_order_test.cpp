#include "carom/analysis/bond_order.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "carom/analysis/analysis.hpp"

namespace carom {
namespace {

constexpr double kPi = std::numbers::pi;

// A frame of spheres of radius 0.5 at `points`: periodic in `box`, or between walls.
Frame spheres(const std::vector<Vec<3>>& points, Vec<3> box, bool periodic) {
  Frame f;
  f.dimension = 3;
  f.box = box;
  f.periodic = periodic;
  for (const Vec<3>& x : points) {
    f.position.push_back(x);
    f.velocity.push_back({});
    f.radius.push_back(0.5);
    f.collisions.push_back(0);
  }
  return f;
}

// A periodic crystal: `cells` copies along each axis of a cell of sides `cell` holding `basis`
// (in fractions of the cell).
Frame crystal(const std::vector<Vec<3>>& basis, Vec<3> cell, std::size_t cells) {
  std::vector<Vec<3>> points;
  for (std::size_t a = 0; a < cells; ++a) {
    for (std::size_t b = 0; b < cells; ++b) {
      for (std::size_t c = 0; c < cells; ++c) {
        const Vec<3> corner = {
            {static_cast<double>(a), static_cast<double>(b), static_cast<double>(c)}};
        for (const Vec<3>& u : basis) {
          points.push_back({{(corner[0] + u[0]) * cell[0], (corner[1] + u[1]) * cell[1],
                             (corner[2] + u[2]) * cell[2]}});
        }
      }
    }
  }
  const auto n = static_cast<double>(cells);
  return spheres(points, {{cell[0] * n, cell[1] * n, cell[2] * n}}, true);
}

// Nearest neighbours at distance `spacing`; the next shells at sqrt(2) spacing (FCC, HCP) or
// 2 / sqrt(3) spacing (BCC).
Frame fcc(double spacing) {
  const double a = spacing * std::sqrt(2.0);
  return crystal({{{0, 0, 0}}, {{0.5, 0.5, 0}}, {{0.5, 0, 0.5}}, {{0, 0.5, 0.5}}}, {{a, a, a}}, 4);
}
Frame bcc(double spacing) {
  const double a = spacing * 2.0 / std::sqrt(3.0);
  return crystal({{{0, 0, 0}}, {{0.5, 0.5, 0.5}}}, {{a, a, a}}, 5);
}
// ABAB stacking of triangular layers in an orthorhombic cell a x sqrt(3) a x c.
Frame hcp(double spacing) {
  const double a = spacing, c = std::sqrt(8.0 / 3.0) * a;
  return crystal({{{0, 0, 0}}, {{0.5, 0.5, 0}}, {{0.5, 1.0 / 6.0, 0.5}}, {{0, 2.0 / 3.0, 0.5}}},
                 {{a, std::sqrt(3.0) * a, c}}, 4);
}

// Every particle has the value `expected` to the literature's five digits.
void expect_everywhere(const std::vector<double>& values, double expected, const char* what) {
  for (const double v : values) ASSERT_NEAR(v, expected, 6e-6) << what;
}

// The literature's values (Steinhardt, Nelson, Ronchetti 1983; Lechner, Dellago 2008, table I),
// every particle of each ideal crystal alike. The cutoffs lie between the first and second
// shells, or (BCC with 14 neighbours) between the second and third. BCC's 8 nearest make a cube,
// whose w4 and w6 the literature does not list: these are python/tests' numpy reference's (w4
// of any shell of cubic symmetry is +-0.15932, l = 4 having one cubic invariant).
TEST(BondOrder, IdealCrystalsHaveTheLiteratureValues) {
  struct Case {
    const char* name;
    Frame frame;
    double cutoff;
    std::size_t neighbours;
    double q4, q6, w4, w6;
  };
  const std::vector<Case> cases = {
      {"FCC", fcc(1.0), 1.2, 12, 0.19094, 0.57452, -0.15932, -0.01316},
      {"HCP", hcp(1.0), 1.2, 12, 0.09722, 0.48476, 0.13410, -0.01244},
      // BCC: nearest at 1, second shell at 2 / sqrt(3) = 1.1547, third at 1.633.
      {"BCC 8", bcc(1.0), 1.08, 8, 0.50918, 0.62854, -0.15932, 0.01316},
      {"BCC 14", bcc(1.0), 1.4, 14, 0.03637, 0.51069, 0.15932, 0.01316},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const BondOrder order = bond_order(c.frame, {c.cutoff});
    EXPECT_EQ(order.cutoff, c.cutoff);
    for (const std::size_t count : order.neighbours) ASSERT_EQ(count, c.neighbours);
    expect_everywhere(order.degree(4).q, c.q4, "q4");
    expect_everywhere(order.degree(6).q, c.q6, "q6");
    expect_everywhere(order.degree(4).w, c.w4, "w4");
    expect_everywhere(order.degree(6).w, c.w6, "w6");
  }
}

// The average over the neighbours changes nothing where every particle's q_lm is the same: in
// FCC and BCC, and in HCP too, whose two layers' shells differ by a turn of 60 degrees about the
// c axis, which leaves alone the only q_lm they have (m = 0 and +-6, the shell being
// three-fold and mirror symmetric).
TEST(BondOrder, AveragedOrderEqualsPlainInIdealCrystals) {
  for (const auto& [frame, cutoff] :
       {std::pair{fcc(1.0), 1.2}, std::pair{hcp(1.0), 1.2}, std::pair{bcc(1.0), 1.4}}) {
    const BondOrder order = bond_order(frame, {cutoff});
    for (const int l : kBondOrderDegrees) {
      const SteinhardtInvariants& of = order.degree(l);
      for (std::size_t i = 0; i < of.q.size(); ++i) {
        ASSERT_NEAR(of.q_bar[i], of.q[i], 1e-12) << "l = " << l;
        ASSERT_NEAR(of.w_bar[i], of.w[i], 1e-12) << "l = " << l;
      }
    }
  }
}

// One particle and a shell of 12 around it in any orientation: the icosahedron (q4 = 0,
// q6 = 0.66332, w6 = -0.16975) and FCC's cuboctahedron, turned so that no bond lies along an
// axis. The shell, far from the walls of a large box, is the centre's only neighbours.
TEST(BondOrder, ShellsInAnyOrientation) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec<3>> icosahedron, cuboctahedron;
  for (const double s : {-1.0, 1.0}) {
    for (const double t : {-1.0, 1.0}) {
      icosahedron.insert(icosahedron.end(),
                         {{{0, s, t * phi}}, {{s, t * phi, 0}}, {{t * phi, 0, s}}});
      cuboctahedron.insert(cuboctahedron.end(), {{{0, s, t}}, {{s, t, 0}}, {{t, 0, s}}});
    }
  }
  // Rotations about z, then x, by irrational angles.
  const auto turned = [](Vec<3> x, double scale) {
    const double a = 0.3 * kPi * std::sqrt(2.0), b = 0.1 * kPi * std::sqrt(3.0);
    Vec<3> y = {
        {std::cos(a) * x[0] - std::sin(a) * x[1], std::sin(a) * x[0] + std::cos(a) * x[1], x[2]}};
    y = {{y[0], std::cos(b) * y[1] - std::sin(b) * y[2], std::sin(b) * y[1] + std::cos(b) * y[2]}};
    return Vec<3>{{50 + scale * y[0], 50 + scale * y[1], 50 + scale * y[2]}};
  };
  struct Case {
    const char* name;
    const std::vector<Vec<3>>& shell;
    double q4, q6, w6;
  };
  for (const Case& c : {Case{"icosahedron", icosahedron, 0.0, 0.66332, -0.16975},
                        Case{"cuboctahedron", cuboctahedron, 0.19094, 0.57452, -0.01316}}) {
    SCOPED_TRACE(c.name);
    std::vector<Vec<3>> points = {turned({{0, 0, 0}}, 1.0)};
    for (const Vec<3>& x : c.shell) points.push_back(turned(x, 1.0 / std::sqrt(norm2(x))));
    const BondOrder order = bond_order(spheres(points, {{100, 100, 100}}, false), {1.1});
    EXPECT_EQ(order.neighbours[0], 12u);
    EXPECT_NEAR(order.degree(4).q[0], c.q4, 6e-6);
    EXPECT_NEAR(order.degree(6).q[0], c.q6, 6e-6);
    EXPECT_NEAR(order.degree(6).w[0], c.w6, 6e-6);
  }
}

TEST(BondOrder, WignerSymbolsHaveTheirClosedForms) {
  // (l l 0; m -m 0) = (-1)^(l - m) / sqrt(2l + 1); (2 2 2; 0 0 0) = -sqrt(2 / 35);
  // (4 4 4; 0 0 0) = sqrt(18 / 1001); (6 6 6; 0 0 0) = -20 sqrt(1 / 46189).
  for (const int l : {1, 4, 6}) {
    for (int m = -l; m <= l; ++m) {
      EXPECT_NEAR(wigner_3j(l, l, 0, m, -m, 0),
                  ((l - m) % 2 == 0 ? 1.0 : -1.0) / std::sqrt(2.0 * l + 1.0), 1e-15);
    }
  }
  EXPECT_NEAR(wigner_3j(2, 2, 2, 0, 0, 0), -std::sqrt(2.0 / 35.0), 1e-15);
  EXPECT_NEAR(wigner_3j(4, 4, 4, 0, 0, 0), std::sqrt(18.0 / 1001.0), 1e-15);
  EXPECT_NEAR(wigner_3j(6, 6, 6, 0, 0, 0), -20.0 / std::sqrt(46189.0), 1e-15);
  // (1 1 2; 1 0 -1) = (-1)^(1 - 1 + 1) / sqrt(5) <1 1; 1 0 | 2 1> = -1 / sqrt(10): a symbol whose
  // phase (-1)^(l1 - l2 - m3) is odd.
  EXPECT_NEAR(wigner_3j(1, 1, 2, 1, 0, -1), -1.0 / std::sqrt(10.0), 1e-15);
  // Swapping two columns, or negating every m, multiplies by (-1)^(l1 + l2 + l3).
  for (const auto& [l1, l2, l3] : {std::array{4, 6, 5}, std::array{6, 6, 6}, std::array{4, 4, 7}}) {
    const double sign = (l1 + l2 + l3) % 2 == 0 ? 1.0 : -1.0;
    for (int m1 = -l1; m1 <= l1; ++m1) {
      for (int m2 = -l2; m2 <= l2; ++m2) {
        const int m3 = -m1 - m2;
        const double symbol = wigner_3j(l1, l2, l3, m1, m2, m3);
        ASSERT_NEAR(wigner_3j(l2, l1, l3, m2, m1, m3), sign * symbol, 1e-15);
        ASSERT_NEAR(wigner_3j(l1, l2, l3, -m1, -m2, -m3), sign * symbol, 1e-15);
      }
    }
  }
  EXPECT_EQ(wigner_3j(6, 6, 6, 1, 1, 1), 0.0);  // m's do not add to 0
  EXPECT_EQ(wigner_3j(1, 1, 3, 0, 0, 0), 0.0);  // no triangle
  // Orthogonality: (2 l3 + 1) sum over m1, m2 of the squares is 1 for every m3 the l's allow.
  for (const int l : kBondOrderDegrees) {
    for (int l3 = 0; l3 <= 2 * l; ++l3) {
      for (int m3 = -l3; m3 <= l3; ++m3) {
        double sum = 0.0;
        for (int m1 = -l; m1 <= l; ++m1) {
          const double symbol = wigner_3j(l, l, l3, m1, -m1 - m3, m3);
          sum += symbol * symbol;
        }
        ASSERT_NEAR((2 * l3 + 1) * sum, 1.0, 1e-13) << l << " " << l3 << " " << m3;
      }
    }
  }
}

TEST(BondOrder, EveryParticleOfAnIdealCrystalIsSolidLikeInOneCluster) {
  // FCC and HCP at the hard-sphere melting density (packing 0.545: nearest at 1.107 d, second
  // shell at 1.566 d), with the default cutoff of 1.5 d; BCC with its 8 and its 14 neighbours.
  const double melting = std::cbrt(kPi / (3.0 * std::sqrt(2.0) * 0.545));
  struct Case {
    const char* name;
    Frame frame;
    double cutoff;
  };
  for (const Case& c : {Case{"FCC", fcc(melting), 0.0}, Case{"HCP", hcp(melting), 0.0},
                        Case{"BCC 8", bcc(1.0), 1.08}, Case{"BCC 14", bcc(1.0), 1.4}}) {
    SCOPED_TRACE(c.name);
    const BondOrder order = bond_order(c.frame, {c.cutoff});
    const std::size_t n = c.frame.position.size();
    if (c.cutoff == 0.0) {
      EXPECT_DOUBLE_EQ(order.cutoff, 1.5);
    }
    EXPECT_EQ(std::count(order.solid_like.begin(), order.solid_like.end(), true),
              static_cast<std::ptrdiff_t>(n));
    EXPECT_EQ(order.cluster_sizes, std::vector<std::size_t>{n});
    EXPECT_EQ(std::count(order.cluster.begin(), order.cluster.end(), 0),
              static_cast<std::ptrdiff_t>(n));
  }
}

// `n` points uniformly in a periodic cube of side `side` (overlapping: an ideal gas).
Frame ideal_gas(std::size_t n, double side, std::uint32_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> along(0.0, side);
  std::vector<Vec<3>> points(n);
  for (Vec<3>& x : points) x = {{along(random), along(random), along(random)}};
  return spheres(points, {{side, side, side}}, true);
}

TEST(BondOrder, AnIdealGasHasAlmostNoSolidLikeParticles) {
  // About 12 neighbours within 1.5 d, as in a dense liquid, but no order.
  const Frame gas = ideal_gas(3000, 15.2, 7);
  const BondOrder order = bond_order(gas);
  const auto solid = std::count(order.solid_like.begin(), order.solid_like.end(), true);
  EXPECT_LE(solid, 3);
  EXPECT_LE(order.cluster_sizes.empty() ? 0 : order.cluster_sizes.front(), 2u);
  double q6 = 0.0;
  for (const double q : order.degree(6).q) q6 += q / 3000.0;
  EXPECT_GT(q6, 0.2);  // a few random bonds are far from isotropic ...
  EXPECT_LT(q6, 0.4);  // ... but far from a crystal's order
}

// The neighbours are the pairs closer than the cutoff by minimum image, as every pair shows.
TEST(BondOrder, NeighboursAreEveryPairWithinTheCutoff) {
  const Frame gas = ideal_gas(500, 7.0, 3);
  const double cutoff = 1.3;
  std::vector<std::size_t> expected(gas.position.size(), 0);
  for (std::size_t i = 0; i < gas.position.size(); ++i) {
    for (std::size_t j = 0; j < gas.position.size(); ++j) {
      double r2 = 0.0;
      for (std::size_t k = 0; k < 3; ++k) {
        double dx = gas.position[j][k] - gas.position[i][k];
        dx -= gas.box[k] * std::nearbyint(dx / gas.box[k]);
        r2 += dx * dx;
      }
      if (i != j && r2 < cutoff * cutoff) ++expected[i];
    }
  }
  EXPECT_EQ(bond_order(gas, {cutoff}).neighbours, expected);
}

// Two crystallites, apart in a large walled box with a gas around them: two clusters, the larger
// first, each particle labelled with its own crystallite's; the gas is in none.
TEST(BondOrder, SeparateCrystallitesAreSeparateClusters) {
  std::vector<Vec<3>> points;
  std::vector<int> block;
  const auto add_block = [&](double corner, std::size_t cells, int label) {
    const double a = std::sqrt(2.0);
    const Frame f = crystal({{{0, 0, 0}}, {{0.5, 0.5, 0}}, {{0.5, 0, 0.5}}, {{0, 0.5, 0.5}}},
                            {{a, a, a}}, cells);
    for (const Vec<3>& x : f.position) {
      points.push_back({{corner + x[0], corner + x[1], corner + x[2]}});
      block.push_back(label);
    }
  };
  add_block(5.0, 3, 0);
  add_block(30.0, 4, 1);
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> along(1.0, 49.0);
  for (std::size_t g = 0; g < 300; ++g) {
    points.push_back({{along(random), along(random), 20.0 + 0.2 * along(random)}});
    block.push_back(-1);
  }
  const BondOrder order = bond_order(spheres(points, {{50, 50, 50}}, false), {1.2});
  ASSERT_EQ(order.cluster_sizes.size(), 2u);
  EXPECT_GT(order.cluster_sizes[0], order.cluster_sizes[1]);
  EXPECT_GT(order.cluster_sizes[1], 50u);  // most of 108: all but the crystallite's edges
  std::vector<std::size_t> counted(2, 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (block[i] < 0) {
      EXPECT_EQ(order.cluster[i], -1) << i;
    } else if (order.cluster[i] >= 0) {
      // The larger crystallite (block 1) is cluster 0.
      EXPECT_EQ(order.cluster[i], 1 - block[i]) << i;
      ++counted[static_cast<std::size_t>(order.cluster[i])];
    }
    EXPECT_EQ(order.cluster[i] >= 0, static_cast<bool>(order.solid_like[i])) << i;
  }
  EXPECT_EQ(counted, order.cluster_sizes);
}

TEST(BondOrder, SeriesHoldsEachFramesMeansAndTheLastFrame) {
  Frame crystal_frame = fcc(1.0),
        gas = ideal_gas(crystal_frame.position.size(), 4 * std::sqrt(2.0), 5);
  crystal_frame.time = 1.0;
  gas.time = 2.0;
  const BondOrderSeries series = bond_order_series({crystal_frame, gas}, {1.2});
  EXPECT_EQ(series.t, (std::vector<double>{1.0, 2.0}));
  EXPECT_NEAR(series.degree(6).q[0], 0.57452, 6e-6);
  EXPECT_NEAR(series.degree(4).w_bar[0], -0.15932, 6e-6);
  EXPECT_EQ(series.solid_like[0], crystal_frame.position.size());
  EXPECT_EQ(series.largest_cluster[0], crystal_frame.position.size());
  EXPECT_EQ(series.cluster_sizes[0], std::vector<std::size_t>{crystal_frame.position.size()});
  const BondOrder last = bond_order(gas, {1.2});
  EXPECT_EQ(series.last_frame.degree(6).q, last.degree(6).q);
  EXPECT_EQ(series.last_frame.cluster, last.cluster);
  double q6 = 0.0;
  for (const double q : last.degree(6).q) q6 += q / static_cast<double>(last.neighbours.size());
  EXPECT_NEAR(series.degree(6).q[1], q6, 1e-12);
}

TEST(BondOrder, RefusesDisksAndACutoffTheBoxCannotHave) {
  Frame disks = fcc(1.0);
  disks.dimension = 2;
  EXPECT_THROW(bond_order(disks), std::invalid_argument);
  const Frame lattice = fcc(1.0);  // a periodic box of side 5.66
  EXPECT_NO_THROW(bond_order(lattice, {2.8}));
  EXPECT_THROW(bond_order(lattice, {2.9}), std::invalid_argument);
  EXPECT_THROW(static_cast<void>(bond_order(lattice).degree(8)), std::invalid_argument);
}

// carom analyze: the bond order of spheres, absent for disks; a default cutoff the box cannot
// have is a warning, one asked for an error.
TEST(BondOrder, AnalyzeHasItForSpheresOnly) {
  const Analysis spheres_analysis = analyze({fcc(1.0)}, "fcc.gsd");
  ASSERT_TRUE(spheres_analysis.steinhardt);
  EXPECT_DOUBLE_EQ(spheres_analysis.steinhardt->cutoff, 1.5);
  AnalysisOptions options;
  options.bond_order.cutoff = 1.2;
  EXPECT_NEAR(analyze({fcc(1.0)}, "fcc.gsd", options).steinhardt->degree(6).q[0], 0.57452, 6e-6);
  Frame disks = ideal_gas(50, 10.0, 1);
  disks.dimension = 2;
  for (Vec<3>& x : disks.position) x[2] = 0.0;
  const Analysis disks_analysis = analyze({disks}, "disks.gsd");
  EXPECT_FALSE(disks_analysis.steinhardt);
  const Analysis small = analyze({ideal_gas(20, 2.5, 1)}, "small.gsd");
  EXPECT_FALSE(small.steinhardt);
  EXPECT_TRUE(std::any_of(small.warnings.begin(), small.warnings.end(), [](const std::string& w) {
    return w.find("no Steinhardt bond order") != std::string::npos;
  }));
  options.bond_order.cutoff = 2.0;
  EXPECT_THROW(analyze({ideal_gas(20, 2.5, 1)}, "small.gsd", options), std::invalid_argument);
}

}  // namespace
}  // namespace carom
