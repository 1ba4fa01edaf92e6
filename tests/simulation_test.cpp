// The Simulation: runs cut into pieces equal whole runs bit for bit (walls and periodic, swap,
// elastic, inelastic with a large TC time, a measurement window inside a piece, 2D and 3D),
// observers on their own timeline, the stop flag, run-length guards and checkpoints.
#include "carom/engine/simulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <sstream>

#include "carom/engine/initial.hpp"
#include "carom/engine/invariant_check.hpp"
#include "carom/io/checkpoint.hpp"
#include "carom/io/classic_input.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

using carom::testing::boxed;
using carom::testing::disk;
using carom::testing::EventRecorder;
using carom::testing::random_gas;
using carom::testing::square_lattice;
using carom::testing::uniform;

// Two runs are the same run: same time, stored states, records, counts and window, bit for bit.
template <std::size_t D>
void expect_identical(const Simulation<D>& a, const Simulation<D>& b, const std::string& label) {
  ASSERT_EQ(a.time(), b.time()) << label;
  ASSERT_EQ(a.settled(), b.settled()) << label;
  ASSERT_EQ(a.counts(), b.counts()) << label;
  ASSERT_EQ(a.measurement(), b.measurement()) << label;
  ASSERT_EQ(a.pending_measurement(), b.pending_measurement()) << label;
  ASSERT_EQ(a.state().epoch, b.state().epoch) << label;
  ASSERT_EQ(a.state().particles, b.state().particles) << label;
  ASSERT_EQ(a.state().records, b.state().records) << label;
  ASSERT_EQ(a.snapshot(), b.snapshot()) << label;
}

// Frames: the time and the snapshot a time observer saw.
template <std::size_t D>
struct FrameRecorder final : Observer<D> {
  explicit FrameRecorder(double every) : Observer<D>(Trigger::every_time(every)) {}
  void observe(const Simulation<D>& simulation) override {
    times.push_back(simulation.time());
    positions.push_back(simulation.snapshot());
  }
  std::vector<double> times;
  std::vector<std::vector<Particle<D>>> positions;
};

struct Case {
  std::string label;
  System<2> system;
  Settings settings;
  double end_time;
  double measure_from;
};

std::vector<Case> cases() {
  pcg32 rng(20261122);
  std::vector<Case> list;
  for (int trial = 0; trial < 12; ++trial) {
    System<2> gas = random_gas(rng, 30, 0.2, 0.5, 10, 8);
    const bool periodic = trial % 2 == 1;
    if (periodic) gas.box.boundary = Boundary::periodic;
    Settings settings;
    switch (trial % 4) {
      case 0:
        settings.rule = {Rule::swap};
        break;
      case 1:
        settings.rule = {Rule::elastic};
        break;
      default:
        // Inelastic, with a TC time long enough that many collisions are made elastic by it.
        settings.rule = {Rule::elastic, 0.6, 0.3};
        break;
    }
    list.push_back({"trial " + std::to_string(trial) + (periodic ? " periodic" : " walls"), gas,
                    settings, uniform(rng, 15, 30), uniform(rng, 2, 10)});
  }
  // Touching lattices: many events at one instant, where an event limit can fall between them.
  list.push_back({"lattice", square_lattice(rng, 6, 0.5, 0.1, true), {{Rule::elastic}}, 8.0, 1.0});
  return list;
}

// A simulation of a case, with recorders of its events and of frames every 0.7.
struct Observed {
  explicit Observed(const Case& c) : simulation(c.system, c.settings) {
    simulation.add_observer(events);
    simulation.add_observer(frames);
    simulation.measure_from(c.measure_from);
  }
  Simulation<2> simulation;
  std::shared_ptr<EventRecorder<2>> events = std::make_shared<EventRecorder<2>>();
  std::shared_ptr<FrameRecorder<2>> frames = std::make_shared<FrameRecorder<2>>(0.7);
};

