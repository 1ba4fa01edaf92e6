// The engines: the classic assignment's cases through the library, the fast engine against the
// reference engine on many random systems, and the invariants every run must keep.
#include "carom/engine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "carom/classic_input.hpp"
#include "carom/formats.hpp"
#include "carom/initial.hpp"
#include "carom/overlap.hpp"
#include "fast_engine.hpp"
#include "list_engine.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

using carom::testing::boxed;
using carom::testing::count;
using carom::testing::disk;
using carom::testing::events_until;
using carom::testing::random_gas;
using carom::testing::simulate;
using carom::testing::square_lattice;
using carom::testing::uniform;

System<2> case_system(const std::string& name) {
  return read_classic_file<2>(std::string(CAROM_TEST_DATA) + "/cases/" + name).system;
}

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
enum class Checked { fast, cells, lists, lists_avx2, lists_scalar };

template <std::size_t D>
std::unique_ptr<Engine<D>> checked_engine(Checked checked, const System<D>& system,
                                          const CollisionRule& rule, const Growth& growth) {
  switch (checked) {
    case Checked::cells:
      return std::make_unique<FastEngine<D>>(system, rule, growth);
    case Checked::lists:
      return std::make_unique<ListEngine<D>>(system, rule);
    case Checked::lists_avx2:
      return std::make_unique<ListEngine<D>>(system, rule, ContactKernel::avx2);
    case Checked::lists_scalar:
      return std::make_unique<ListEngine<D>>(system, rule, ContactKernel::scalar);
    default:
      return make_engine(EngineKind::fast, system, rule, growth);
  }
}

template <std::size_t D>
void expect_same_runs(const System<D>& system, const CollisionRule& rule, double end_time,
                      int max_events, const std::string& label, int rebase_every = 37,
                      double growth_rate = 0.0, Checked checked = Checked::fast) {
  const Growth growth{growth_rate, end_time};
  if (growth_rate != 0.0) rebase_every = max_events + 1;
  auto fast = checked_engine(checked, system, rule, growth);
  auto reference = make_engine(EngineKind::reference, system, rule, growth);
  double last = 0.0;
  int events = 0;
  for (; events < max_events; ++events) {
    const auto a = fast->step(end_time);
    const auto b = reference->step(end_time);
    ASSERT_EQ(a.has_value(), b.has_value()) << label << " event " << events;
    if (!a) break;
    ASSERT_EQ(*a, *b) << label << " event " << events << ": fast " << describe(*a) << " at "
                      << a->time << ", reference " << describe(*b) << " at " << b->time;
    ASSERT_EQ(a->impulse, b->impulse) << label << " event " << events;
    ASSERT_EQ(a->elastic_by_tc, b->elastic_by_tc) << label << " event " << events;
    ASSERT_GE(a->time, last) << label << " time ran backwards at event " << events;
    last = a->time;
    if ((events + 1) % rebase_every == 0) {
      fast->rebase();
      reference->rebase();
      ASSERT_EQ(fast->system().epoch, a->time) << label << " event " << events;
      ASSERT_EQ(reference->system().epoch, a->time) << label << " event " << events;
    }
  }
  const double stop = events == max_events ? last : end_time;
  const auto pf = synchronised(fast->system(), fast->system().stored(stop));
  const auto pr = synchronised(reference->system(), reference->system().stored(stop));
  const auto& rf = fast->system().records;
  const auto& rr = reference->system().records;
  for (std::size_t i = 0; i < pf.size(); ++i) {
    ASSERT_EQ(pf[i].position, pr[i].position) << label << " particle " << i;
    ASSERT_EQ(pf[i].velocity, pr[i].velocity) << label << " particle " << i;
    ASSERT_EQ(rf[i].wall_collisions, rr[i].wall_collisions) << label << " particle " << i;
    ASSERT_EQ(rf[i].pair_collisions, rr[i].pair_collisions) << label << " particle " << i;
    ASSERT_EQ(rf[i].last_collision, rr[i].last_collision) << label << " particle " << i;
    ASSERT_EQ(rf[i].image, rr[i].image) << label << " particle " << i;
  }
  // The run kept every disk in the box and apart (at the radii grown to then).
  System<D> grown = fast->system();
  for (Particle<D>& p : grown.particles) p.radius = grown_radius(p.radius, growth_rate, stop);
  EXPECT_FALSE(find_pair_overlap(grown, grown.stored(stop)).has_value()) << label;
  const Box<D>& box = fast->system().box;
  for (auto p : pf) {
    p.radius = grown_radius(p.radius, growth_rate, stop);
    for (int wall = -1; wall >= -2 * static_cast<int>(D) && !box.periodic(); --wall) {
      EXPECT_FALSE(overlaps_wall(p, box, wall)) << label;
    }
    for (std::size_t k = 0; k < D && box.periodic(); ++k) {
      EXPECT_TRUE(p.position[k] >= 0.0 && p.position[k] <= box.size[k]) << label;
    }
  }
}

