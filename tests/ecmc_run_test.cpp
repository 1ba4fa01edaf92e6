// Event chains as a Simulation runs them (Settings::sampler): the chains' turns reach the fluxes,
// so the pressure tensor and Z along each axis are exact; the observables are in kT = 1; a
// checkpoint holds the chain in flight and its generator, so a resumed run is the run in one.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "carom/engine/checkpoint_state.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/checkpoint.hpp"
#include "carom/io/input_error.hpp"

namespace carom {
namespace {

template <std::size_t D>
System<D> periodic_gas(std::uint64_t n, double phi) {
  InitialOptions options;
  options.n = n;
  options.packing_fraction = phi;
  options.boundary = Boundary::periodic;
  options.placement = Placement::lattice;
  options.seed = 5;
  return make_initial<D>(options);
}

Settings chains(double chain_length = 0.0) {
  Settings settings;
  settings.sampler = {SamplerKind::ecmc, chain_length, 11};
  return settings;
}

template <std::size_t D>
void expect_same_run(const Simulation<D>& a, const Simulation<D>& b) {
  ASSERT_EQ(a.counts(), b.counts());
  ASSERT_EQ(a.state().epoch, b.state().epoch);
  for (std::size_t i = 0; i < a.state().size(); ++i) {
    const Particle<D>& p = a.state().particles[i];
    const Particle<D>& q = b.state().particles[i];
    ASSERT_EQ(p.position, q.position) << i;
    ASSERT_EQ(p.velocity, q.velocity) << i;
    ASSERT_EQ(p.time, q.time) << i;
    const ParticleRecord& r = a.state().records[i];
    const ParticleRecord& s = b.state().records[i];
    ASSERT_EQ(r.pair_collisions, s.pair_collisions) << i;
    ASSERT_EQ(r.last_collision, s.last_collision) << i;
    ASSERT_EQ(r.image, s.image) << i;
  }
  ASSERT_EQ(a.chain(), b.chain());
}

template <std::size_t D>
void resumed_runs_are_the_run_in_one(std::uint64_t n, double phi) {
  Simulation<D> whole(periodic_gas<D>(n, phi), chains());
  whole.run_until(30.0);
  Simulation<D> first(periodic_gas<D>(n, phi), chains());
  first.run_until(7.5);
  first.run_until(first.time(), 1234);  // stopped mid-instant: between lifts
  std::stringstream saved;
  write_checkpoint(saved, first.checkpoint("gas"));
  AnyCheckpoint read = read_checkpoint(saved, "saved");
  Simulation<D> resumed(std::get<Checkpoint<D>>(read));
  resumed.run_until(30.0);
  expect_same_run(whole, resumed);
  EXPECT_GT(whole.counts().pair_collisions, 20 * n);
}

TEST(EcmcRun, ResumedFromACheckpointIsTheRunInOne2D) { resumed_runs_are_the_run_in_one<2>(200, 0.6); }
TEST(EcmcRun, ResumedFromACheckpointIsTheRunInOne3D) { resumed_runs_are_the_run_in_one<3>(216, 0.4); }

// Counts the events it sees, one by one.
template <std::size_t D>
class EventCounter final : public Observer<D> {
 public:
  EventCounter() : Observer<D>(Trigger::each_event()) {}
  void observe(const Simulation<D>&) override { ++seen; }
  std::uint64_t seen = 0;
};

// Unwatched, the engine lifts in batches (EcmcEngine::lift_quietly); watched, the Simulation
// records each lift: the same run, counts, fluxes and window bit for bit, rebases and chain turns
// included, and in pieces cut by an event limit.
template <std::size_t D>
void batches_are_the_lifts_one_by_one(std::uint64_t n, double phi) {
  Simulation<D> batched(periodic_gas<D>(n, phi), chains(4.0));
  batched.run_until(5.0, 777);
  batched.run_until(200.0);
  Simulation<D> watched(periodic_gas<D>(n, phi), chains(4.0));
  auto counter = std::make_shared<EventCounter<D>>();
  watched.add_observer(counter);
  watched.run_until(200.0);
  expect_same_run(batched, watched);
  EXPECT_EQ(batched.measurement(), watched.measurement());
  EXPECT_EQ(counter->seen, watched.counts().events);
  // Past several rebases (Simulation::rebase_period).
  EXPECT_GT(watched.counts().events, 3 * Simulation<D>::rebase_period(n));
}

TEST(EcmcRun, BatchesAreTheLiftsOneByOne2D) { batches_are_the_lifts_one_by_one<2>(200, 0.6); }
TEST(EcmcRun, BatchesAreTheLiftsOneByOne3D) { batches_are_the_lifts_one_by_one<3>(216, 0.4); }

// Where the System is larger than a cache, a lift's stop is written with the chain's others, in
// bulk (EcmcEngine::stops_held_): in batches thousands at a time (chains longer than the stops
// held, so some are written mid-chain), watched one at a time; the same run and records.
TEST(EcmcRun, StopsWrittenInBulkAreTheStopsOneByOne) {
  const std::uint64_t n = 200000;  // 20 MB of the System's entries
  Simulation<2> batched(periodic_gas<2>(n, 0.6), chains(1000.0));
  batched.run_until(0.03);
  Simulation<2> watched(periodic_gas<2>(n, 0.6), chains(1000.0));
  auto counter = std::make_shared<EventCounter<2>>();
  watched.add_observer(counter);
  watched.run_until(0.03);
  expect_same_run(batched, watched);
  EXPECT_GT(watched.counts().events, 20000u);
}

// Chains far shorter than the space between particles end by the thousand without a lift: a
// slice bounds them too, so that a run looks at its stop flag (and takes their velocity changes)
// every few thousand chains. Regression: a run of chains of 1e-6 diameters went on to its end
// without a look at the flag, its velocity changes held by the billion (gigabytes).
TEST(EcmcRun, ShortChainsStillLookAtTheStopFlag) {
  Simulation<2> simulation(periodic_gas<2>(256, 0.6), chains(1e-6));
  const std::atomic<int> stop{1};
  simulation.set_stop_flag(&stop);
  EXPECT_EQ(simulation.run_until(1e-3), RunStatus::stopped);
  EXPECT_LT(simulation.time(), 1e-4);  // a slice: 4096 chains of 1e-6 / 256
}

// Chains too short for a double to count their ends by the run's end are refused before the run,
// not left to run for ever at one time.
TEST(EcmcRun, ChainsTooShortForTheClockAreRefused) {
  Simulation<2> simulation(periodic_gas<2>(256, 0.6), chains(1e-9));
  EXPECT_NO_THROW(simulation.run_until(1e-6));
  try {
    simulation.run_until(1e4);
    FAIL() << "chains of 1e-9 diameters ran to 1e4";
  } catch (const RunLengthError& e) {
    EXPECT_NE(std::string(e.what()).find("use a longer chain length"), std::string::npos)
        << e.what();
  }
}

// One particle moves at v at every instant, along x, y (and z) in turn: the kinetic stress's
// diagonal sums to m v^2 t, and each axis has its share, only if every chain's turn reached the
// fluxes.
template <std::size_t D>
void every_turn_reaches_the_fluxes() {
  Simulation<D> simulation(periodic_gas<D>(D == 2 ? 300 : 343, D == 2 ? 0.5 : 0.3), chains(3.0));
  simulation.run_until(40.0);
  const Fluxes fluxes = *simulation.current_counts().fluxes;
  const double n = static_cast<double>(simulation.state().size());
  const double speed = n * mean_diameter(simulation.state());
  double total = 0.0;
  for (std::size_t k = 0; k < D; ++k) {
    total += fluxes.kinetic_stress[k];
    EXPECT_NEAR(fluxes.kinetic_stress[k] / (speed * speed * 40.0), 1.0 / D, 0.02) << k;
  }
  EXPECT_NEAR(total / (speed * speed * 40.0), 1.0, 1e-12);
  const Observables<D> o = simulation.observables();
  ASSERT_TRUE(o.directional_z.has_value());
  for (std::size_t k = 0; k < D; ++k) EXPECT_NEAR((*o.directional_z)[k], o.compressibility_factor, 0.1 * o.compressibility_factor) << k;
  EXPECT_EQ(o.temperature, 1.0);
  EXPECT_NEAR(o.pressure, o.compressibility_factor * n / box_volume(simulation.state().box),
              1e-12 * o.pressure);
  double trace = 0.0;
  for (std::size_t k = 0; k < D; ++k) trace += (*o.pressure_tensor)[k];
  EXPECT_NEAR(trace / D, o.pressure, 0.02 * o.pressure);
}

TEST(EcmcRun, EveryChainsTurnReachesTheFluxes2D) { every_turn_reaches_the_fluxes<2>(); }
TEST(EcmcRun, EveryChainsTurnReachesTheFluxes3D) { every_turn_reaches_the_fluxes<3>(); }

// A checkpoint whose chain does not fit its particles is refused, as any other broken one.
TEST(EcmcRun, ACheckpointsChainIsChecked) {
  Simulation<2> simulation(periodic_gas<2>(100, 0.5), chains());
  simulation.run_until(2.0);
  std::stringstream saved;
  write_checkpoint(saved, simulation.checkpoint("gas"));
  const auto refused = [&](const std::function<void(nlohmann::json&)>& edit,
                           const std::string& words) {
    nlohmann::json j = nlohmann::json::parse(saved.str());
    j.erase("checksum");
    edit(j);
    std::istringstream in(j.dump());
    try {
      read_checkpoint(in, "ck");
      ADD_FAILURE() << "accepted; expected \"" << words << "\"";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused([](nlohmann::json& j) { j.erase("chains"); }, "needs its chain");
  refused([](nlohmann::json& j) { j["sampler"] = "md"; }, "dynamics has none");
  refused([](nlohmann::json& j) { j.erase("sampler"); }, "sampler");
  refused([](nlohmann::json& j) { j["chains"]["active"] = 100; }, "not one of the 100");
  refused([](nlohmann::json& j) { j["chains"]["axis"] = 2; }, "not one of 2 axes");
  refused([](nlohmann::json& j) { j["chains"]["rng"] = "x"; }, "not a pcg32 state");
  refused(
      [](nlohmann::json& j) {
        const std::uint64_t other = j["chains"]["active"].get<std::uint64_t>() == 0 ? 1 : 0;
        j["particles"][other][2] = 0.5;  // a second particle moving
      },
      "event chains move only the active particle");
  // A chain that would never end (no turn to another axis), and masses chains cannot move.
  refused([](nlohmann::json& j) { j["chains"]["chain_end"] = 1e300; }, "more than a chain");
  refused([](nlohmann::json& j) { j["particles"][0][6] = 2.0; }, "every mass must be 1");
  // Untouched, it is read.
  std::istringstream in(saved.str());
  EXPECT_NO_THROW(read_checkpoint(in, "ck"));
}

// A lone particle is never lifted and its motion is the centre of mass's (no kinetic
// temperature to convert the sampler's clock by): an ideal gas of one, Z = 1, beta P = 1 / V.
TEST(EcmcRun, ALoneParticleIsAnIdealGas) {
  System<2> one = periodic_gas<2>(1, 0.01);
  Simulation<2> simulation(one, chains());
  simulation.run_until(3.0);
  const Observables<2> o = simulation.observables();
  EXPECT_EQ(o.compressibility_factor, 1.0);
  EXPECT_DOUBLE_EQ(o.pressure, 1.0 / box_volume(one.box));
  ASSERT_TRUE(o.directional_z);
  for (const double z : *o.directional_z) EXPECT_EQ(z, 1.0);
}

TEST(EcmcRun, TheDefaultChainLengthIsResolvedAndKept) {
  const System<2> gas = periodic_gas<2>(400, 0.5);
  Simulation<2> simulation(gas, chains());
  const double side = std::sqrt(box_volume(gas.box));
  EXPECT_DOUBLE_EQ(simulation.settings().sampler.chain_length, 0.24 * side / mean_diameter(gas));
  EXPECT_THROW(Simulation<2>(gas, chains(-1.0)), std::invalid_argument);
  Settings thermostat = chains();
  thermostat.thermostat = {ThermostatKind::rescale, 1.0, 1.0, 0.0, 1};
  EXPECT_THROW(Simulation<2>(gas, thermostat), std::invalid_argument);
}

// Simulation::kinetic_temperature() is kinetic_temperature(state()) at every instant, without the
// sum over the particles under event chains (the drift blocks and the log rows take it often).
template <std::size_t D>
void the_kinetic_temperature_is_the_states(std::uint64_t n, double phi) {
  Simulation<D> sim(periodic_gas<D>(n, phi), chains());
  for (double t = 0.37; t < 4.0; t += 0.37) {
    sim.run_until(t);
    EXPECT_EQ(sim.kinetic_temperature(), kinetic_temperature(sim.state())) << "at " << t;
  }
  std::stringstream saved;
  write_checkpoint(saved, sim.checkpoint("gas"));
  Simulation<D> resumed(std::get<Checkpoint<D>>(read_checkpoint(saved, "saved")));
  resumed.run_until(5.0);
  EXPECT_EQ(resumed.kinetic_temperature(), kinetic_temperature(resumed.state()));
  Simulation<D> dynamics(periodic_gas<D>(n, phi));
  dynamics.run_until(1.0);
  EXPECT_EQ(dynamics.kinetic_temperature(), kinetic_temperature(dynamics.state()));
}
TEST(EcmcRun, TheKineticTemperatureIsTheStates2D) {
  the_kinetic_temperature_is_the_states<2>(200, 0.6);
}
TEST(EcmcRun, TheKineticTemperatureIsTheStates3D) {
  the_kinetic_temperature_is_the_states<3>(216, 0.4);
}

}  // namespace
}  // namespace carom