TEST(Simulation, RunsCutIntoPiecesEqualWholeRunsBitForBit) {
  pcg32 rng(7);
  for (const Case& c : cases()) {
    Observed a(c), b(c);
    Simulation<2>& whole = a.simulation;
    Simulation<2>& pieces = b.simulation;
    ASSERT_EQ(whole.run_until(c.end_time), RunStatus::reached);
    // Stops at random times, at the window's start exactly, at frame times exactly, and after
    // random numbers of events.
    std::vector<double> stops = {0.0, c.measure_from, 2.1, 1.4};
    for (int k = 0; k < 6; ++k) stops.push_back(uniform(rng, 0, c.end_time));
    std::sort(stops.begin(), stops.end());
    for (const double stop : stops) {
      if (stop < pieces.time()) continue;
      while (pieces.run_until(stop, 1 + rng() % 40) == RunStatus::event_limit) {
        ASSERT_TRUE(pieces.settled()) << c.label;
      }
    }
    ASSERT_EQ(pieces.run_until(c.end_time), RunStatus::reached);
    expect_identical(whole, pieces, c.label);
    ASSERT_EQ(a.events->events.size(), b.events->events.size()) << c.label;
    for (std::size_t i = 0; i < a.events->events.size(); ++i) {
      const Event& x = a.events->events[i];
      const Event& y = b.events->events[i];
      ASSERT_EQ(x, y) << c.label << " event " << i;
      ASSERT_EQ(x.impulse, y.impulse) << c.label << " event " << i;
      ASSERT_EQ(x.elastic_by_tc, y.elastic_by_tc) << c.label << " event " << i;
    }
    EXPECT_EQ(a.frames->times, b.frames->times) << c.label;
    EXPECT_EQ(a.frames->positions, b.frames->positions) << c.label;
    EXPECT_EQ(whole.measurement().start_time, c.measure_from) << c.label;
    EXPECT_GT(whole.counts().events, whole.measurement().counts.events) << c.label;
    if (c.settings.rule.restitution < 1.0) {
      EXPECT_GT(whole.counts().elastic_by_tc, 0u) << c.label;
    }
  }
}

TEST(Simulation, ThreeDimensionalRunsCutIntoPiecesEqualWholeRuns) {
  pcg32 rng(3);
  for (const Boundary boundary : {Boundary::walls, Boundary::periodic}) {
    System<3> system;
    system.box = {{{6.5, 6.5, 6.5}}, boundary};
    for (int i = 0; i < 27; ++i) {
      Particle<3> p;
      p.radius = 0.7;
      p.position = {{1.1 + 2.1 * (i % 3), 1.1 + 2.1 * (i / 3 % 3), 1.1 + 2.1 * (i / 9)}};
      p.velocity = {{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)}};
      system.add(p, uniform(rng, 0.5, 2));
    }
    for (const EngineKind engine : {EngineKind::fast, EngineKind::reference}) {
      const Settings settings{{Rule::elastic, 0.8, 0.2}, engine};
      Simulation<3> whole(system, settings);
      whole.measure_from(3.0);
      whole.run_until(20.0);
      Simulation<3> pieces(system, settings);
      pieces.measure_from(3.0);
      for (double t = 0.9; t < 20.0; t += 0.9) pieces.run_until(t, 17);
      while (pieces.run_until(20.0, 13) != RunStatus::reached) {
      }
      const std::string label = std::string(name_of(boundary)) + " " + std::string(name_of(engine));
      expect_identical(whole, pieces, label);
      EXPECT_GT(whole.counts().pair_collisions, 100u) << label;
    }
  }
}

TEST(Simulation, BothEnginesGiveTheSameRun) {
  for (const Case& c : cases()) {
    Settings fast = c.settings, reference = c.settings;
    reference.engine = EngineKind::reference;
    Simulation<2> a(c.system, fast), b(c.system, reference);
    a.measure_from(c.measure_from);
    b.measure_from(c.measure_from);
    a.run_until(c.end_time);
    b.run_until(c.end_time);
    expect_identical(a, b, c.label);
  }
}

// Regression: the stored time doubled as the TC model's last-collision time, so a run whose
// states had been brought to a common time (to print them) treated every disk as having just
// collided, and the next collision came out elastic.
TEST(Simulation, TheTcModelReadsLastCollisionsNotStoredTimes) {
  // Head on, touching at t = 1; the TC time is 0.5.
  const System<2> system = boxed({20, 20}, {disk({5, 10}, {1, 0}, 1), disk({9, 10}, {-1, 0}, 1)});
  Simulation<2> simulation(system, {{Rule::elastic, 0.5, 0.5}});
  simulation.run_until(0.9);
  ASSERT_EQ(simulation.snapshot()[0].time, 0.9);  // printing the state
  simulation.run_until(2.0);
  ASSERT_EQ(simulation.counts().pair_collisions, 1u);
  EXPECT_EQ(simulation.counts().elastic_by_tc, 0u);
  EXPECT_EQ(simulation.state().particles[0].velocity, (Vec2{{-0.5, 0}}));  // restitution 0.5
  EXPECT_EQ(simulation.state().records[0].last_collision, 1.0);

  // A wall hit at t = 0.25, 0.25 before the pair collision, does count.
  const System<2> after_wall =
      boxed({20, 20}, {disk({1.25, 10}, {-1, 0}, 1), disk({3.75, 10}, {-1, 0}, 1)});
  Simulation<2> second(after_wall, {{Rule::elastic, 0.5, 0.5}});
  second.run_until(0.6);
  EXPECT_EQ(second.counts().wall_collisions, 1u);
  EXPECT_EQ(second.counts().elastic_by_tc, 1u);
}

