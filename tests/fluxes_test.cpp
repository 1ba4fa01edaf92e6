// The momentum and energy fluxes (fluxes.hpp): the pure pieces against hand-computed values, and
// whole runs against what the fluxes must add up to (the virial, the kinetic energy, isotropy),
// resumed from checkpoints bit for bit.
#include "carom/core/fluxes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <variant>

#include "carom/core/observables.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/checkpoint.hpp"

namespace carom {
namespace {

template <std::size_t D>
System<D> gas(std::uint64_t n, double phi, std::uint64_t seed = 1) {
  InitialOptions o;
  o.n = n;
  o.packing_fraction = phi;
  o.seed = seed;
  o.boundary = Boundary::periodic;
  return make_initial<D>(o);
}

TEST(Fluxes, SymmetricOuterProductsTouchTheComponentsADimensionHas) {
  SymmetricTensor t2{};
  add_symmetric_outer<2>(t2, Vec<2>{1.0, 2.0}, Vec<2>{3.0, 5.0});
  EXPECT_EQ(t2, (SymmetricTensor{3.0, 10.0, 0.0, 5.5, 0.0, 0.0}));
  SymmetricTensor t3{1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
  add_symmetric_outer<3>(t3, Vec<3>{1.0, 2.0, 4.0}, Vec<3>{3.0, 5.0, 7.0});
  EXPECT_EQ(t3, (SymmetricTensor{4.0, 11.0, 29.0, 6.5, 10.5, 18.0}));
  EXPECT_EQ(tensor_components<2>().size(), 3u);
  EXPECT_EQ(tensor_components<3>().size(), 6u);
}

TEST(Fluxes, AHeadOnCollisionTransfersMomentumAlongItsContact) {
  // Two unit masses meet head on along x: each reverses; the first (on the right, moving left)
  // receives +2 in x, at stored time 3.
  Event event;
  event.time = 1003.0;
  event.first = 0;
  event.partner = 1;
  event.momentum = {2.0, 0.0, 0.0};
  event.contact = {1.0, 0.0, 0.0};
  Fluxes f;
  f.stress_rate = {1.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  f.stored = 1.0;
  f.heat = true;
  f.add_event<2>(event, 3.0, 1.0, Vec<2>{1.0, 0.5}, 1.0, Vec<2>{-1.0, 0.5});
  EXPECT_EQ(f.time, 1003.0);
  EXPECT_EQ(f.stored, 3.0);
  EXPECT_EQ(f.kinetic_stress, (SymmetricTensor{2.0, 0.0, 0.0, 0.0, 0.0, 0.0}));  // 1 for 2
  // r dp: the virial 2 in xx only.
  EXPECT_EQ(f.collisional_stress, (SymmetricTensor{2.0, 0.0, 0.0, 0.0, 0.0, 0.0}));
  // Reversing vx changes no m vx vx; m vx vy goes up by 1 for the first and down by 1 for the
  // partner: the momentum flux they carry is the same.
  EXPECT_EQ(f.stress_rate, (SymmetricTensor{1.0, 0.0, 0.0, 0.0, 0.0, 0.0}));
  // Energies unchanged: no heat crosses the contact; the carried heat flips with vx for both.
  EXPECT_EQ(f.collisional_heat, (std::array<double, 3>{0.0, 0.0, 0.0}));
  EXPECT_EQ(f.heat_rate, (std::array<double, 3>{0.0, 0.0, 0.0}));
}

TEST(Fluxes, IntegralsGrowAtTheirRatesBetweenEvents) {
  Fluxes f;
  f.stress_rate = {1.0, 2.0, 0.0, 0.5, 0.0, 0.0};
  f.heat_rate = {0.25, 0.0, 0.0};
  // Stored times step the integrals (absolute 1001 is stored 1 here): absolute ones only label.
  f.since = f.time = 1001.0;
  f.stored = 1.0;
  const Fluxes later = f.advanced(1003.0, 3.0);
  EXPECT_EQ(later.kinetic_stress, (SymmetricTensor{2.0, 4.0, 0.0, 1.0, 0.0, 0.0}));
  EXPECT_EQ(later.kinetic_heat, (std::array<double, 3>{0.5, 0.0, 0.0}));
  EXPECT_EQ(later.time, 1003.0);
  EXPECT_EQ(later.stored, 3.0);
  const Fluxes d = flux_difference(later.advanced(1004.0, 4.0), later);
  EXPECT_EQ(d.since, 1003.0);
  EXPECT_EQ(d.kinetic_stress, (SymmetricTensor{1.0, 2.0, 0.0, 0.5, 0.0, 0.0}));
}

// A run's fluxes against the counts kept independently: the trace of the collisional stress is
// the virial, the trace of the kinetic one twice the kinetic energy times the time.
template <std::size_t D>
void expect_fluxes_add_up(std::uint64_t n, double phi, double end) {
  Simulation<D> simulation(gas<D>(n, phi), {{Rule::elastic}});
  simulation.run_until(end);
  const Fluxes f = *simulation.current_counts().fluxes;
  double collisional = 0.0, kinetic = 0.0;
  for (std::size_t k = 0; k < D; ++k) {
    collisional += f.collisional_stress[k];
    kinetic += f.kinetic_stress[k];
  }
  EXPECT_NEAR(collisional / simulation.counts().virial, 1.0, 1e-12);
  EXPECT_NEAR(kinetic / (2.0 * kinetic_energy(simulation.state()) * end), 1.0, 1e-12);
  // Isotropic: the diagonal components agree, the off-diagonal ones are near zero (each within
  // a few percent of the pressure over this many collisions).
  const Observables<D> o = simulation.observables();
  ASSERT_TRUE(o.pressure_tensor.has_value());
  const SymmetricTensor& p = *o.pressure_tensor;
  for (std::size_t k = 0; k < D; ++k) EXPECT_NEAR(p[k] / o.pressure, 1.0, 0.03) << k;
  for (std::size_t c = 3; c < (D == 2 ? 4u : 6u); ++c)
    EXPECT_NEAR(p[c] / o.pressure, 0.0, 0.03) << c;
  // The trace over D is the pressure, but for the kinetic part: sum m v v = 2 KE over D (N - 1)
  // degrees of freedom, against N kT in the pressure.
  double trace = 0.0;
  for (std::size_t k = 0; k < D; ++k) trace += p[k] / D;
  const double volume = box_volume(simulation.state().box);
  EXPECT_NEAR(trace, o.pressure - o.temperature / volume, 1e-9 * o.pressure);
}

TEST(Fluxes, DisksAddUpToTheVirialAndTheKineticEnergy) {
  expect_fluxes_add_up<2>(400, 0.5, 40.0);
}

TEST(Fluxes, SpheresAddUpToTheVirialAndTheKineticEnergy) {
  expect_fluxes_add_up<3>(500, 0.4, 20.0);
}

TEST(Fluxes, WallsGiveNoCollisionalStress) {
  InitialOptions o;
  o.n = 100;
  o.packing_fraction = 0.3;
  o.boundary = Boundary::walls;
  Simulation<2> simulation(make_initial<2>(o), {{Rule::elastic}});
  simulation.run_until(20.0);
  ASSERT_GT(simulation.counts().wall_collisions, 0u);
  double collisional = 0.0;
  for (std::size_t k = 0; k < 2; ++k)
    collisional += simulation.counts().fluxes->collisional_stress[k];
  EXPECT_NEAR(collisional / simulation.counts().virial, 1.0, 1e-12);
}

// Stopped, checkpointed and resumed, a run keeps the fluxes of one never stopped, bit for bit.
template <std::size_t D>
void expect_resumed_fluxes_equal(std::uint64_t n, double phi) {
  Simulation<D> whole(gas<D>(n, phi), {{Rule::elastic}});
  whole.measure_from(2.0);
  whole.run_until(10.0);

  Simulation<D> first(gas<D>(n, phi), {{Rule::elastic}});
  first.measure_from(2.0);
  first.run_until(4.5);
  std::stringstream saved;
  write_checkpoint(saved, first.checkpoint("test"));
  Simulation<D> resumed(std::get<Checkpoint<D>>(read_checkpoint(saved, "saved")));
  ASSERT_TRUE(resumed.tracks_fluxes());
  resumed.run_until(10.0);
  EXPECT_EQ(resumed.counts(), whole.counts());
  EXPECT_EQ(resumed.measurement(), whole.measurement());
  EXPECT_EQ(*resumed.observables().pressure_tensor, *whole.observables().pressure_tensor);
}

TEST(Fluxes, ResumedDisksKeepTheirFluxesBitForBit) {
  expect_resumed_fluxes_equal<2>(200, 0.6);
}

TEST(Fluxes, ResumedSpheresKeepTheirFluxesBitForBit) {
  expect_resumed_fluxes_equal<3>(200, 0.4);
}

template <std::size_t D>
Fluxes fluxes_of_run(EngineKind engine) {
  Simulation<D> simulation(gas<D>(100, 0.45, 7), {{Rule::elastic}, engine});
  simulation.run_until(3.0);
  return *simulation.counts().fluxes;
}

TEST(Fluxes, BothEnginesGiveTheSameFluxes) {
  EXPECT_EQ(fluxes_of_run<2>(EngineKind::fast), fluxes_of_run<2>(EngineKind::reference));
  EXPECT_EQ(fluxes_of_run<3>(EngineKind::fast), fluxes_of_run<3>(EngineKind::reference));
}

}  // namespace
}  // namespace carom