TEST(CrossCheck, FastEqualsReferenceOnRandomGases) {
  pcg32 rng(20261121);
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t n = 1 + rng() % 40;
    const double lx = uniform(rng, 3, 30), ly = uniform(rng, 3, 30);
    const double r_max = uniform(rng, 0.05, 1.0);
    const bool poly = trial % 3 == 0;
    const System<2> system = random_gas(rng, n, poly ? r_max / 4 : r_max, r_max, lx, ly);
    const CollisionRule rule{trial % 2 ? Rule::elastic : Rule::swap};
    expect_same_runs(
        system, rule, uniform(rng, 1, 60), 300,
        "trial " + std::to_string(trial) + " (" + std::string(name_of(rule.rule)) + ")");
  }
}

TEST(CrossCheck, FastEqualsReferenceOnRandomSpheres) {
  pcg32 rng(20261122);
  for (int trial = 0; trial < 240; ++trial) {
    const std::size_t n = 1 + rng() % 40;
    const double r_max = uniform(rng, 0.1, 0.8);
    const bool periodic = trial % 2 == 1;
    const double least = periodic ? 4.05 * r_max : 2.05 * r_max;
    const Vec<3> size{{uniform(rng, least, 9), uniform(rng, least, 9), uniform(rng, least, 9)}};
    System<3> system =
        carom::testing::random_spheres(rng, n, trial % 3 == 0 ? r_max / 4 : r_max, r_max, size);
    if (periodic) system.box.boundary = Boundary::periodic;
    const CollisionRule rule = trial % 4 < 2 ? CollisionRule{trial % 4 ? Rule::elastic : Rule::swap}
                                             : CollisionRule{Rule::elastic, 0.7, 0.05};
    expect_same_runs(system, rule, uniform(rng, 1, 40), 300,
                     "3D trial " + std::to_string(trial) + " (" + std::string(name_of(rule.rule)) +
                         (periodic ? ", periodic)" : ", walls)"));
  }
}

// Growing particles (carom compress): both engines agree on every event, in 2D and 3D, between
// walls and in periodic boxes down to two diameters (where predictions are renewed at a horizon
// that shrinks as collisions speed the particles up), mono- and polydisperse. Each start is a
// random placement with its radii shrunk by the factor they grow by within the run, so that the
// grown radii fit.
template <std::size_t D>
System<D> shrunk(System<D> system, double scale) {
  for (Particle<D>& p : system.particles) p.radius /= scale;
  return system;
}

TEST(CrossCheck, FastEqualsReferenceWhileGrowing) {
  pcg32 rng(20261123);
  for (int trial = 0; trial < 240; ++trial) {
    const bool periodic = trial % 2 == 1, spheres = trial % 4 >= 2, poly = trial % 3 == 0;
    const std::size_t n = 1 + rng() % 30;
    const double end_time = uniform(rng, 1, 20);
    const double scale = uniform(rng, 1.0, 1.3);
    const double rate = (scale - 1.0) / end_time;
    const std::string label = "growing trial " + std::to_string(trial) + (spheres ? " 3D" : " 2D") +
                              (periodic ? " periodic" : " walls");
    const double r_max = uniform(rng, 0.1, 0.6);
    const double least = (periodic ? 4.05 : 2.05) * r_max;
    if (spheres) {
      const Vec<3> size{{uniform(rng, least, 8), uniform(rng, least, 8), uniform(rng, least, 8)}};
      System<3> system =
          carom::testing::random_spheres(rng, n, poly ? r_max / 3 : r_max, r_max, size);
      if (periodic) system.box.boundary = Boundary::periodic;
      expect_same_runs(shrunk(system, scale), {Rule::elastic}, end_time, 300, label, 0, rate);
    } else {
      System<2> system = random_gas(rng, n, poly ? r_max / 3 : r_max, r_max,
                                    uniform(rng, least, 20), uniform(rng, least, 20));
      if (periodic) system.box.boundary = Boundary::periodic;
      expect_same_runs(shrunk(system, scale), {Rule::elastic}, end_time, 300, label, 0, rate);
    }
  }
}