TEST(Simulation, AStopFlagEndsTheRunAtAWholeInstantAndTheRunGoesOn) {
  pcg32 rng(5);
  const System<2> system = square_lattice(rng, 8, 0.5, 0.1, true);
  Simulation<2> whole(system, {{Rule::elastic}});
  whole.run_until(6.0);

  Simulation<2> stopped(system, {{Rule::elastic}});
  std::atomic<int> flag{0};
  stopped.set_stop_flag(&flag);
  // Set from "outside" after the 50th event, the way a signal handler would.
  struct Raiser final : Observer<2> {
    explicit Raiser(std::atomic<int>& flag) : Observer<2>(Trigger::every_events(50)), flag(flag) {}
    void observe(const Simulation<2>&) override { flag = 2; }
    std::atomic<int>& flag;
  };
  stopped.add_observer(std::make_shared<Raiser>(flag));
  ASSERT_EQ(stopped.run_until(6.0), RunStatus::stopped);
  EXPECT_GE(stopped.counts().events, 50u);
  EXPECT_LT(stopped.time(), 6.0);
  EXPECT_TRUE(stopped.settled());
  // Every event at the time it stopped is processed: none is left at that time.
  Simulation<2> probe(stopped.checkpoint(""));
  auto events = std::make_shared<EventRecorder<2>>();
  probe.add_observer(events);
  probe.run_until(stopped.time());
  EXPECT_TRUE(events->events.empty());
  stopped.set_stop_flag(nullptr);
  ASSERT_EQ(stopped.run_until(6.0), RunStatus::reached);
  expect_identical(whole, stopped, "stopped and resumed");
}

TEST(Simulation, EarlyReturnsFinishTheInstantTheyStopAt) {
  // A corner: two wall hits at t = 1. Stopping after the first still processes the second, so
  // that the run is whole at the time it reports.
  const System<2> corner = boxed({10, 10}, {disk({2, 3}, {-1, -2}, 1)});
  Simulation<2> limited(corner);
  auto seen = std::make_shared<FrameRecorder<2>>(1.0);
  limited.add_observer(seen);
  ASSERT_EQ(limited.run_until(5.0, 1), RunStatus::event_limit);
  EXPECT_EQ(limited.counts().events, 2u);
  EXPECT_EQ(limited.time(), 1.0);
  EXPECT_TRUE(limited.settled());
  EXPECT_EQ(seen->times, (std::vector<double>{0, 1}));  // the frame at 1 saw both hits
  EXPECT_EQ(limited.state().particles[0].velocity, (Vec2{{1, 2}}));

  Simulation<2> flagged(corner);
  std::atomic<int> flag{1};  // set before the run: stops after the first event's instant
  flagged.set_stop_flag(&flag);
  ASSERT_EQ(flagged.run_until(5.0), RunStatus::stopped);
  EXPECT_EQ(flagged.counts().events, 2u);
  EXPECT_EQ(flagged.time(), 1.0);
}

// An observer that waits for whole instants: what it sees, and whether the run was whole then.
template <std::size_t D>
struct InstantRecorder final : Observer<D> {
  explicit InstantRecorder(Trigger trigger) : Observer<D>(trigger.at_whole_instants()) {}
  void observe(const Simulation<D>& simulation) override {
    settled = settled && simulation.settled();
    events.push_back(simulation.counts().events);
  }
  bool settled = true;
  std::vector<std::uint64_t> events;
};

