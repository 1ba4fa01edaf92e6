// The engines: the classic assignment's cases through the library, the fast engine against the
// reference engine on many random systems, and the invariants every run must keep.
#include "carom/engine/engine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "carom/engine/initial.hpp"
#include "carom/engine/overlap.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/run_report.hpp"
#include "engine/fast_engine.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

using carom::testing::boxed;
using carom::testing::case_system;
using carom::testing::count;
using carom::testing::disk;
using carom::testing::events_until;
using carom::testing::random_gas;
using carom::testing::simulate;
using carom::testing::square_lattice;
using carom::testing::uniform;

TEST(Engine, WallsOnlyEventsComeAtTheSeedsTimes) {
  for (EngineKind kind : {EngineKind::fast, EngineKind::reference}) {
    Simulation<2> simulation(case_system("walls_only.txt"), {{Rule::swap}, kind});
    const std::vector<Event> events = simulate(simulation, 20.0);
    ASSERT_EQ(events.size(), 4u) << name_of(kind);
    EXPECT_EQ(events[0], (Event{9.5, 0, -1}));
    EXPECT_DOUBLE_EQ(events[1].time, 13.0);
    EXPECT_EQ(events[1].first, 3u);
    EXPECT_EQ(events[1].partner, -4);
    EXPECT_DOUBLE_EQ(events[2].time, 15.0);
    EXPECT_EQ(events[2].partner, -3);
    EXPECT_DOUBLE_EQ(events[3].time, 18.0);
    EXPECT_EQ(events[3].partner, -2);
    EXPECT_EQ(simulation.counts().wall_collisions, 4u);
    EXPECT_EQ(simulation.counts().pair_collisions, 0u);
    EXPECT_EQ(simulation.counts().events, 4u);
    for (const auto& p : simulation.snapshot()) EXPECT_EQ(p.time, 20.0);
  }
}

TEST(Engine, ParticlesOnlyHasTwoPairCollisionsAndNoWallHits) {
  // Disks 2 and 4 start touching a wall while moving away: no wall event.
  auto engine = make_engine(EngineKind::fast, case_system("particles_only.txt"), {Rule::swap});
  const std::vector<Event> events = events_until(*engine, 18.0);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].first, 1u);
  EXPECT_EQ(events[0].partner, 2);
  EXPECT_NEAR(events[0].time, 14.001202, 5e-7);
  EXPECT_EQ(events[1].first, 5u);
  EXPECT_EQ(events[1].partner, 6);
  EXPECT_NEAR(events[1].time, 17.271454, 5e-7);
}

TEST(Engine, EventsAtExactlyTheEndTimeAreProcessed) {
  const System<2> system =
      boxed({10, 10}, {disk({1, 5}, {1, 0}, 1)});  // reaches x = 9 at t = 8 exactly
  for (EngineKind kind : {EngineKind::fast, EngineKind::reference}) {
    auto at_end = make_engine(kind, system, {Rule::swap});
    EXPECT_EQ(count(events_until(*at_end, 8.0)).wall_collisions, 1u);
    EXPECT_EQ(at_end->system().particles[0].velocity, (Vec2{{-1, 0}}));
    auto before_end = make_engine(kind, system, {Rule::swap});
    EXPECT_EQ(count(events_until(*before_end, std::nextafter(8.0, 0.0))).wall_collisions, 0u);
  }
}

TEST(Engine, EndTimeZeroChangesNothing) {
  const System<2> start = case_system("particles_only.txt");
  auto engine = make_engine(EngineKind::fast, start, {Rule::swap});
  EXPECT_EQ(events_until(*engine, 0.0).size(), 0u);
  for (std::size_t i = 0; i < start.particles.size(); ++i) {
    EXPECT_EQ(engine->system().particles[i].position, start.particles[i].position);
  }
}