// Regression guard for the growing image horizon: two nearly still disks in a periodic box of
// two cells collide and leave at the speed of their growth, 400 times their own; they next meet
// around the box, through the other image, at t = 1.83. Predictions must be renewed on the
// horizon of the new speeds (the one of the start speeds is 150 time units long).
TEST(CrossCheck, TheImageHorizonShrinksAsGrowthSpeedsParticlesUp) {
  const System<2> system =
      boxed({4.2, 4.2}, {disk({1.0, 2.1}, {0.001, 0}, 0.5), disk({2.0, 2.1}, {-0.001, 0}, 0.5)},
            Boundary::periodic);
  expect_same_runs(system, {Rule::elastic}, 2.0, 50, "two disks", 0, 0.4);
  auto fast = make_engine(EngineKind::fast, system, {Rule::elastic}, Growth{0.4, 2.0});
  const auto first = fast->step(2.0), second = fast->step(2.0);
  ASSERT_TRUE(first && second);
  EXPECT_EQ(first->time, 0.0);
  // They leave at 2 x 0.4 + 0.002 and the contact distance grows at 0.4: 4.2 - 1 - 0.802 t = 1 +
  // 0.4 t.
  EXPECT_NEAR(second->time, 2.2 / 1.202, 1e-12);
}

System<2> periodic(System<2> system) {
  system.box.boundary = Boundary::periodic;
  return system;
}

TEST(CrossCheck, FastEqualsReferenceInPeriodicBoxes) {
  pcg32 rng(99);
  for (int trial = 0; trial < 200; ++trial) {
    const double r_max = uniform(rng, 0.1, 0.6);
    // Sides from just over two diameters (the smallest allowed: images within reach, renewal by
    // horizon) to many cells.
    const double lx = uniform(rng, 4.05 * r_max, 25), ly = uniform(rng, 4.05 * r_max, 25);
    const bool poly = trial % 3 == 0;
    const System<2> system =
        periodic(random_gas(rng, 1 + rng() % 40, poly ? r_max / 3 : r_max, r_max, lx, ly));
    const CollisionRule rule{trial % 2 ? Rule::elastic : Rule::swap};
    expect_same_runs(system, rule, uniform(rng, 1, 40), 300,
                     "periodic trial " + std::to_string(trial));
  }
}

TEST(CrossCheck, PairsOnFarEdgesOfAdjacentCellsAreSeenThroughTheRightImage) {
  // Regression (found by the fuzzer): four cells across a periodic axis, two disks crossing into
  // adjacent cells at the same instant, exactly half a box apart: the fast engine took the other
  // image and missed their collision.
  const System<2> system = boxed(
      {10, 11}, {disk({2, 2}, {0.2, -0.5}, 0.5), disk({7, 7}, {-1, 1}, 1)}, Boundary::periodic);
  System<2> heavy = system;
  heavy.records[0].mass = 2;
  expect_same_runs(heavy, {Rule::elastic}, 1000.0, 200, "half-box image");
}

TEST(CrossCheck, FastEqualsReferenceInPeriodicLattices) {
  pcg32 rng(5);
  for (int trial = 0; trial < 40; ++trial) {
    const System<2> system =
        periodic(square_lattice(rng, 3 + rng() % 7, 0.5, trial % 2 ? 0.0 : 0.2, trial % 4 < 2));
    expect_same_runs(system, {Rule::elastic}, 30.0, 400,
                     "periodic lattice " + std::to_string(trial));
  }
}

TEST(CrossCheck, FastEqualsReferenceForInelasticDisks) {
  pcg32 rng(17);
  for (int trial = 0; trial < 60; ++trial) {
    System<2> system =
        random_gas(rng, 2 + rng() % 30, 0.3, 0.6, uniform(rng, 5, 15), uniform(rng, 5, 15));
    if (trial % 2) system = periodic(system);
    const CollisionRule rule{Rule::elastic, uniform(rng, 0.3, 0.99), trial % 3 ? 1e-3 : 0.0};
    expect_same_runs(system, rule, 30.0, 400, "inelastic " + std::to_string(trial));
  }
}