TEST(Simulation, WholeInstantObserversSeeEveryEventOfTheirInstantAndChangeNothing) {
  // Every case, ties of touching lattices included: an observer due after every 7th event but
  // waiting for the instant to be complete (what a checkpoint needs) sees a settled run, at
  // least 7 events after the last time; and the run is the one without it, bit for bit.
  for (const Case& c : cases()) {
    Observed plain(c), watched(c);
    auto waiting = std::make_shared<InstantRecorder<2>>(Trigger::every_events(7));
    watched.simulation.add_observer(waiting);
    plain.simulation.run_until(c.end_time);
    watched.simulation.run_until(c.end_time);
    expect_identical(plain.simulation, watched.simulation, c.label);
    EXPECT_EQ(plain.events->events, watched.events->events) << c.label;
    EXPECT_EQ(plain.frames->times, watched.frames->times) << c.label;
    EXPECT_TRUE(waiting->settled) << c.label;
    ASSERT_FALSE(waiting->events.empty()) << c.label;
    for (std::size_t k = 0; k < waiting->events.size(); ++k) {
      EXPECT_GE(waiting->events[k], 7 * (k + 1)) << c.label;
    }
  }
}

TEST(Simulation, TargetsOutOfReachAreRefused) {
  Simulation<2> simulation(boxed({10, 10}, {disk({5, 5}, {1, 0.5}, 1)}));
  simulation.run_until(5.0);
  EXPECT_THROW(simulation.run_until(4.0), RunLengthError);
  EXPECT_THROW(simulation.run_until(std::nan("")), RunLengthError);
  EXPECT_THROW(simulation.run_until(2e12), RunLengthError);
  EXPECT_NO_THROW(simulation.check_target(5e11));  // 5.6e10 box crossings: fine...
  Simulation<2> fast(boxed({10, 10}, {disk({5, 5}, {1e3, 0}, 1)}));
  EXPECT_THROW(fast.check_target(2e11), RunLengthError);  // ...2e13 are not
  EXPECT_NO_THROW(fast.check_target(1e9));
  EXPECT_EQ(simulation.time(), 5.0);
}

TEST(Simulation, TheMeasurementWindowOpensWhenAsked) {
  Simulation<2> simulation(boxed({10, 10}, {disk({5, 5}, {2, 0}, 1)}));  // walls at 2, 6, 10...
  simulation.measure_from(5.0);
  EXPECT_EQ(simulation.pending_measurement(), 5.0);
  simulation.run_until(12.0);
  EXPECT_EQ(simulation.pending_measurement(), std::nullopt);
  EXPECT_EQ(simulation.measurement().start_time, 5.0);
  EXPECT_EQ(simulation.measurement().counts.wall_collisions, 2u);  // 6, 10
  EXPECT_EQ(simulation.counts().wall_collisions, 3u);
  EXPECT_EQ(simulation.observables().elapsed, 7.0);
  simulation.reset_measurement();
  EXPECT_EQ(simulation.measurement().start_time, 12.0);
  Counts window = simulation.measurement().counts;  // the window's fluxes: since it opened
  ASSERT_TRUE(window.fluxes.has_value());
  EXPECT_EQ(window.fluxes->since, 12.0);  // the window's fluxes begin with it
  EXPECT_EQ(window.fluxes->stress_moment(), SymmetricTensor{});
  window.fluxes.reset();
  EXPECT_EQ(window, Counts{});
  EXPECT_EQ(simulation.measurement().kinetic_energy_initial, 2.0);
  simulation.measure_from(3.0);  // in the past: now
  EXPECT_EQ(simulation.measurement().start_time, 12.0);
  EXPECT_THROW(simulation.measure_from(std::nan("")), std::invalid_argument);
}

TEST(Simulation, ObserversFireOnTheirOwnTimeline) {
  Simulation<2> simulation(boxed({10, 10}, {disk({5, 5}, {2, 0}, 1)}));
  auto frames = std::make_shared<FrameRecorder<2>>(2.5);
  simulation.add_observer(frames);
  struct Counter final : Observer<2> {
    Counter() : Observer<2>(Trigger::every_events(2)) {}
    void observe(const Simulation<2>& s) override { seen.push_back(s.counts().events); }
    std::vector<std::uint64_t> seen;
  };
  auto counter = std::make_shared<Counter>();
  simulation.add_observer(counter);
  simulation.run_until(10.0);
  EXPECT_EQ(frames->times, (std::vector<double>{0, 2.5, 5, 7.5, 10}));
  // At t = 5 the disk, back from the right wall at t = 2, is at x = 9 - 2 x 3.
  EXPECT_EQ(frames->positions[2][0].position, (Vec2{{3, 5}}));
  EXPECT_EQ(counter->seen, (std::vector<std::uint64_t>{2}));  // hits at 2, 6, 10
  // An observer added to a run that is whole at 10 starts after it.
  auto late = std::make_shared<FrameRecorder<2>>(5.0);
  simulation.add_observer(late);
  simulation.run_until(15.0);
  EXPECT_EQ(late->times, (std::vector<double>{15}));
  EXPECT_THROW(simulation.add_observer(std::make_shared<FrameRecorder<2>>(0.0)),
               std::invalid_argument);
  // A removed observer is called no more; the others go on.
  EXPECT_EQ(counter->seen, (std::vector<std::uint64_t>{2, 4}));  // the hit at 14
  simulation.remove_observer(counter.get());
  simulation.remove_observer(late.get());
  simulation.run_until(30.0);  // hits at 18, 22, 26, 30
  EXPECT_EQ(counter->seen, (std::vector<std::uint64_t>{2, 4}));
  EXPECT_EQ(late->times, (std::vector<double>{15}));
  EXPECT_EQ(frames->times.back(), 30.0);
}

