// carom init's configurations: non-overlapping, at the requested packing fraction and temperature,
// reproducible, in two and three dimensions.
#include "carom/engine/initial.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "carom/core/observables.hpp"
#include "carom/core/physics.hpp"
#include "carom/engine/overlap.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/run_report.hpp"

namespace carom {
namespace {

// n particles at packing fraction phi, the other options at their defaults.
InitialOptions request(std::uint64_t n, double phi, Boundary boundary = Boundary::walls) {
  InitialOptions o;
  o.n = n;
  o.packing_fraction = phi;
  o.boundary = boundary;
  return o;
}

// The smallest gap between two surfaces over the contact distance (0 when the closest pair
// touches), by brute force through the nearest images.
template <std::size_t D>
double smallest_relative_gap(const System<D>& system) {
  double smallest = kNever;
  for (std::size_t i = 0; i < system.size(); ++i) {
    for (std::size_t j = i + 1; j < system.size(); ++j) {
      const Particle<D>& a = system.particles[i];
      const Particle<D>& b = system.particles[j];
      const double sigma = a.radius + b.radius;
      smallest = std::min(smallest, std::sqrt(norm2(separation(a, b, system.box))) / sigma - 1.0);
    }
  }
  return smallest;
}

template <std::size_t D>
void expect_valid(const System<D>& system, const InitialOptions& o) {
  ASSERT_EQ(system.size(), o.n);
  EXPECT_EQ(find_violation(system, 0.0), std::nullopt);
  EXPECT_NEAR(packing_fraction(system), o.packing_fraction, 1e-13 * o.packing_fraction);
  EXPECT_NEAR(kinetic_temperature(system), o.temperature, 1e-13);
  for (std::size_t k = 0; k < D; ++k) EXPECT_NEAR(momentum(system)[k], 0.0, 1e-11);
}

TEST(Initial, HitsThePackingFractionWithZeroMomentumAndExactTemperature) {
  for (double phi : {0.1, 0.45, 0.8}) {
    for (Boundary b : {Boundary::walls, Boundary::periodic}) {
      InitialOptions o;
      o.n = 500;
      o.packing_fraction = phi;
      o.temperature = 2.5;
      o.boundary = b;
      const System<2> s = make_initial<2>(o);
      ASSERT_EQ(s.particles.size(), 500u);
      EXPECT_NEAR(packing_fraction(s), phi, 1e-12);
      EXPECT_NEAR(momentum(s)[0], 0.0, 1e-10);
      EXPECT_NEAR(momentum(s)[1], 0.0, 1e-10);
      // kT over the degrees of freedom the run has: 2 N with walls, 2 (N - 1) periodic.
      const double dof = b == Boundary::walls ? 2.0 * 500 : 2.0 * 499;
      EXPECT_NEAR(2.0 * kinetic_energy(s) / dof, 2.5, 1e-12);
      EXPECT_NEAR(kinetic_temperature(s), 2.5, 1e-12);
      EXPECT_FALSE(find_pair_overlap(s, 0.0).has_value()) << phi;
      for (const Particle<2>& p : s.particles) {
        for (int wall = -1; wall >= -4 && b == Boundary::walls; --wall) {
          EXPECT_FALSE(overlaps_wall(p, s.box, wall));
        }
      }
    }
  }
}

TEST(Initial, IsReproducibleBitForBitAndPolydisperseOnRequest) {
  InitialOptions o;
  o.n = 200;
  o.packing_fraction = 0.3;
  o.polydispersity = 0.2;
  o.seed = 9;
  const System<2> a = make_initial<2>(o), b = make_initial<2>(o);
  for (std::size_t i = 0; i < 200; ++i) {
    EXPECT_EQ(a.particles[i].position, b.particles[i].position);
    EXPECT_EQ(a.particles[i].velocity, b.particles[i].velocity);
    EXPECT_EQ(a.particles[i].radius, b.particles[i].radius);
  }
  double mean = 0.0, square = 0.0;
  for (const auto& p : a.particles) mean += p.radius / 200;
  for (const auto& p : a.particles) square += (p.radius - mean) * (p.radius - mean) / 200;
  EXPECT_NEAR(std::sqrt(square) / mean, 0.2, 0.03);
  EXPECT_NEAR(mean, 0.5, 0.03);
  EXPECT_NEAR(packing_fraction(a), 0.3, 1e-12);
}

TEST(Initial, ImpossibleDisksAreRefused) {
  InitialOptions o;
  o.n = 10;
  o.packing_fraction = 0.95;
  EXPECT_THROW(make_initial<2>(o), InitialError);
  o.packing_fraction = 0.7;
  o.placement = Placement::random;
  o.n = 400;
  EXPECT_THROW(make_initial<2>(o), InitialError);
}

TEST(Initial, SpheresFillWholeFccCellsUpToClosePacking) {
  for (const std::uint64_t cells : {2, 3, 5}) {
    InitialOptions o;
    o.n = 4 * cells * cells * cells;
    o.packing_fraction = kClosePackingSpheres;
    o.boundary = Boundary::periodic;
    const System<3> system = make_initial<3>(o);
    expect_valid(system, o);
    // Every sphere touches its twelve neighbours, within round-off.
    EXPECT_NEAR(smallest_relative_gap(system), 0.0, 1e-12) << cells;
    EXPECT_EQ(system.box.size[0], system.box.size[1]);
    EXPECT_EQ(system.box.size[0], system.box.size[2]);
  }
}

TEST(Initial, AnFccLatticeWithVacanciesSpreadsThem) {
  InitialOptions o;
  o.n = 1009;  // prime: the lattice has more sites than spheres
  o.packing_fraction = 0.5;
  o.boundary = Boundary::periodic;
  o.placement = Placement::lattice;
  const System<3> system = make_initial<3>(o);
  expect_valid(system, o);
  // Each half of the box along every axis holds about half the spheres.
  for (std::size_t k = 0; k < 3; ++k) {
    std::size_t lower = 0;
    for (const Particle<3>& p : system.particles) lower += p.position[k] < system.box.size[k] / 2;
    EXPECT_NEAR(static_cast<double>(lower), 504.5, 10.0) << k;
  }
}

TEST(Initial, SpheresAtRandomWithWallsAndPeriodic) {
  for (const Boundary boundary : {Boundary::walls, Boundary::periodic}) {
    InitialOptions o;
    o.n = 2000;
    o.packing_fraction = 0.25;
    o.boundary = boundary;
    o.temperature = 2.5;
    o.seed = 11;
    const System<3> system = make_initial<3>(o);
    expect_valid(system, o);
    EXPECT_GT(smallest_relative_gap(system), 0.0);
  }
}

TEST(Initial, PolydisperseSpheresHaveTheRequestedSpread) {
  InitialOptions o;
  o.n = 4000;
  o.packing_fraction = 0.4;
  o.polydispersity = 0.1;
  o.boundary = Boundary::periodic;
  const System<3> system = make_initial<3>(o);
  expect_valid(system, o);
  double sum = 0.0, sum2 = 0.0;
  for (const Particle<3>& p : system.particles) {
    sum += p.radius;
    sum2 += p.radius * p.radius;
  }
  const double mean = sum / o.n, spread = std::sqrt(sum2 / o.n - mean * mean) / mean;
  EXPECT_NEAR(spread, 0.1, 0.005);
}

TEST(Initial, ABoxGivenFixesTheRadius) {
  InitialOptions o;
  o.n = 300;
  o.packing_fraction = 0.2;
  o.box = {20.0, 10.0, 15.0};
  const System<3> system = make_initial<3>(o);
  expect_valid(system, o);
  EXPECT_EQ(system.box.size, (Vec<3>{{20.0, 10.0, 15.0}}));
  o.box = {20.0, 10.0};
  EXPECT_THROW(make_initial<3>(o), InitialError);
  InitialOptions disks = request(10, 0.3);
  disks.box = {1, 2, 3};
  EXPECT_THROW(make_initial<2>(disks), InitialError);
}

TEST(Initial, TheSameSeedGivesTheSameSpheresBitForBit) {
  InitialOptions o = request(500, 0.3);
  o.polydispersity = 0.05;
  o.seed = 5;
  const System<3> a = make_initial<3>(o), b = make_initial<3>(o);
  EXPECT_EQ(a.particles, b.particles);
  o.seed = 6;
  EXPECT_NE(a.particles, make_initial<3>(o).particles);
}

TEST(Initial, ImpossibleSpheresAreRefused) {
  EXPECT_THROW(make_initial<3>(request(10, 0.75)), InitialError);
  InitialOptions random_placement = request(1000, 0.5);
  random_placement.placement = Placement::random;
  EXPECT_THROW(make_initial<3>(random_placement), InitialError);
  // With walls the outer layer keeps R from the walls: a cube at close packing has no room.
  EXPECT_THROW(make_initial<3>(request(500, kClosePackingSpheres)), InitialError);
  // Two spheres in a small box jam random placement; automatic placement takes the lattice.
  const System<3> pair = make_initial<3>(request(2, 0.2));
  EXPECT_EQ(find_violation(pair, 0.0), std::nullopt);
}

TEST(Initial, SpheresWrittenInTheClassicFormatReadBackExactly) {
  InitialOptions polydisperse = request(200, 0.3);
  polydisperse.polydispersity = 0.1;
  polydisperse.seed = 3;
  const System<3> system = make_initial<3>(polydisperse);
  std::stringstream file;
  write_classic(file, system, 0.5);
  const ClassicInput<3> read = read_classic<3>(file, "spheres.txt");
  EXPECT_EQ(read.system.box.size, system.box.size);
  ASSERT_EQ(read.system.size(), system.size());
  for (std::size_t i = 0; i < system.size(); ++i) {
    EXPECT_EQ(read.system.particles[i].position, system.particles[i].position);
    EXPECT_EQ(read.system.particles[i].velocity, system.particles[i].velocity);
    EXPECT_EQ(read.system.particles[i].radius, system.particles[i].radius);
  }
}

TEST(Initial, DenseDisksInAPeriodicBoxKeepApart) {
  const InitialOptions o = request(400, 0.85, Boundary::periodic);
  const System<2> system = make_initial<2>(o);
  expect_valid(system, o);
  EXPECT_GT(smallest_relative_gap(system), 0.0);
}

}  // namespace
}  // namespace carom
