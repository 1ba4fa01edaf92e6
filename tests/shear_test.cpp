// Lees-Edwards shear (Box::sheared): the images' geometry against explicit images, the wrap, the
// pressure tensor relative to the streaming profile against the viscous heating it must account
// for exactly, and whole runs in both engines and across checkpoints, with and without a
// thermostat. (Event-by-event cross-checks against the reference engine: cross_check_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <variant>

#include "carom/core/fluxes.hpp"
#include "carom/core/observables.hpp"
#include "carom/engine/engine.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/checkpoint.hpp"

namespace carom {
namespace {

template <std::size_t D>
System<D> sheared_gas(std::uint64_t n, double phi, double rate, std::uint64_t seed = 1) {
  InitialOptions o;
  o.n = n;
  o.packing_fraction = phi;
  o.seed = seed;
  o.boundary = Boundary::periodic;
  System<D> system = make_initial<D>(o);
  system.box.shear_rate = rate;
  return system;
}

Box<2> sheared_box() {
  Box<2> box{{10.0, 8.0}, Boundary::periodic};
  box.shear_rate = 0.3;
  box.shear_offset = 2.5;
  return box;
}

TEST(Shear, TheImagesSlideAlongXAtTheShearRateTimesLy) {
  const Box<2> box = sheared_box();
  EXPECT_EQ(box.sheared_shift(0.0), 2.5);
  EXPECT_DOUBLE_EQ(box.sheared_shift(2.0), 2.5 + 0.3 * 8.0 * 2.0);
  EXPECT_DOUBLE_EQ(box.image_speed(), 2.4);
  EXPECT_DOUBLE_EQ(box.stream_velocity(8.0) - box.stream_velocity(0.0), 2.4);
  // The image one box up of a particle at the origin sits at (shift, Ly) at stored time 1.
  const Vec<2> cells = sheared_cells(Vec<2>{-(2.5 + 2.4), -8.0}, box, 1.0);
  EXPECT_EQ(cells, (Vec<2>{0.0, -1.0}));
  EXPECT_EQ(sheared_offset(Vec<2>{0.0, 1.0}, box, 1.0), (Vec<2>{4.9, 8.0}));
}

TEST(Shear, ContactTimesAreThoseWithTheMovingImage) {
  const Box<2> box = sheared_box();
  // a near the top edge, b near the bottom: a meets b's image one box up, which moves with b's
  // velocity plus the images' speed.
  const Particle<2> a{{3.0, 7.5}, {0.1, 0.2}, 0.5, 0.5};
  const Particle<2> b{{-1.9, 0.4}, {-0.3, -0.1}, 0.2, 0.5};
  const Vec<2> cells = sheared_cells(position_at(a, 0.5) - position_at(b, 0.5), box, 0.5);
  ASSERT_EQ(cells[1], 1.0);  // a sees b's image one box up
  const double t = sheared_contact_time(a, b, cells, box);
  ASSERT_NE(t, kNever);
  Particle<2> image = b;
  image.position += sheared_offset(cells, box, b.time);
  image.velocity[0] += box.image_speed();
  EXPECT_NEAR(t, contact_time(a, image), 1e-12);
  // Both ways round, bit for bit.
  EXPECT_EQ(t, sheared_contact_time(b, a, -1.0 * cells, box));
  // They touch then, through that image.
  const Vec<2> apart = position_at(a, t) - position_at(b, t) - sheared_offset(cells, box, t);
  EXPECT_NEAR(std::sqrt(norm2(apart)), 1.0, 1e-12);
  // Without the images' motion (a box not sheared) the time would differ.
  EXPECT_GT(std::abs(t - contact_time(a, b, sheared_offset(cells, box, 0.5))), 1e-3);
}

TEST(Shear, WrappingAcrossYMovesAParticleToItsImage) {
  const Box<2> box = sheared_box();
  Particle<2> p{{4.0, 8.5}, {1.0, 0.5}, 2.0, 0.5};
  const Vec<2> peculiar = peculiar_velocity(p, box);
  std::array<std::int32_t, 3> image{};
  wrap(p, box, image);
  EXPECT_DOUBLE_EQ(p.position[1], 0.5);
  EXPECT_DOUBLE_EQ(p.position[0], 4.0 - box.sheared_shift(2.0) + 10.0);
  EXPECT_DOUBLE_EQ(p.velocity[0], 1.0 - box.image_speed());
  EXPECT_EQ(image[1], 1);
  EXPECT_EQ(image[0], -1);
  // The velocity relative to the streaming profile is the image's too.
  EXPECT_NEAR(peculiar_velocity(p, box)[0], peculiar[0], 1e-14);
  EXPECT_EQ(peculiar_velocity(p, box)[1], peculiar[1]);
  // Going the other way, the wrap undoes itself.
  Particle<2> q{{4.0, -0.5}, {1.0, -0.5}, 2.0, 0.5};
  wrap(q, box, image);
  EXPECT_DOUBLE_EQ(q.position[1], 7.5);
  EXPECT_DOUBLE_EQ(q.velocity[0], 1.0 + box.image_speed());
}

TEST(Shear, BoxesThatCannotShearAreRefused) {
  System<2> walls = sheared_gas<2>(50, 0.2, 0.5);
  walls.box.boundary = Boundary::walls;
  EXPECT_THROW(make_engine(EngineKind::fast, walls, {Rule::elastic}), std::invalid_argument);
  const System<2> gas = sheared_gas<2>(50, 0.2, 0.5);
  EXPECT_THROW(make_engine(EngineKind::reference, gas, {Rule::swap}), std::invalid_argument);
  EXPECT_THROW(make_engine(EngineKind::fast, gas, {Rule::elastic}, Growth{0.1, 1.0}),
               std::invalid_argument);
}

// The pressure tensor's integrals (kinetic relative to the streaming profile, and collisional)
// against Simpson's rule between events on the synchronised states, exact for the quadratic the
// kinetic rate is between events.
template <std::size_t D>
void expect_sheared_kinetic_stress_integrates_exactly(double rate) {
  auto engine = make_engine(EngineKind::fast, sheared_gas<D>(40, 0.2, rate, 5), {Rule::elastic});
  Fluxes fluxes = fluxes_of(engine->system(), 0.0, 0.0, false);
  SymmetricTensor simpson{};
  const auto kinetic_rate = [](const System<D>& system, double t) {
    SymmetricTensor r{};
    for (const Particle<D>& p : synchronised(system, t)) {
      const Vec<D> c = peculiar_velocity(p, system.box);
      add_symmetric_outer<D>(r, c, c);  // masses 1
    }
    return r;
  };
  double last = 0.0;
  for (int events = 0; events < 400; ++events) {
    const System<D> before = engine->system();
    const auto event = engine->step(kNever);
    ASSERT_TRUE(event);
    const double t = engine->stored_time();
    const SymmetricTensor r0 = kinetic_rate(before, last),
                          r1 = kinetic_rate(before, (last + t) / 2), r2 = kinetic_rate(before, t);
    for (std::size_t c = 0; c < 6; ++c)
      simpson[c] += (t - last) / 6.0 * (r0[c] + 4 * r1[c] + r2[c]);
    const System<D>& after = engine->system();
    const auto partner = static_cast<std::size_t>(event->partner);
    fluxes.add_event<D>(*event, t, 1.0, flux_velocity(after.particles[event->first], after.box),
                        1.0, flux_velocity(after.particles[partner], after.box));
    last = t;
  }
  for (const std::size_t c : tensor_components<D>()) {
    EXPECT_NEAR(fluxes.kinetic_stress[c], simpson[c], 1e-9 * (1.0 + std::abs(simpson[c])))
        << "component " << kTensorComponents[c];
  }
}

TEST(Shear, TheKineticStressIsIntegratedExactlyRelativeToTheProfile) {
  expect_sheared_kinetic_stress_integrates_exactly<2>(0.7);
  expect_sheared_kinetic_stress_integrates_exactly<3>(-1.1);
}

// The viscous heating: the energy relative to the streaming profile grows by exactly the work
// the shear does, -rate times the integral of V pxy (kinetic and collisional), while the momentum
// relative to the profile is conserved.
template <std::size_t D>
void expect_the_heating_balances_the_stress(double rate) {
  Simulation<D> simulation(sheared_gas<D>(200, 0.3, rate), {{Rule::elastic}});
  const auto peculiar_energy = [](const System<D>& system) {
    double energy = 0.0;
    for (std::size_t i = 0; i < system.size(); ++i) {
      energy +=
          0.5 * system.records[i].mass * norm2(peculiar_velocity(system.particles[i], system.box));
    }
    return energy;
  };
  const auto now = [&simulation] {  // every particle at the run's time
    System<D> system = simulation.state();
    system.particles = simulation.snapshot();
    return system;
  };
  const double before = peculiar_energy(now());
  const Vec<D> momentum_before = peculiar_momentum(now());
  simulation.run_until(20.0);
  const System<D> after = now();
  const double work = -rate * simulation.current_counts().fluxes->stress_moment()[3];
  EXPECT_GT(work, 0.0);
  EXPECT_NEAR(peculiar_energy(after) - before, work, 1e-9 * before);
  const Vec<D> momentum_after = peculiar_momentum(after);
  for (std::size_t k = 0; k < D; ++k) EXPECT_NEAR(momentum_after[k], momentum_before[k], 1e-9);
  EXPECT_GT(kinetic_temperature(after), 1.01);  // it heats up
}

TEST(Shear, TheViscousHeatingIsTheWorkOfTheShearStress) {
  expect_the_heating_balances_the_stress<2>(0.5);
  expect_the_heating_balances_the_stress<3>(-0.4);
}

// The same sheared run in both engines, and in pieces through a checkpoint (which carries the
// images' offset), bit for bit; a thermostat holds the temperature relative to the profile.
template <std::size_t D>
void expect_sheared_runs_agree(double rate, bool thermostat, bool andersen = false) {
  const auto make = [&](EngineKind engine) {
    Settings settings{{Rule::elastic}, engine};
    if (thermostat) settings.thermostat = {ThermostatKind::rescale, 1.0, 0.25, 0.0, 1};
    if (andersen) settings.thermostat = {ThermostatKind::andersen, 1.0, 0.0, 0.5, 2};
    return Simulation<D>(sheared_gas<D>(D == 2 ? 150 : 100, 0.35, rate), settings);
  };
  Simulation<D> fast = make(EngineKind::fast), reference = make(EngineKind::reference);
  fast.run_until(6.0);
  reference.run_until(6.0);
  EXPECT_EQ(fast.counts(), reference.counts());
  EXPECT_EQ(fast.snapshot(), reference.snapshot());
  // The thermostat's interventions move the epoch, and with it the images' offset.
  if (thermostat) {
    EXPECT_NE(fast.state().box.shear_offset, 0.0);
  }

  Simulation<D> first = make(EngineKind::fast);
  first.run_until(2.3);
  std::stringstream saved;
  write_checkpoint(saved, first.checkpoint("test"));
  Simulation<D> resumed(std::get<Checkpoint<D>>(read_checkpoint(saved, "saved")));
  EXPECT_EQ(resumed.state().box.shear_rate, rate);
  resumed.run_until(6.0);
  EXPECT_EQ(resumed.counts(), fast.counts());
  EXPECT_EQ(resumed.snapshot(), fast.snapshot());
  if (thermostat) {  // it acted at t = 6 last
    System<D> system = fast.state();
    system.particles = fast.snapshot();
    EXPECT_NEAR(kinetic_temperature(system), 1.0, 1e-12);
  }
}

TEST(Shear, ShearedDisksAgreeInBothEnginesAndAcrossCheckpoints) {
  expect_sheared_runs_agree<2>(0.8, false);
  expect_sheared_runs_agree<2>(-0.3, true);
}

TEST(Shear, ShearedSpheresAgreeInBothEnginesAndAcrossCheckpoints) {
  expect_sheared_runs_agree<3>(0.5, true);
  expect_sheared_runs_agree<3>(1.5, false);
  expect_sheared_runs_agree<3>(0.7, false, true);  // Andersen's resets as events
}

// Where every particle would be at the run's time had the box not wrapped it: position + image x
// sides, plus image_y x the images' shift along x (see ParticleRecord::image).
template <std::size_t D>
std::vector<Vec<D>> unwrapped_positions(const Simulation<D>& simulation) {
  const System<D>& system = simulation.state();
  const double t = simulation.stored_time();
  std::vector<Vec<D>> unwrapped;
  for (std::size_t i = 0; i < system.size(); ++i) {
    std::array<std::int32_t, 3> image = system.records[i].image;
    Vec<D> u = synchronised(system.particles[i], system.box, t, image).position;
    for (std::size_t k = 0; k < D; ++k) u[k] += image[k] * system.box.size[k];
    u[0] += image[1] * shown_shift(system.box, t);
    unwrapped.push_back(u);
  }
  return unwrapped;
}

// Image flags count real crossings only: the unwrapped positions of a sheared run never jump,
// along any axis, through collisions across the sliding images, crossings of the sheared
// boundary, the epoch's moves (which reduce the stored shift by whole sides) and a thermostat's
// interventions. Each particle's unwrapped motion between two looks dt apart is bounded by its
// flight at the largest lab speed of the run (the peculiar speed plus the stream's at the
// farthest layer any particle reached), which the old flags broke by whole box sides.
template <std::size_t D>
void expect_unwrapped_motion_is_continuous(double rate, bool thermostat) {
  Settings settings{{Rule::elastic}, EngineKind::fast};
  if (thermostat) settings.thermostat = {ThermostatKind::rescale, 1.0, 0.25, 0.0, 1};
  System<D> gas = sheared_gas<D>(D == 2 ? 200 : 150, 0.4, rate);
  const double height = gas.box.size[1];
  Simulation<D> simulation(std::move(gas), settings);
  std::vector<Vec<D>> before = unwrapped_positions(simulation);
  const double dt = 0.02;
  double farthest = 0.0;  // the most layers any particle has moved along y
  for (int step = 1; step <= 500; ++step) {
    double fastest = 0.0;
    for (const Particle<D>& p : simulation.snapshot()) {
      fastest = std::max(fastest, std::sqrt(norm2(peculiar_velocity(p, simulation.state().box))));
    }
    simulation.run_until(step * dt);
    const std::vector<Vec<D>> after = unwrapped_positions(simulation);
    const double stream = std::abs(rate) * height * (farthest + 1.0);
    const double reach = 3.0 * (fastest + 1.0 + stream) * dt;
    for (std::size_t i = 0; i < after.size(); ++i) {
      for (std::size_t k = 0; k < D; ++k) {
        ASSERT_LE(std::abs(after[i][k] - before[i][k]), reach)
            << "particle " << i << " axis " << k << " at t = " << step * dt;
      }
      farthest = std::max(farthest, std::ceil(std::abs(after[i][1]) / height));
    }
    before = after;
  }
  // The events crossed the sheared boundary many times, and the flags saw real crossings.
  int crossed = 0;
  for (const ParticleRecord& r : simulation.state().records) crossed += r.image[1] != 0;
  EXPECT_GT(crossed, 0);
}

TEST(Shear, ImageFlagsCountRealCrossingsOnly) {
  expect_unwrapped_motion_is_continuous<2>(1e-9, false);
  expect_unwrapped_motion_is_continuous<2>(0.6, false);
  expect_unwrapped_motion_is_continuous<2>(-0.4, true);
  expect_unwrapped_motion_is_continuous<3>(0.5, false);
  expect_unwrapped_motion_is_continuous<3>(0.8, true);
}

// A collision through a sliding image moves no flag of either particle: two disks that meet
// across the sheared boundary without crossing it keep their flags at 0.
TEST(Shear, ACollisionThroughTheSlidingImagesMovesNoFlag) {
  System<2> system;
  // The image of `high` one box down starts at x = 2.5 - 7.5 = 5 - 10 and slides by -3 t.
  system.box = {{10.0, 10.0}, Boundary::periodic, 0.3, 7.5};
  Particle<2> low{{5.0, 0.6}, {0.0, -1.0}, 0.0, 0.5}, high{{2.5, 9.4}, {0.0, 1.0}, 0.0, 0.5};
  system.particles = {low, high};
  system.records.resize(2);
  Simulation<2> simulation(std::move(system), {{Rule::elastic}});
  simulation.run_until(0.2);  // they touch at t = 0.169, y = 0.43 and 9.57: neither crossed
  ASSERT_EQ(simulation.counts().pair_collisions, 1u);
  for (const ParticleRecord& r : simulation.state().records) {
    EXPECT_EQ(r.image, (std::array<std::int32_t, 3>{0, 0, 0}));
  }
}

}  // namespace
}  // namespace carom
