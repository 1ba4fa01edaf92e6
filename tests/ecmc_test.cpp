// Event-chain Monte Carlo's engine (src/engine/ecmc_engine.hpp), tested alone: its lifts are the
// swap rule's collisions of one moving particle, they never let particles overlap, a run in
// pieces is the run in one, and its pressure is the hard-disk equation of state.
#include <gtest/gtest.h>

#include <cmath>
#include <pcg_random.hpp>
#include <random>
#include <vector>

#include "carom/core/equation_of_state.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/overlap.hpp"
#include "engine/ecmc_engine.hpp"
#include "engine/reference_engine.hpp"

namespace carom {
namespace {

// Placed at random where random sequential addition reaches (below its saturation, 0.547 for
// disks and 0.384 for spheres): a lattice's exact symmetries make exact ties, which the chains
// and the reference engine may break differently.
template <std::size_t D>
System<D> periodic_start(std::uint64_t n, double phi, std::uint64_t seed) {
  InitialOptions options;
  options.placement = phi < (D == 2 ? 0.54 : 0.38) ? Placement::random : Placement::lattice;
  options.n = n;
  options.packing_fraction = phi;
  options.boundary = Boundary::periodic;
  options.seed = seed;
  return make_initial<D>(options);
}

TEST(Physics, LiftDistanceIsTheUnitVelocityContactBitForBit) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  int lifts = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    const Vec<3> r{coordinate(random), coordinate(random), coordinate(random)};
    const std::size_t axis = static_cast<std::size_t>(trial % 3);
    Vec<3> unit{};
    unit[axis] = 1.0;
    const double lift = lift_distance(r, axis, 1.3);
    ASSERT_EQ(lift, earliest_contact(0.0, r, unit, 1.3, kNever)) << trial;
    lifts += lift != kNever;
  }
  EXPECT_GT(lifts, 1000);
  // Near contact the distance keeps its digits: no cancellation.
  const Vec<2> touching{-(1.0 + 1e-12), 0.0};
  EXPECT_NEAR(lift_distance(touching, 0, 1.0), 1e-12, 1e-16);
  EXPECT_EQ(lift_distance(Vec<2>{0.5, 0.0}, 0, 1.0), kNever);   // behind
  EXPECT_EQ(lift_distance(Vec<2>{-0.5, 0.0}, 0, 1.0), 0.0);     // overlapping: at once
  EXPECT_EQ(lift_distance(Vec<2>{-3.0, 1.5}, 0, 1.0), kNever);  // passes beside
}

// Every lift is a contact, and no pair ever overlaps.
TEST(Ecmc, LiftsTouchAndNeverOverlap) {
  for (double phi : {0.3, 0.7}) {
    EcmcEngine<2> engine(periodic_start<2>(200, phi, 3), 5.0, pcg32(11));
    for (int k = 0; k < 20000; ++k) {
      const std::optional<Event> event = engine.step(kNever);
      ASSERT_TRUE(event.has_value());
      ASSERT_FALSE(event->is_wall());
      const double touching = std::sqrt(norm2(Vec<2>{event->contact[0], event->contact[1]}));
      ASSERT_NEAR(touching, 1.0, 1e-9) << "lift " << k << " at phi " << phi;
      if (k % 500 == 0) {
        ASSERT_FALSE(find_pair_overlap(engine.system(), engine.stored_time()).has_value())
            << "after lift " << k << " at phi " << phi;
      }
    }
  }
}

// Lifts of a mover with every other particle at rest are the swap rule's collisions: the
// reference engine, every pair checked after every event, finds the same partners at the same
// times (to round-off: its states move by time, the chain's by distance).
TEST(Ecmc, LiftsAreTheSwapRulesCollisionsOfOneMover) {
  for (int dimension : {2, 3}) {
    const auto check = [&]<std::size_t D>(System<D> start) {
      EcmcEngine<D> chains(start, 1e9, pcg32(5));
      System<D> one_mover = chains.system();
      ReferenceEngine<D> reference(one_mover, {Rule::swap, 1.0, 0.0});
      for (int k = 0; k < 300; ++k) {
        const std::optional<Event> lift = chains.step(kNever);
        const std::optional<Event> collision = reference.step(kNever);
        ASSERT_TRUE(lift && collision);
        ASSERT_EQ(lift->first, collision->first) << "event " << k;
        ASSERT_EQ(lift->partner, collision->partner) << "event " << k;
        ASSERT_NEAR(lift->time, collision->time, 1e-9 * (1.0 + collision->time)) << "event " << k;
      }
    };
    if (dimension == 2) check(periodic_start<2>(64, 0.5, 2));
    if (dimension == 3) check(periodic_start<3>(64, 0.3, 2));
  }
}

// Stopping anywhere and going on gives the same chains, bit for bit.
TEST(Ecmc, AnyPiecesGiveTheSameRun) {
  EcmcEngine<3> whole(periodic_start<3>(100, 0.3, 4), 3.0, pcg32(9));
  EcmcEngine<3> pieces(periodic_start<3>(100, 0.3, 4), 3.0, pcg32(9));
  while (whole.step(2.0)) {
  }
  for (double end = 0.0137; end < 2.0; end += 0.0137) {
    while (pieces.step(end)) {
    }
  }
  while (pieces.step(2.0)) {
  }
  ASSERT_EQ(whole.system().particles.size(), pieces.system().particles.size());
  for (std::size_t i = 0; i < whole.system().size(); ++i) {
    EXPECT_EQ(whole.system().particles[i].position, pieces.system().particles[i].position) << i;
    EXPECT_EQ(whole.system().particles[i].time, pieces.system().particles[i].time) << i;
  }
  EXPECT_EQ(whole.chain().active, pieces.chain().active);
}

// Z = 1 + (sum of the lifts' separations along the move) / (the displacement): from the lifts'
// virials, r . dp = v dx with unit masses, over v^2 t.
TEST(Ecmc, PressureIsTheHardDiskEquationOfState) {
  const double phi = 0.5;
  EcmcEngine<2> engine(periodic_start<2>(400, phi, 6), 10.0, pcg32(1));
  const double equilibrated = 20.0, end = 220.0;
  while (engine.step(equilibrated)) {
  }
  double virial = 0.0;
  while (const std::optional<Event> event = engine.step(end)) virial += event->impulse;
  const double v = engine.speed();
  const double z = 1.0 + virial / (v * v * (end - equilibrated));
  EXPECT_NEAR(z, henderson_z(phi), 0.02 * henderson_z(phi));
}

}  // namespace
}  // namespace carom