TEST(Simulation, CheckpointsContinueExactly) {
  for (const Case& c : cases()) {
    Simulation<2> whole(c.system, c.settings);
    whole.measure_from(c.measure_from);
    whole.run_until(c.end_time);

    Simulation<2> first(c.system, c.settings);
    first.measure_from(c.measure_from);
    first.run_until(c.measure_from / 2, 97);  // before the window opens
    std::stringstream file;
    write_checkpoint(file, first.checkpoint("start.txt"));
    AnyCheckpoint read = read_checkpoint(file, "ck");
    ASSERT_TRUE(std::holds_alternative<Checkpoint<2>>(read));
    EXPECT_EQ(std::get<Checkpoint<2>>(read).source, "start.txt");
    Simulation<2> resumed(std::get<Checkpoint<2>>(read));
    expect_identical(first, resumed, c.label + " after reading");
    resumed.run_until(c.end_time);
    expect_identical(whole, resumed, c.label);
  }
}

TEST(Simulation, ThreeDimensionalCheckpointsRecordTheirDimension) {
  System<3> system;
  system.box = {{{5, 6, 7}}, Boundary::periodic};
  Particle<3> p;
  p.radius = 0.5;
  p.position = {{1, 2, 3}};
  p.velocity = {{0.1, -0.2, 0.3}};
  system.add(p, 2.0);
  Simulation<3> simulation(system, {{Rule::elastic}});
  simulation.run_until(4.0);
  std::stringstream file;
  write_checkpoint(file, simulation.checkpoint("x"));
  EXPECT_NE(file.str().find("\"dimension\": 3"), std::string::npos);
  const AnyCheckpoint read = read_checkpoint(file, "ck");
  ASSERT_TRUE(std::holds_alternative<Checkpoint<3>>(read));
  expect_identical(simulation, Simulation<3>(std::get<Checkpoint<3>>(read)), "3D");
}

TEST(Simulation, CheckpointsContinueExactlyAcrossEpochs) {
  pcg32 rng(5);
  System<2> gas = random_gas(rng, 30, 0.3, 0.5, 10, 8);
  gas.box.boundary = Boundary::periodic;
  const std::uint64_t period = Simulation<2>::rebase_period(gas.size());
  Simulation<2> whole(gas, {{Rule::elastic}});
  whole.run_until(1e6, 5 * period + 17);
  Simulation<2> first(gas, {{Rule::elastic}});
  first.run_until(1e6, 2 * period + 40);  // past two epochs, between them and the next
  EXPECT_GT(first.state().epoch, 0.0);
  std::stringstream file;
  write_checkpoint(file, first.checkpoint("gas"));
  Simulation<2> resumed(std::get<Checkpoint<2>>(read_checkpoint(file, "ck")));
  expect_identical(first, resumed, "after reading");
  resumed.run_until(1e6, 3 * period - 23);
  expect_identical(whole, resumed, "resumed");
}

// The system of the report: two disks in a 2.1 x 2.1 box, every stored time `start`.
System<2> two_disks_at(double start) {
  System<2> system = boxed(
      {2.1, 2.1}, {disk({0.55, 0.6}, {0.7, 0.31}, 0.5), disk({1.5, 1.45}, {-0.43, 0.52}, 0.5)});
  for (Particle<2>& p : system.particles) p.time = start;
  return system;
}