TEST(CrossCheck, FastEqualsReferenceOnDenseLatticesWithTies) {
  pcg32 rng(7);
  for (int trial = 0; trial < 60; ++trial) {
    const bool aligned = trial % 2 == 0;
    // Gap 0: every neighbour starts touching; aligned velocities make many equal event times.
    const double gap = trial % 3 == 0 ? 0.0 : uniform(rng, 0.01, 0.5);
    const System<2> system = square_lattice(rng, 2 + rng() % 6, 0.5, gap, aligned);
    const CollisionRule rule{trial % 4 < 2 ? Rule::swap : Rule::elastic};
    expect_same_runs(system, rule, 20.0, 400, "lattice " + std::to_string(trial));
  }
}

TEST(CrossCheck, FastEqualsReferenceOnTouchingSphereLatticesWithTies) {
  pcg32 rng(8);
  for (int trial = 0; trial < 80; ++trial) {
    // Gap 0: every neighbour starts touching, and aligned velocities tie many event times.
    const double gap = trial % 3 == 0 ? 0.0 : uniform(rng, 0.01, 0.5);
    System<3> system =
        carom::testing::cubic_lattice<3>(rng, 2 + rng() % 3, 0.5, gap, trial % 2 == 0);
    // A periodic box needs sides over two diameters: three cells or more.
    if (trial % 4 >= 2 && system.box.size[0] > 2.0) system.box.boundary = Boundary::periodic;
    const CollisionRule rule = trial % 5 == 0   ? CollisionRule{Rule::elastic, 0.8, 0.01}
                               : trial % 2 == 0 ? CollisionRule{Rule::swap}
                                                : CollisionRule{Rule::elastic};
    expect_same_runs(system, rule, 20.0, 400, "sphere lattice " + std::to_string(trial));
  }
}

TEST(CrossCheck, FastEqualsReferenceAtFiveHundredSpheres) {
  pcg32 rng(12);
  System<3> system = carom::testing::cubic_lattice<3>(rng, 8, 0.5, 0.15, false);
  system.box.boundary = Boundary::periodic;
  expect_same_runs(system, {Rule::elastic}, 1e9, 1500, "N=512 periodic spheres");
}

TEST(CrossCheck, FastEqualsReferenceAtFiveHundredDisks) {
  pcg32 rng(11);
  const System<2> system = square_lattice(rng, 22, 0.5, 0.15, false);
  expect_same_runs(system, {Rule::elastic}, 1e9, 3000, "N=484");
}

TEST(CrossCheck, FastEqualsReferenceOnAssignmentCases) {
  for (const char* name : {"normal.txt", "particles1.txt", "particles_only.txt"}) {
    expect_same_runs(case_system(name), {Rule::swap}, 1000.0, 100000, name);
  }
}

// The neighbour-list engine on dense starts, where make_engine chooses it for spheres; disks run
// through it here too (make_engine keeps them in cells), as do walls, mixtures up to the size
// ratio of two and every rule.
template <std::size_t D>
void check_lists_against_reference(std::uint64_t seed, int trials, int events) {
  pcg32 rng(seed);
  int checked_trials = 0;
  for (int trial = 0; trial < trials; ++trial) {
    InitialOptions options;
    options.n = 20 + rng() % (D == 2 ? 200 : 150);
    options.packing_fraction =
        D == 2 ? uniform(rng, 0.25, 0.8) : uniform(rng, 0.2, trial % 4 == 0 ? 0.7 : 0.5);
    options.polydispersity = trial % 3 == 0 ? uniform(rng, 0.0, 0.15) : 0.0;
    options.boundary = trial % 2 == 0 ? Boundary::periodic : Boundary::walls;
    options.seed = rng();
    System<D> system;
    try {
      system = make_initial<D>(options);
    } catch (const InitialError&) {
      continue;  // a random placement that jammed: another trial
    }
    const CollisionRule rule = trial % 5 == 0   ? CollisionRule{Rule::elastic, 0.8, 1e-3}
                               : trial % 7 == 0 ? CollisionRule{Rule::swap}
                                                : CollisionRule{Rule::elastic};
    const std::string label = std::to_string(D) + "D lists trial " + std::to_string(trial) +
                              " (N = " + std::to_string(options.n) + ", phi " +
                              std::to_string(options.packing_fraction) +
                              (options.boundary == Boundary::periodic ? ", periodic)" : ", walls)");
    if (!ListEngine<D>::suits(system, {})) continue;  // a periodic box too small for lists
    // An inelastic gas cools and its collisions spread out in time, which the reference engine
    // (windows of the image horizon, all pairs each) pays dearly for: fewer events then.
    const int checked = rule.restitution < 1.0 ? events / 5 : events;
    // Each kernel in turn.
    const Checked engine = trial % 3 == 0   ? Checked::lists
                           : trial % 3 == 1 ? Checked::lists_avx2
                                            : Checked::lists_scalar;
    expect_same_runs(system, rule, 1e9, checked, label, 37 + trial % 200, 0.0, engine);
    ++checked_trials;
  }
  EXPECT_GE(checked_trials, trials / 2);
}

