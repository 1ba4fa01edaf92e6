// Thermostats (thermostat.hpp): the velocity changes alone, then runs that hold a temperature in
// both engines bit for bit, in pieces and across checkpoints.
#include "carom/core/thermostat.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <variant>

#include "carom/core/fluxes.hpp"
#include "carom/core/observables.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/invariant_check.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/checkpoint.hpp"

namespace carom {
namespace {

template <std::size_t D>
System<D> gas(std::uint64_t n, double phi, Boundary boundary = Boundary::periodic) {
  InitialOptions o;
  o.n = n;
  o.packing_fraction = phi;
  o.seed = 4;
  o.boundary = boundary;
  return make_initial<D>(o);
}

TEST(Thermostat, RescalingSetsTheTemperatureAndKeepsTheCentreOfMassMoving) {
  System<3> system = gas<3>(100, 0.2);
  for (Particle<3>& p : system.particles) p.velocity[0] += 0.5;  // a drift
  const Vec<3> drift = momentum(system);
  rescale_velocities(system, 2.5);
  EXPECT_NEAR(kinetic_temperature(system), 2.5, 1e-12);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(momentum(system)[k], drift[k], 1e-12);
}

TEST(Thermostat, AndersenResetsTheExpectedShareFromItsOwnStream) {
  System<2> system = gas<2>(4000, 0.3);
  const Thermostat t{ThermostatKind::andersen, 3.0, 0.5, 0.2, 9};  // p = 1 - exp(-0.1)
  pcg32 rng(t.seed), same(t.seed);
  System<2> copy = system;
  const std::size_t resets = andersen_resets(system, t, rng);
  EXPECT_NEAR(static_cast<double>(resets) / 4000.0, -std::expm1(-0.1), 0.015);
  EXPECT_EQ(andersen_resets(copy, t, same), resets);
  EXPECT_EQ(copy.particles, system.particles);
  // With a rate far above 1 / every, every particle is drawn anew: the temperature is kT's.
  const Thermostat all{ThermostatKind::andersen, 3.0, 1.0, 100.0, 9};
  EXPECT_EQ(andersen_resets(system, all, rng), 4000u);
  EXPECT_NEAR(kinetic_temperature(system), 3.0, 0.15);
}

TEST(Thermostat, BadThermostatsAreRefused) {
  EXPECT_NO_THROW(check_thermostat({}));
  EXPECT_THROW(check_thermostat({ThermostatKind::rescale, 0.0, 1.0, 0.0, 1}),
               std::invalid_argument);
  EXPECT_THROW(check_thermostat({ThermostatKind::rescale, 1.0, -1.0, 0.0, 1}),
               std::invalid_argument);
  EXPECT_THROW(check_thermostat({ThermostatKind::andersen, 1.0, 1.0, 0.0, 1}),
               std::invalid_argument);
  EXPECT_THROW(check_thermostat({ThermostatKind::rescale, NAN, 1.0, 0.0, 1}),
               std::invalid_argument);
}

TEST(Thermostat, RescalingHoldsAnInelasticGasAtItsTemperature) {
  Settings settings{{Rule::elastic, 0.8}};
  settings.thermostat = {ThermostatKind::rescale, 1.5, 0.25, 0.0, 1};
  Simulation<2> simulation(gas<2>(300, 0.3), settings);
  for (double t = 0.25; t <= 5.0; t += 0.25) {
    simulation.run_until(t);
    // Just after each instant the temperature is kT, however much the gas cooled in between.
    EXPECT_NEAR(kinetic_temperature(simulation.state()), 1.5, 1e-12) << t;
  }
  ASSERT_GT(simulation.counts().pair_collisions, 1000u);
  // Between instants it cools (e = 0.8): halfway it is below kT.
  simulation.run_until(5.125);
  EXPECT_LT(kinetic_temperature(simulation.state()), 1.5);
}

// The kinetic temperature of a run sampled every 0.5 from `from` to `to`, averaged.
double mean_temperature_after(Simulation<2>& simulation, double from, double to) {
  double sum = 0.0;
  int samples = 0;
  for (double t = 0.5; t <= to; t += 0.5) {
    simulation.run_until(t);
    if (t < from) continue;
    sum += kinetic_temperature(simulation.state());
    ++samples;
  }
  return sum / samples;
}

TEST(Thermostat, AndersenBringsAGasToItsTemperatureAndHoldsIt) {
  // Started at kT = 1, held at 2: after a few 1 / rate the temperature fluctuates about 2.
  Settings settings{{Rule::elastic}};
  settings.thermostat = {ThermostatKind::andersen, 2.0, 0.05, 1.0, 5};
  Simulation<2> simulation(gas<2>(500, 0.3), settings);
  // kT over 500 disks fluctuates by about 2 / sqrt(500) = 4.5 %; the mean of 49 samples less.
  EXPECT_NEAR(mean_temperature_after(simulation, 6.0, 30.0), 2.0, 0.04);
}

// The same run in both engines, and in pieces through a checkpoint, bit for bit.
template <std::size_t D>
void expect_thermostatted_runs_agree(const Thermostat& thermostat, double phi,
                                     Boundary boundary = Boundary::periodic) {
  const auto make = [&](EngineKind engine) {
    Settings settings{{Rule::elastic}, engine};
    settings.thermostat = thermostat;
    return Simulation<D>(gas<D>(150, phi, boundary), settings);
  };
  Simulation<D> fast = make(EngineKind::fast), reference = make(EngineKind::reference);
  fast.run_until(3.0);
  reference.run_until(3.0);
  EXPECT_EQ(fast.counts(), reference.counts());
  EXPECT_EQ(fast.snapshot(), reference.snapshot());

  Simulation<D> first = make(EngineKind::fast);
  first.run_until(1.3);
  std::stringstream saved;
  write_checkpoint(saved, first.checkpoint("test"));
  Simulation<D> resumed(std::get<Checkpoint<D>>(read_checkpoint(saved, "saved")));
  resumed.run_until(2.0);  // an instant: the pieces end where the thermostat acts
  resumed.run_until(3.0);
  EXPECT_EQ(resumed.counts(), fast.counts());
  EXPECT_EQ(resumed.snapshot(), fast.snapshot());
  EXPECT_EQ(resumed.state().records, fast.state().records);
}

TEST(Thermostat, RescaledDisksAgreeInBothEnginesAndAcrossCheckpoints) {
  expect_thermostatted_runs_agree<2>({ThermostatKind::rescale, 2.0, 0.5, 0.0, 1}, 0.5);
}

TEST(Thermostat, AndersenSpheresAgreeInBothEnginesAndAcrossCheckpoints) {
  expect_thermostatted_runs_agree<3>({ThermostatKind::andersen, 0.5, 0.25, 1.0, 7}, 0.35);
}

TEST(Thermostat, AndersenDisksWithWallsAgreeInBothEnginesAndAcrossCheckpoints) {
  expect_thermostatted_runs_agree<2>({ThermostatKind::andersen, 1.0, 0.2, 2.0, 3}, 0.3,
                                     Boundary::walls);
}

TEST(Thermostat, AndersenResetsAsEventsAgreeInBothEnginesAndAcrossCheckpoints) {
  // Without an interval: one particle at a time, at the events of a Poisson process.
  expect_thermostatted_runs_agree<2>({ThermostatKind::andersen, 2.0, 0.0, 1.0, 4}, 0.5);
  expect_thermostatted_runs_agree<3>({ThermostatKind::andersen, 0.5, 0.0, 2.0, 9}, 0.35);
  expect_thermostatted_runs_agree<2>({ThermostatKind::andersen, 1.0, 0.0, 0.5, 3}, 0.2);
  expect_thermostatted_runs_agree<2>({ThermostatKind::andersen, 1.5, 0.0, 1.0, 6}, 0.3,
                                     Boundary::walls);
}

TEST(Thermostat, AndersenResetsAsEventsComeAtTheirRateAndHoldTheTemperature) {
  Settings settings{{Rule::elastic}};
  settings.thermostat = {ThermostatKind::andersen, 2.0, 0.0, 1.0, 5};
  Simulation<2> simulation(gas<2>(500, 0.3), settings);
  EXPECT_NEAR(mean_temperature_after(simulation, 6.0, 30.0), 2.0, 0.04);
  // 500 particles at rate 1 for 30: 15000 resets, give or take sqrt(15000) = 122.
  const double resets = static_cast<double>(simulation.checkpoint("test").thermostat_instants);
  EXPECT_NEAR(resets, 15000.0, 4.0 * 122.0);
  // The fluxes' kinetic rates followed every reset.
  const Fluxes kept = *simulation.current_counts().fluxes;
  const Fluxes exact = fluxes_of(simulation.state(), simulation.time(), 0.0, false);
  for (const std::size_t c : tensor_components<2>()) {
    EXPECT_NEAR(kept.stress_rate[c], exact.stress_rate[c], 1e-9 * 500) << c;
  }
}

TEST(Thermostat, HeatingATinyBoxKeepsItsImagesRight) {
  // A box of a few cells, where the cell engine bounds how long predictions through one image
  // stay right by the speeds the energy allows: heating ten-thousandfold must shorten that bound.
  Settings settings{{Rule::elastic}};
  settings.thermostat = {ThermostatKind::rescale, 1e4, 0.01, 0.0, 1};
  const auto run = [&](EngineKind engine) {
    settings.engine = engine;
    Simulation<2> simulation(gas<2>(4, 0.15), settings);
    simulation.add_observer(std::make_shared<InvariantCheck<2>>(1));  // no overlap, ever
    simulation.run_until(1.0);
    return simulation.snapshot();
  };
  EXPECT_EQ(run(EngineKind::fast), run(EngineKind::reference));
}

}  // namespace
}  // namespace carom