TEST(Simulation, TimeIsResolvedAsFinelyAtAnyAbsoluteTime) {
  // Regression: stored times were absolute, so the moments of contact were rounded to the
  // resolution of the absolute time: these disks overlapped by 1.2e-9 near t = 8.4e6, and by
  // 2.6e-6 at once from t = 1e11. The run counts time from an epoch that moves with it, so a run
  // from 1e11 is the run from 0, bit for bit, over many epochs.
  constexpr std::uint64_t kEvents = 200000;
  Simulation<2> from_zero(two_disks_at(0.0), {{Rule::elastic}});
  from_zero.run_until(1e6, kEvents);
  ASSERT_GT(kEvents, 20 * Simulation<2>::rebase_period(2));
  for (const double start : {1e7, 1e9, 1e11}) {
    Simulation<2> later(two_disks_at(start), {{Rule::elastic}});
    later.add_observer(std::make_shared<InvariantCheck<2>>(1));
    EXPECT_NO_THROW(later.run_until(start + 1e6, kEvents)) << start;
    // The flux integrals (fluxes.hpp) step on stored times too: only their absolute labels differ.
    Counts later_counts = later.counts();
    later_counts.fluxes->since -= start;
    later_counts.fluxes->time = from_zero.counts().fluxes->time;
    EXPECT_EQ(later_counts, from_zero.counts()) << start;
    EXPECT_EQ(later.state().particles, from_zero.state().particles) << start;
    EXPECT_EQ(later.state().records, from_zero.state().records) << start;
    EXPECT_NEAR(later.time() - start, from_zero.time(), 1e-4 * start / 1e11) << start;
  }
}

TEST(Simulation, TinyParticlesInABigBoxAreNotCutIntoEndlessSlices) {
  // Regression (found by fuzzing the GSD reader): slices of time were sized from the diameter
  // alone, so twelve points of radius 1e-41 in a box of side 3 advanced by 1e-38 a slice and a
  // run to t = 1 never ended.
  System<3> points;
  points.box = {{{3.155, 3.155, 3.155}}, Boundary::periodic};
  for (int i = 0; i < 12; ++i) {
    Particle<3> p;
    p.position = {{0.25 * i + 0.1, 0.2 * i + 0.3, 3.0 - 0.24 * i}};
    p.velocity = {{0.5 - 0.1 * i, 0.3 * (i % 3) - 0.2, 0.1 * i - 0.6}};
    p.radius = 1.1389753918032113e-41;
    points.add(p);
  }
  Simulation<3> simulation(points, {{Rule::elastic}});
  EXPECT_EQ(simulation.run_until(1.0), RunStatus::reached);
  EXPECT_EQ(simulation.time(), 1.0);
}

TEST(Simulation, CarromOneCheckpointsAreStillRead) {
  const std::string folder = std::string(CAROM_TEST_DATA) + "/checkpoint_v1/";
  std::ifstream file(folder + "v1.ckpt");
  const AnyCheckpoint read = read_checkpoint(file, "v1.ckpt");
  ASSERT_TRUE(std::holds_alternative<Checkpoint<2>>(read));
  Simulation<2> resumed(std::get<Checkpoint<2>>(read));
  EXPECT_EQ(resumed.pending_measurement(), std::nullopt);
  EXPECT_EQ(resumed.measurement().start_time, 2.0);
  resumed.run_until(9.0);
  // The same run made afresh by this carom (periodic, elastic, measuring from t = 2).
  System<2> start = read_classic_file<2>(folder + "gas.txt", Boundary::periodic).system;
  Simulation<2> whole(start, {{Rule::elastic}});
  whole.measure_from(2.0);
  whole.run_until(9.0);
  // The same collisions; the states agree to round-off grown over a thousand collisions of a
  // chaotic gas, since the old checkpoint's absolute stored times were re-based when it was read.
  EXPECT_EQ(resumed.measurement().counts.events, 1115u);  // as carom 1.0 counted
  EXPECT_EQ(resumed.measurement().counts.pair_collisions,
            whole.measurement().counts.pair_collisions);
  EXPECT_NEAR(resumed.measurement().counts.virial, whole.measurement().counts.virial, 1e-6);
  const std::vector<Particle<2>> a = resumed.snapshot(), b = whole.snapshot();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_NEAR(a[i].position[k], b[i].position[k], 1e-6) << i;
      EXPECT_NEAR(a[i].velocity[k], b[i].velocity[k], 1e-6) << i;
    }
  }
}

}  // namespace
}  // namespace carom