TEST(CrossCheck, ListsEqualReferenceForDenseSpheres) {
  check_lists_against_reference<3>(20261123, 40, 2000);
}

TEST(CrossCheck, ListsEqualReferenceForDenseDisks) {
  check_lists_against_reference<2>(20261124, 40, 2000);
}

TEST(CrossCheck, ListsEqualReferenceOnTouchingSphereLatticesWithTies) {
  pcg32 rng(81);
  for (int trial = 0; trial < 20; ++trial) {
    const double gap = trial % 3 == 0 ? 0.0 : uniform(rng, 0.01, 0.2);
    System<3> system =
        carom::testing::cubic_lattice<3>(rng, 4 + rng() % 3, 0.5, gap, trial % 2 == 0);
    if (trial % 4 >= 2) system.box.boundary = Boundary::periodic;
    if (!ListEngine<3>::suits(system, {})) continue;
    const CollisionRule rule{trial % 2 == 0 ? Rule::swap : Rule::elastic};
    expect_same_runs(system, rule, 20.0, 1500, "sphere lattice, lists " + std::to_string(trial),
                     37, 0.0, Checked::lists);
  }
}

TEST(CrossCheck, CellsEqualReferenceForDenseSpheres) {
  // make_engine gives dense spheres lists: the cell engine is checked on them here.
  pcg32 rng(82);
  InitialOptions options;
  options.n = 200;
  options.packing_fraction = 0.45;
  options.boundary = Boundary::periodic;
  expect_same_runs(make_initial<3>(options), {Rule::elastic}, 1e9, 3000, "cells, spheres 0.45",
                   37, 0.0, Checked::cells);
}

TEST(ListEngine, ServesDenseSystemsOfSimilarSizesThatDoNotGrow) {
  InitialOptions options;
  options.n = 500;
  options.packing_fraction = 0.45;
  options.boundary = Boundary::periodic;
  const System<3> dense = make_initial<3>(options);
  EXPECT_TRUE(ListEngine<3>::suits(dense, {}));
  EXPECT_FALSE(ListEngine<3>::suits(dense, Growth{0.01, 1.0}));
  System<3> mixed = dense;
  mixed.particles[0].radius = 0.2;  // the largest more than twice the smallest
  EXPECT_FALSE(ListEngine<3>::suits(mixed, {}));
  options.packing_fraction = 0.1;
  EXPECT_FALSE(ListEngine<3>::suits(make_initial<3>(options), {}));
  options.n = 20;  // a box of side 3.6: the lists' reach of 3 diameters is more than half of it
  options.packing_fraction = 0.45;
  EXPECT_FALSE(ListEngine<3>::suits(make_initial<3>(options), {}));
}