TEST(Engine, CornerHitIsTwoEventsAtTheSameTime) {
  const System<2> system = boxed({10, 10}, {disk({2, 3}, {-1, -2}, 1)});
  for (EngineKind kind : {EngineKind::fast, EngineKind::reference}) {
    auto engine = make_engine(kind, system, {Rule::swap});
    const std::vector<Event> events = events_until(*engine, 1.5);
    ASSERT_EQ(events.size(), 2u);
    EXPECT_EQ(events[0], (Event{1.0, 0, -1}));
    EXPECT_EQ(events[1], (Event{1.0, 0, -3}));
    EXPECT_EQ(engine->system().particles[0].velocity, (Vec2{{1, 2}}));
    EXPECT_EQ(engine->system().records[0].wall_collisions, 2u);
  }
}

TEST(Engine, APairThatJustCollidedDoesNotCollideAgainAfterAnUnrelatedEvent) {
  // The classic assignment's "not the same pair as last time" guard fails here: disks 0 and 1
  // collide, then disk 2 hits a wall, and the classic assignment's code would let 0 and 1 (still
  // touching) collide again and swap back. Here they separate: exactly one pair collision.
  System<2> system;
  system.box.size = {20, 20};
  const auto add = [&](double x, double y, double vx, double vy) {
    Particle<2> p;
    p.position = {x, y};
    p.velocity = {vx, vy};
    p.radius = 1;
    system.add(p);
  };
  add(5, 10, 1, 0);
  add(9, 10, -1, 0);
  add(17, 5, 1.0, 0);
  for (EngineKind kind : {EngineKind::fast, EngineKind::reference}) {
    auto engine = make_engine(kind, system, {Rule::swap});
    const std::vector<Event> events = events_until(*engine, 3.0);
    ASSERT_EQ(events.size(), 2u) << name_of(kind);
    EXPECT_EQ(events[0], (Event{1.0, 0, 1}));
    EXPECT_EQ(events[1], (Event{2.0, 2, -2}));
    EXPECT_EQ(count(events).pair_collisions, 1u);
  }
}

TEST(Engine, ATouchingApproachingPairCollidesAtOnce) {
  System<2> system;
  system.box.size = {10, 10};
  Particle<2> a, b;
  a.position = {3, 5};
  a.velocity = {1, 0};
  a.radius = 1;
  b.position = {5, 5};
  b.velocity = {0, 0};
  b.radius = 1;
  system.add(a);
  system.add(b);
  auto engine = make_engine(EngineKind::fast, system, {Rule::swap});
  const auto first = engine->step(10.0);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(*first, (Event{0.0, 0, 1}));
  EXPECT_EQ(engine->system().particles[1].velocity, (Vec2{{1, 0}}));
}

// Runs both engines side by side and demands the same events and the same final state, bit for
// bit: both predict from stored states with the same functions and order ties the same way. Both
// move to a new epoch after every `rebase_every`-th event, as a Simulation does every so often.
//
// With growth (a growing engine is never rebased) the radii grow until the end time.
//
// `fast` names the engine checked: the one make_engine picks, or the cell or the list engine (with
// the widest contact kernel the CPU runs, or the four-wide or the scalar one).

TEST(Engine, ANewEpochMovesNoParticle) {
  pcg32 rng(8);
  for (const EngineKind kind : {EngineKind::fast, EngineKind::reference}) {
    auto engine = make_engine(kind, random_gas(rng, 20, 0.3, 0.5, 10, 8), {Rule::elastic});
    for (int e = 0; e < 50; ++e) ASSERT_TRUE(engine->step(kNever));
    const double now = engine->time();
    const std::vector<Particle<2>> before = synchronised(engine->system(), engine->stored_time());
    const std::vector<ParticleRecord> records = engine->system().records;
    engine->rebase();
    EXPECT_EQ(engine->system().epoch, now) << name_of(kind);
    EXPECT_EQ(engine->time(), now) << name_of(kind);
    EXPECT_EQ(engine->system().latest_stored(), 0.0) << name_of(kind);
    // Brought to the epoch, every particle is where it was, bit for bit: p.time - now and
    // now - p.time round alike.
    EXPECT_EQ(engine->stored_time(), 0.0) << name_of(kind);
    const std::vector<Particle<2>> after = synchronised(engine->system(), 0.0);
    for (std::size_t i = 0; i < after.size(); ++i) {
      EXPECT_EQ(after[i].position, before[i].position) << name_of(kind) << " particle " << i;
      EXPECT_EQ(records[i].version(), engine->system().records[i].version());
    }
    engine->rebase();  // nothing happened since: nothing to move
    EXPECT_EQ(engine->system().epoch, now) << name_of(kind);
  }
}

