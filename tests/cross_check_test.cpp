// The fast engines (cells, neighbour lists, their kernels) against the reference engine, event for
// event, bit for bit, on random and adversarial systems.
#include <gtest/gtest.h>

#include <cmath>

#include "carom/engine/engine.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/overlap.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/run_report.hpp"
#include "engine/fast_engine.hpp"
#include "engine/list_engine.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

using carom::testing::boxed;
using carom::testing::case_system;
using carom::testing::disk;
using carom::testing::random_gas;
using carom::testing::square_lattice;
using carom::testing::uniform;

// The engine a cross-check runs against the reference: the default fast engine, or one of its
// structures or kernels forced.
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
    // What the pressure tensor and the transport moments are made of (fluxes.hpp).
    ASSERT_EQ(a->momentum, b->momentum) << label << " event " << events;
    ASSERT_EQ(a->contact, b->contact) << label << " event " << events;
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
    expect_same_runs(system, rule, 20.0, 1500, "sphere lattice, lists " + std::to_string(trial), 37,
                     0.0, Checked::lists);
  }
}

TEST(CrossCheck, CellsEqualReferenceForDenseSpheres) {
  // make_engine gives dense spheres lists: the cell engine is checked on them here.
  pcg32 rng(82);
  InitialOptions options;
  options.n = 200;
  options.packing_fraction = 0.45;
  options.boundary = Boundary::periodic;
  expect_same_runs(make_initial<3>(options), {Rule::elastic}, 1e9, 3000, "cells, spheres 0.45", 37,
                   0.0, Checked::cells);
}

// Lees-Edwards: random gases in sheared periodic boxes, at random rates and starting offsets
// (elastic and inelastic), against the reference engine.
template <std::size_t D>
void check_sheared_against_reference(std::uint64_t seed, int trials, std::size_t most, int events) {
  pcg32 rng(seed);
  for (int trial = 0; trial < trials; ++trial) {
    const std::size_t n = 2 + rng() % most;
    const double r_max = uniform(rng, 0.1, 0.8);
    Vec<D> size;
    for (std::size_t k = 0; k < D; ++k) size[k] = uniform(rng, 4.05 * r_max, D == 2 ? 30 : 10);
    System<D> system;
    if constexpr (D == 2) {
      system = random_gas(rng, n, trial % 3 == 0 ? r_max / 4 : r_max, r_max, size[0], size[1]);
    } else {
      system =
          carom::testing::random_spheres(rng, n, trial % 3 == 0 ? r_max / 4 : r_max, r_max, size);
    }
    system.box.boundary = Boundary::periodic;
    system.box.shear_rate = (trial % 2 ? 1.0 : -1.0) * uniform(rng, 0.01, 2.0);
    system.box.shear_offset = trial % 4 < 2 ? 0.0 : uniform(rng, 0.0, size[0]);
    const CollisionRule rule =
        trial % 5 == 4 ? CollisionRule{Rule::elastic, 0.8, 0.05} : CollisionRule{Rule::elastic};
    expect_same_runs(system, rule, uniform(rng, 1, 40), events,
                     std::string(D == 2 ? "sheared" : "sheared 3D") + " trial " +
                         std::to_string(trial) + " (rate " + std::to_string(system.box.shear_rate) +
                         ")");
  }
}

TEST(CrossCheck, FastEqualsReferenceInShearedBoxes) {
  check_sheared_against_reference<2>(20261125, 200, 40, 400);
  check_sheared_against_reference<3>(20261126, 120, 40, 400);
}

TEST(CrossCheck, FastEqualsReferenceForDenseShearedSystems) {
  // Many cells along x, so that an edge row's partners across the boundary lie far from its own
  // columns, and a fast shear that carries images across many of them.
  for (const double rate : {0.05, 3.0}) {
    InitialOptions options;
    options.n = 300;
    options.packing_fraction = 0.5;
    options.boundary = Boundary::periodic;
    System<2> disks = make_initial<2>(options);
    disks.box.shear_rate = rate;
    expect_same_runs(disks, {Rule::elastic}, 1e9, 3000,
                     "sheared disks at rate " + std::to_string(rate));
    options.n = 250;
    options.packing_fraction = 0.4;
    System<3> spheres = make_initial<3>(options);
    spheres.box.shear_rate = -rate;
    expect_same_runs(spheres, {Rule::elastic}, 1e9, 3000,
                     "sheared spheres at rate " + std::to_string(rate));
  }
}

}  // namespace
}  // namespace carom