TEST(ListEngine, ListsAreSymmetricAndHoldEveryPairWithinReach) {
  InitialOptions options;
  options.n = 400;
  options.packing_fraction = 0.5;
  options.boundary = Boundary::periodic;
  ListEngine<3> engine(make_initial<3>(options), {Rule::elastic});
  for (int e = 0; e < 20000; ++e) ASSERT_TRUE(engine.step(kNever));
  const System<3>& system = engine.system();
  const double shell = engine.shell(), reach = 2.0 * (0.5 + shell);
  EXPECT_EQ(shell, ListEngine<3>::skin(0.5) * 0.5);
  const auto n = static_cast<std::uint32_t>(system.size());
  std::size_t pairs = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::vector<std::uint32_t> list = engine.neighbours(i);
    // No particle has left its shell.
    const Vec<3> moved = position_at(system.particles[i], engine.stored_time()) -
                         engine.shell_centre(i);
    EXPECT_LE(std::sqrt(norm2(moved)), shell * (1 + 1e-9)) << "particle " << i;
    for (std::uint32_t j = 0; j < n; ++j) {
      if (j == i) continue;
      Vec<3> apart = engine.shell_centre(i) - engine.shell_centre(j);
      apart -= image_offset(apart, system.box);
      const bool listed = std::find(list.begin(), list.end(), j) != list.end();
      const std::vector<std::uint32_t> other = engine.neighbours(j);
      EXPECT_EQ(listed, std::find(other.begin(), other.end(), i) != other.end())
          << i << " and " << j;
      if (norm2(apart) < reach * reach * (1 - 1e-6)) {
        EXPECT_TRUE(listed) << j << " within reach of " << i;
        ++pairs;
      }
    }
  }
  EXPECT_GT(pairs, 10u * n);  // about 13 neighbours each at this density
}

TEST(ShellExitDelay, EndsOnTheShellWithoutCancellation) {
  EXPECT_EQ(shell_exit_delay(Vec<3>{{0, 0, 0}}, Vec<3>{{0, 0, 0}}, 0.25), kNever);
  EXPECT_EQ(shell_exit_delay(Vec<3>{{0.3, 0, 0}}, Vec<3>{{1, 0, 0}}, 0.25), 0.0);
  EXPECT_DOUBLE_EQ(shell_exit_delay(Vec<3>{{0, 0, 0}}, Vec<3>{{2, 0, 0}}, 0.25), 0.125);
  EXPECT_DOUBLE_EQ(shell_exit_delay(Vec<3>{{0.2, 0, 0}}, Vec<3>{{-1, 0, 0}}, 0.25), 0.45);
  EXPECT_DOUBLE_EQ(shell_exit_delay(Vec<3>{{0.2, 0, 0}}, Vec<3>{{1, 0, 0}}, 0.25), 0.05);
  // Moving outward from near the shell: the root -b + sqrt(b^2 - v^2 c) would cancel.
  const double delay = shell_exit_delay(Vec<2>{{0.25 - 1e-12, 0}}, Vec<2>{{1e6, 0}}, 0.25);
  EXPECT_NEAR(delay, 1e-18, 1e-21);
  pcg32 rng(3);
  for (int trial = 0; trial < 10000; ++trial) {
    Vec<3> offset, velocity;
    for (std::size_t k = 0; k < 3; ++k) {
      offset[k] = uniform(rng, -0.14, 0.14);
      velocity[k] = uniform(rng, -3, 3);
    }
    const double t = shell_exit_delay(offset, velocity, 0.25);
    EXPECT_NEAR(std::sqrt(norm2(offset + velocity * t)), 0.25, 1e-14);
  }
}

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

TEST(Invariants, FindViolationNamesOverlapsAndWalls) {
  EXPECT_EQ(find_violation(boxed({10, 10}, {disk({3, 3}, {1, 0}, 1), disk({5, 3}, {0, 0}, 1)}), 0),
            std::nullopt);
  EXPECT_EQ(
      find_violation(boxed({10, 10}, {disk({3, 3}, {1, 0}, 1), disk({4.5, 3}, {0, 0}, 1)}), 0),
      "particles 0 and 1 overlap: centres 1.5 apart, contact at 2");
  // Moved to the asked time: at t = 2 the disk is through the right wall.
  EXPECT_EQ(find_violation(boxed({10, 10}, {disk({8, 3}, {1, 0}, 1)}), 2.0),
            "particle 0 at 10, 3 reaches through the right wall");
  // Periodic boxes have no walls, and overlaps are seen through the boundary.
  EXPECT_EQ(find_violation(boxed({10, 10}, {disk({8, 3}, {1, 0}, 1)}, Boundary::periodic), 2.0),
            std::nullopt);
  EXPECT_NE(find_violation(boxed({10, 10}, {disk({0.5, 3}, {0, 0}, 1), disk({9, 3}, {0, 0}, 1)},
                                 Boundary::periodic),
                           0),
            std::nullopt);
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