TEST(Engine, AWedgedDiskIsAJamNotAHang) {
  // Regression: a disk exactly as wide as the box, moving across it, hit the walls at t = 0
  // forever.
  const System<2> system = boxed({1, 10}, {disk({0.5, 5}, {1, 0}, 0.5)});
  for (EngineKind kind : {EngineKind::fast, EngineKind::reference}) {
    auto engine = make_engine(kind, system, {Rule::swap});
    EXPECT_THROW(events_until(*engine, 1.0), JamError) << name_of(kind);
  }
}

TEST(Engine, AHorizonBelowTheTimeResolutionIsAnErrorNotAHang) {
  // Regression (found by the fuzzer): in a small periodic box, predictions are renewed every
  // horizon; when the horizon is below the resolution of the time, the renewal never advanced.
  System<2> system = boxed({4.05, 4.05}, {disk({1, 1}, {1e3, 0.1}, 1)}, Boundary::periodic);
  system.particles[0].time = 1e12;
  for (EngineKind kind : {EngineKind::fast, EngineKind::reference}) {
    EXPECT_THROW(
        {
          auto engine = make_engine(kind, system, {Rule::elastic});
          engine->step(2e12);
        },
        JamError)
        << name_of(kind);
  }
}

TEST(Engine, NothingLeftToHappenEndsEvenAtAnInfiniteEndTime) {
  const System<2> system = boxed({10, 10}, {disk({5, 5}, {0, 0}, 1)});
  for (EngineKind kind : {EngineKind::fast, EngineKind::reference}) {
    auto engine = make_engine(kind, system, {Rule::swap});
    EXPECT_FALSE(engine->step(kNever).has_value()) << name_of(kind);
    EXPECT_EQ(engine->system().particles[0].position, (Vec2{{5, 5}}));
  }
}

TEST(Engine, PeriodicBoxesMustExceedTwoDiameters) {
  const auto in_box = [](double side) {
    return boxed({side, 10}, {disk({2, 5}, {0, 0}, 1)}, Boundary::periodic);
  };
  EXPECT_THROW(make_engine(EngineKind::fast, in_box(4.0), {Rule::swap}), std::invalid_argument);
  EXPECT_NO_THROW(make_engine(EngineKind::fast, in_box(4.01), {Rule::swap}));
}

TEST(Engine, ThreeDimensionalSpheresRunInBothEngines) {
  pcg32 rng(3);
  System<3> system;
  system.box.size = {{6, 6, 6}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) {
        Particle<3> p;
        p.radius = 0.8;
        p.position = {{1 + 2.0 * i, 1 + 2.0 * j, 1 + 2.0 * k}};
        p.velocity = {{uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)}};
        system.add(p);
      }
    }
  }
  auto fast = make_engine(EngineKind::fast, system, {Rule::elastic});
  auto reference = make_engine(EngineKind::reference, system, {Rule::elastic});
  std::uint64_t pair_collisions = 0;
  for (int e = 0; e < 500; ++e) {
    const auto a = fast->step(100.0), b = reference->step(100.0);
    ASSERT_EQ(a.has_value(), b.has_value());
    if (!a) break;
    ASSERT_EQ(*a, *b) << "event " << e;
    pair_collisions += a->is_wall() ? 0 : 1;
  }
  EXPECT_GT(pair_collisions, 0u);
  EXPECT_FALSE(find_pair_overlap(fast->system(), fast->stored_time()).has_value());
}

}  // namespace
}  // namespace carom
