// Physics checked against theory: conservation laws, the Maxwell-Boltzmann distribution, the
// hard-disk equation of state and the collision-rate identity; and the start configurations.
#include "carom/observables.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "carom/initial.hpp"
#include "carom/overlap.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

System<2> gas(std::uint64_t n, double phi, std::uint64_t seed = 1) {
  InitialOptions o;
  o.n = n;
  o.packing_fraction = phi;
  o.seed = seed;
  o.boundary = Boundary::periodic;
  return make_initial(o);
}

// Henderson's equation of state for hard disks.
double henderson(double eta) {
  return (1 + eta * eta / 8) / ((1 - eta) * (1 - eta)) -
         0.043 * std::pow(eta, 4) / std::pow(1 - eta, 3);
}

TEST(Initial, HitsThePackingFractionWithZeroMomentumAndExactTemperature) {
  for (double phi : {0.1, 0.45, 0.8}) {
    for (Boundary b : {Boundary::walls, Boundary::periodic}) {
      InitialOptions o;
      o.n = 500;
      o.packing_fraction = phi;
      o.temperature = 2.5;
      o.boundary = b;
      const System<2> s = make_initial(o);
      ASSERT_EQ(s.particles.size(), 500u);
      EXPECT_NEAR(packing_fraction(s), phi, 1e-12);
      EXPECT_NEAR(momentum(s)[0], 0.0, 1e-10);
      EXPECT_NEAR(momentum(s)[1], 0.0, 1e-10);
      EXPECT_NEAR(2.0 * kinetic_energy(s) / (2.0 * 500), 2.5, 1e-12);
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
  const System<2> a = make_initial(o), b = make_initial(o);
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

TEST(Initial, RefusesTheImpossible) {
  InitialOptions o;
  o.n = 10;
  o.packing_fraction = 0.95;
  EXPECT_THROW(make_initial(o), InitialError);
  o.packing_fraction = 0.7;
  o.placement = Placement::random;
  o.n = 400;
  EXPECT_THROW(make_initial(o), InitialError);
}

TEST(Physics, ElasticRunsConserveEnergyAndMomentum) {
  auto engine = make_engine(EngineKind::fast, gas(400, 0.5), {Rule::elastic});
  const double e0 = kinetic_energy(engine->system());
  run(*engine, 750.0);
  ASSERT_GT(engine->counts().pair_collisions, 1000000u);
  EXPECT_NEAR(kinetic_energy(engine->system()) / e0, 1.0, 1e-12);
  EXPECT_NEAR(momentum(engine->system())[0], 0.0, 1e-11);
  EXPECT_NEAR(momentum(engine->system())[1], 0.0, 1e-11);
  EXPECT_FALSE(find_pair_overlap(engine->system(), engine->time()).has_value());
}

TEST(Physics, VelocitiesRelaxToMaxwellBoltzmann) {
  // Start far from equilibrium: every disk at the same speed.
  System<2> s = gas(2000, 0.3, 4);
  for (Particle<2>& p : s.particles) {
    p.velocity *= 1.0 / std::sqrt(norm2(p.velocity));
  }
  auto engine = make_engine(EngineKind::fast, s, {Rule::elastic});
  const auto ratio = [&] {
    double v2 = 0.0, v4 = 0.0;
    for (const auto& p : engine->system().particles) {
      v2 += norm2(p.velocity);
      v4 += norm2(p.velocity) * norm2(p.velocity);
    }
    const double n = static_cast<double>(engine->system().particles.size());
    return (v4 / n) / ((v2 / n) * (v2 / n));
  };
  EXPECT_NEAR(ratio(), 1.0, 1e-9);
  run(*engine, 40.0);
  EXPECT_NEAR(ratio(), 2.0, 0.12);  // the 2D Maxwell-Boltzmann value
}

TEST(Physics, PressureMatchesTheEquationOfStateAndTheCollisionRateIdentity) {
  for (double eta : {0.3, 0.5}) {
    auto engine = make_engine(EngineKind::fast, gas(1024, eta, 2), {Rule::elastic});
    run(*engine, 20.0);  // equilibrate
    engine->reset_counts();
    const double e0 = kinetic_energy(engine->system());
    run(*engine, 80.0);
    const Observables<2> o = measure(*engine, 60.0, e0);
    EXPECT_NEAR(o.compressibility_factor / henderson(eta), 1.0, 0.02) << eta;
    // Z - 1 = omega sigma sqrt(pi m / kT) / 4, sigma = 1, m = 1.
    const double predicted = o.collision_rate * std::sqrt(std::numbers::pi / o.temperature) / 4.0;
    EXPECT_NEAR((o.compressibility_factor - 1.0) / predicted, 1.0, 0.02) << eta;
    EXPECT_NEAR(o.mean_free_time * o.collision_rate, 1.0, 1e-12);
  }
}

TEST(Physics, InelasticGasCoolsWithoutCollapse) {
  auto engine = make_engine(EngineKind::fast, gas(1000, 0.3, 3), {Rule::elastic, 0.8, 1e-5});
  const double e0 = kinetic_energy(engine->system());
  run(*engine, 50.0);
  const double e1 = kinetic_energy(engine->system());
  EXPECT_LT(e1, 0.5 * e0);
  EXPECT_GT(e1, 0.0);
  EXPECT_GT(engine->counts().pair_collisions, 10000u);
  EXPECT_NEAR(momentum(engine->system())[0], 0.0, 1e-9);
}

TEST(Physics, WallPressureCountsMomentumGivenToTheWalls) {
  // One disk bouncing between two walls along x: momentum 2 m v per hit, (L - 2R) / v apart.
  const System<2> s = testing::boxed({10, 10}, {testing::disk({5, 5}, {2, 0}, 1)});
  auto engine = make_engine(EngineKind::fast, s, {Rule::swap});
  run(*engine, 40.0);  // hits at 2, 6, ..., 38: 10 hits
  const Observables<2> o = measure(*engine, 40.0, 2.0);
  EXPECT_EQ(engine->counts().wall_collisions, 10u);
  EXPECT_DOUBLE_EQ(o.wall_pressure, 10 * 4.0 / (40.0 * 40.0));
  EXPECT_EQ(o.collision_rate, 0.0);
}

}  // namespace
}  // namespace carom
