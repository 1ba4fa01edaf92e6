// The physics functions alone: free flight, wall hits, pair contacts and collision rules.
#include "carom/core/physics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "carom/core/event.hpp"

namespace carom {
namespace {

Particle<2> disk(double x, double y, double vx, double vy, double r = 1.0, double t = 0.0) {
  Particle<2> p;
  p.position = {x, y};
  p.velocity = {vx, vy};
  p.radius = r;
  p.time = t;
  return p;
}

const Box<2> kBox{{20.0, 10.0}};

TEST(WallLabels, FollowTheSeed) {
  EXPECT_EQ(wall_label(0, false), -1);
  EXPECT_EQ(wall_label(0, true), -2);
  EXPECT_EQ(wall_label(1, false), -3);
  EXPECT_EQ(wall_label(1, true), -4);
  EXPECT_EQ(wall_axis(-4), 1u);
  EXPECT_TRUE(wall_is_upper(-2));
  EXPECT_FALSE(wall_is_upper(-3));
  EXPECT_EQ(wall_name(-1), "left");
  EXPECT_EQ(wall_name(-4), "top");
}

TEST(PositionAt, MovesAlongTheLineFromTheStoredTime) {
  const Particle<2> p = disk(1, 2, 0.5, -1, 1, 4);
  EXPECT_EQ(position_at(p, 6.0), (Vec2{{2.0, 0.0}}));
  EXPECT_EQ(position_at(p, 4.0), (Vec2{{1.0, 2.0}}));
}

TEST(NextWallHit, FindsTheNearestWallInTheDirectionOfMotion) {
  // The classic assignment's walls_only disk 0: reaches the left wall (x = R = 0.2) at t = 9.5.
  const WallHit left = next_wall_hit(disk(2.1, 5, -0.2, -0.15, 0.2), kBox);
  EXPECT_DOUBLE_EQ(left.time, 9.5);
  EXPECT_EQ(left.label, -1);
  const WallHit top = next_wall_hit(disk(7, 8.5, -0.25, 0.1, 0.2), kBox);
  EXPECT_DOUBLE_EQ(top.time, 13.0);
  EXPECT_EQ(top.label, -4);
  const WallHit right = next_wall_hit(disk(18, 7, 0.1, -0.2, 0.2), kBox);
  EXPECT_DOUBLE_EQ(right.time, 18.0);
  EXPECT_EQ(right.label, -2);
}

TEST(NextWallHit, CountsFromTheStoredTime) {
  EXPECT_DOUBLE_EQ(next_wall_hit(disk(5, 5, 1, 0, 1, 3.0), kBox).time, 3.0 + 14.0);
}

TEST(NextWallHit, ZeroVelocityComponentMeansNoWallOnThatAxis) {
  const WallHit hit = next_wall_hit(disk(5, 5, 0, 2, 1), kBox);
  EXPECT_EQ(hit.label, -4);
  EXPECT_DOUBLE_EQ(hit.time, 2.0);
  EXPECT_EQ(next_wall_hit(disk(5, 5, 0, 0, 1), kBox).time, kNever);
  EXPECT_EQ(next_wall_hit(disk(5, 5, -0.0, 0.0, 1), kBox).time, kNever);
}

TEST(NextWallHit, TouchingAndMovingInHitsAtOnceMovingAwayNever) {
  const WallHit in = next_wall_hit(disk(1, 5, -1, 0, 1, 2.5), kBox);
  EXPECT_EQ(in.time, 2.5);
  EXPECT_EQ(in.label, -1);
  EXPECT_EQ(next_wall_hit(disk(1, 5, 1, 0, 1), kBox).label, -2);  // away: the far wall
  // Overlapping the wall by round-off while moving in: at once, never before the stored time.
  EXPECT_EQ(next_wall_hit(disk(1 - 1e-15, 5, -1, 0, 1, 7.0), kBox).time, 7.0);
  EXPECT_EQ(next_wall_hit(disk(19 + 1e-14, 5, 1, 0, 1, 7.0), kBox).time, 7.0);
}

TEST(NextWallHit, CornerTieGoesToTheXWallFirst) {
  const WallHit hit = next_wall_hit(disk(2, 2, -1, -1, 1), kBox);
  EXPECT_EQ(hit.time, 1.0);
  EXPECT_EQ(hit.label, -1);
}

TEST(ContactTime, HeadOnApproach) {
  // Centres 10 apart, closing at 2, contact at distance 2: t = 4.
  EXPECT_DOUBLE_EQ(contact_time(disk(0, 0, 1, 0), disk(10, 0, -1, 0)), 4.0);
}

TEST(ContactTime, SeedParticlesOnlyCase) {
  // Disks 1 and 2 of the classic assignment's particles_only case touch at t = 14.001202.
  const double t = contact_time(disk(1.5, 12, 0.4, 0.05), disk(2.5, 19, 0.3, -0.31));
  EXPECT_NEAR(t, 14.001202, 5e-7);
}

TEST(ContactTime, BringsBothToTheLaterStoredTime) {
  // b was stored at t = 2 at x = 8; at t = 2, a is at x = 2: 6 apart, closing at 2, touching at 2
  // apart: 2 time units after t = 2.
  EXPECT_DOUBLE_EQ(contact_time(disk(0, 0, 1, 0, 1, 0.0), disk(8, 0, -1, 0, 1, 2.0)), 4.0);
}

TEST(ContactTime, SeparatingOrParallelPairsNeverCollide) {
  EXPECT_EQ(contact_time(disk(0, 0, -1, 0), disk(10, 0, 1, 0)), kNever);
  EXPECT_EQ(contact_time(disk(0, 0, 1, 0), disk(10, 0, 1, 0)), kNever);
  EXPECT_EQ(contact_time(disk(0, 0, 0, 1), disk(10, 0, 0, 1)), kNever);
}

TEST(ContactTime, MissingPairsNeverCollide) {
  // Passing with 3 between the lines of motion, more than the contact distance 2.
  EXPECT_EQ(contact_time(disk(0, 0, 1, 0), disk(10, 3, -1, 0)), kNever);
}

TEST(ContactTime, GrazingPairCollidesAtTheTangentPoint) {
  // Lines of motion exactly 2 apart: discriminant zero, one root at closest approach.
  EXPECT_DOUBLE_EQ(contact_time(disk(0, 0, 1, 0), disk(10, 2, -1, 0)), 5.0);
}

TEST(ContactTime, TouchingOrOverlappingApproachCollidesAtOnceSeparationNever) {
  EXPECT_EQ(contact_time(disk(0, 0, 1, 0, 1, 3.0), disk(2, 0, -1, 0, 1, 3.0)), 3.0);
  EXPECT_EQ(contact_time(disk(0, 0, 1, 0, 1, 3.0), disk(2 - 1e-13, 0, 0, 0, 1, 1.0)), 3.0);
  EXPECT_EQ(contact_time(disk(0, 0, -1, 0), disk(2, 0, 1, 0)), kNever);
  EXPECT_EQ(contact_time(disk(0, 0, -1, 0), disk(2 - 1e-13, 0, 1, 0)), kNever);
}

TEST(ContactTime, UsesEachParticlesOwnRadius) {
  EXPECT_DOUBLE_EQ(contact_time(disk(0, 0, 1, 0, 0.5), disk(10, 0, 0, 0, 1.5)), 8.0);
}

TEST(ContactTime, IsSymmetricBitForBit) {
  const Particle<2> a = disk(0.1, 0.7, 0.31, -0.12, 0.3, 0.25);
  const Particle<2> b = disk(2.9, 0.2, -0.77, 0.05, 0.3, 1.75);
  EXPECT_EQ(contact_time(a, b), contact_time(b, a));
}

// contact_time moves only the particle with the earlier stored time (the other's position at its
// own time is its stored position): the same times, bit for bit, as moving both, which the
// engines' histories were made with. Integer-valued times and positions give exact zeros too.
TEST(ContactTime, MovingOnlyTheEarlierParticleChangesNoTime) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  std::uniform_int_distribution<int> small(-2, 2);
  const auto both_moved = [](const Particle<2>& a, const Particle<2>& b, const Vec2& offset) {
    const double t0 = std::max(a.time, b.time);
    const Vec2 r = position_at(a, t0) - position_at(b, t0) - offset;
    const Vec2 v = a.velocity - b.velocity;
    const double rv = dot(r, v);
    if (!(rv < 0.0)) return kNever;
    const double sigma = a.radius + b.radius, c = norm2(r) - sigma * sigma;
    if (c <= 0.0) return t0;
    const double discriminant = rv * rv - norm2(v) * c;
    return discriminant < 0.0 ? kNever : t0 + c / (-rv + std::sqrt(discriminant));
  };
  int collide = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    const bool exact = trial % 2 == 0;
    const auto value = [&] { return exact ? double(small(rng)) : uniform(rng); };
    const Particle<2> a{{{value(), value()}}, {{value(), value()}}, value(), 0.5};
    const Particle<2> b{{{value(), value()}}, {{value(), value()}}, value(), 0.25};
    const Vec2 offset{{trial % 3 == 0 ? 10.0 : 0.0, 0.0}};
    const double expected = both_moved(a, b, offset);
    collide += expected != kNever;
    ASSERT_EQ(contact_time(a, b, offset), expected) << trial;
  }
  EXPECT_GT(collide, 5000);  // many pairs collide, and the early exits are exercised too
}

TEST(ContactTime, NoCancellationForAlmostTouchingFastPairs) {
  // A gap of 1e-12 closed at speed 1e6: the naive (-b - sqrt(d)) / a form loses every digit.
  const Particle<2> a = disk(0, 0, 1e6, 0);
  const Particle<2> b = disk(2 + 1e-12, 0, 0, 0);
  const double t = contact_time(a, b);
  EXPECT_GT(t, 0.0);
  EXPECT_NEAR(t, 1e-18, 1e-21);
}

TEST(Collide, SwapExchangesWholeVelocities) {
  Particle<2> a = disk(0, 0, 1, 2), b = disk(2, 0, -3, 4);
  const double virial = collide(a, b, a.position - b.position, Rule::swap, 1.0, 1.0, 1.0);
  EXPECT_EQ(a.velocity, (Vec2{{-3, 4}}));
  EXPECT_EQ(b.velocity, (Vec2{{1, 2}}));
  EXPECT_EQ(virial, 1.0 * dot(Vec2{{-2, 0}}, Vec2{{-4, 2}}));  // r . (m_a dv_a)
}

TEST(Collide, ElasticExchangesTheNormalComponentOnly) {
  Particle<2> a = disk(0, 0, 1, 2), b = disk(2, 0, -3, 4);
  collide(a, b, a.position - b.position, Rule::elastic, 1.0, 1.0, 1.0);
  EXPECT_EQ(a.velocity, (Vec2{{-3, 2}}));
  EXPECT_EQ(b.velocity, (Vec2{{1, 4}}));
}

TEST(Collide, ElasticConservesMomentumAndEnergyWithMasses) {
  Particle<2> a = disk(0, 0, 0.3, -0.7), b = disk(1.2, 1.6, -0.4, -0.9);
  const double ma = 2.0, mb = 0.5;
  const Vec2 p0 = ma * a.velocity + mb * b.velocity;
  const double e0 = ma * norm2(a.velocity) + mb * norm2(b.velocity);
  collide(a, b, a.position - b.position, Rule::elastic, 1.0, ma, mb);
  const Vec2 p1 = ma * a.velocity + mb * b.velocity;
  EXPECT_NEAR(p1[0], p0[0], 1e-15);
  EXPECT_NEAR(p1[1], p0[1], 1e-15);
  EXPECT_NEAR(ma * norm2(a.velocity) + mb * norm2(b.velocity), e0, 1e-15);
  // After the collision the pair separates.
  EXPECT_GT(dot(a.position - b.position, a.velocity - b.velocity), 0.0);
}

TEST(Bounce, FlipsOneComponentAndPutsTheDiskOnTheWall) {
  Particle<2> p = disk(0.2000000000000002, 3, -0.2, -0.15, 0.2);
  EXPECT_EQ(bounce(p, -1, kBox, 3.0), 3.0 * 2 * 0.2);  // the momentum given to the wall
  EXPECT_EQ(p.position, (Vec2{{0.2, 3}}));
  EXPECT_EQ(p.velocity, (Vec2{{0.2, -0.15}}));
  Particle<2> q = disk(5, 9.8, 1, 0.5, 0.2);
  bounce(q, -4, kBox, 1.0);
  EXPECT_EQ(q.position, (Vec2{{5, 9.8}}));
  EXPECT_EQ(q.velocity, (Vec2{{1, -0.5}}));
}

TEST(EventKey, OrdersByTimeThenParticleThenWallsBeforeParticles) {
  const auto key = [](double t, std::uint32_t i, std::int32_t partner) {
    return key_of<2>(Event{t, i, partner});
  };
  EXPECT_LT(key(1.0, 5, 6), key(2.0, 0, 1));
  EXPECT_LT(key(1.0, 0, 9), key(1.0, 1, 2));
  EXPECT_LT(key(1.0, 3, -1), key(1.0, 3, -2));
  EXPECT_LT(key(1.0, 3, -4), key(1.0, 3, 4));
  EXPECT_LT(key(1.0, 3, 4), key(1.0, 3, 5));
  EXPECT_EQ(pair_event(1.0, 7, 2), (Event{1.0, 2, 7}));
}

TEST(Vec, WorksInThreeDimensions) {
  Particle<3> a, b;
  a.position = {{0, 0, 0}};
  a.velocity = {{1, 1, 1}};
  a.radius = 0.5;
  b.position = {{3, 3, 3}};
  b.radius = 0.5;
  // Closing along the diagonal: distance 3 sqrt 3 - t sqrt 3 = 1 at t = 3 - 1/sqrt 3.
  EXPECT_NEAR(contact_time(a, b), 3.0 - 1.0 / std::sqrt(3.0), 1e-12);
  const Box<3> box{{{4, 4, 4}}};
  EXPECT_EQ(next_wall_hit(a, box).label, -2);  // a corner: the x wall first
  EXPECT_DOUBLE_EQ(next_wall_hit(a, box).time, 3.5);
  a.position = {{2, 2, 2}};
  a.velocity = {{0, 0, 1}};
  EXPECT_EQ(next_wall_hit(a, box).label, -6);
  EXPECT_DOUBLE_EQ(next_wall_hit(a, box).time, 1.5);
}

// Growing particles (Lubachevsky-Stillinger).

TEST(Growth, WithoutGrowthTheGrowingFunctionsAreThePlainOnesBitForBit) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const Particle<2> a = disk(10 + u(random), 5 + u(random) / 2, u(random), u(random), 0.5, 0.25);
    const Particle<2> b = disk(10 + u(random), 5 + u(random) / 2, u(random), u(random), 0.3, 0.5);
    EXPECT_EQ(growing_contact_time(a, b, Vec2{}, 0.0), contact_time(a, b));
    const WallHit plain = next_wall_hit(a, kBox), grown = growing_wall_hit(a, kBox, 0.0);
    EXPECT_EQ(plain.time, grown.time);
    if (plain.time != kNever) {
      EXPECT_EQ(plain.label, grown.label);
      Particle<2> p = a, q = a;
      advance(p, plain.time);
      advance(q, plain.time);
      EXPECT_EQ(bounce(p, plain.label, kBox, 1.5), growing_bounce(q, plain.label, kBox, 1.5, 0.0));
      EXPECT_EQ(p.position, q.position);
      EXPECT_EQ(p.velocity, q.velocity);
    }
  }
}

TEST(Growth, ParticlesAtRestTouchOnceTheyHaveGrownIntoEachOther) {
  // Radii 1 growing at rate g: contact distance 2 (1 + g t) = 3 at t = 0.5 / g.
  const Particle<2> a = disk(2, 5, 0, 0), b = disk(5, 5, 0, 0);
  EXPECT_DOUBLE_EQ(growing_contact_time(a, b, Vec2{}, 0.01), 50.0);
  EXPECT_DOUBLE_EQ(grown_radius(1.0, 0.01, 50.0), 1.5);
}

TEST(Growth, AnOpeningPairMeetsAgainOnlyIfItsGrowthOutrunsIt) {
  for (const double speed : {0.1, 0.3}) {  // the contact distance grows at 2 x 0.2 = 0.4
    const Particle<2> a = disk(2, 5, -speed, 0), b = disk(5, 5, speed, 0);
    const double t = growing_contact_time(a, b, Vec2{}, 0.2);
    if (2 * speed >= 0.4) {
      EXPECT_EQ(t, kNever);
      continue;
    }
    // At that time the centres are exactly the grown contact distance apart.
    const double distance = 3.0 + 2 * speed * t, sigma = grown_radius(2.0, 0.2, t);
    EXPECT_NEAR(distance, sigma, 1e-12);
    EXPECT_GT(t, 0.0);
  }
  // Far apart and moving apart (r.v > sigma sigma': the gap opens at first), yet slower than the
  // contact distance grows: they meet at the later root.
  const Particle<2> a = disk(0, 5, -0.075, 0), b = disk(4, 5, 0.075, 0);  // gap 2, opening
  const double again = growing_contact_time(a, b, Vec2{}, 0.1);           // sigma' = 0.2
  EXPECT_NEAR(4.0 + 0.15 * again, grown_radius(2.0, 0.1, again), 1e-12);
  EXPECT_GT(again, 0.0);
  // Touching and closing: at once.
  EXPECT_EQ(growing_contact_time(disk(0, 5, 0.05, 0), disk(2, 5, -0.05, 0), Vec2{}, 0.1), 0.0);
}

TEST(Growth, ACollisionReversesTheRateAtWhichTheGapCloses) {
  // Touching disks approaching slower than they grow: afterwards the gap opens as fast as it
  // closed, in the frame of the moving surfaces, and momentum is kept.
  Particle<2> a = disk(0, 0, 0.3, 0.2), b = disk(1.2, 1.6, -0.1, -0.4);  // distance 2 = r_a + r_b
  const Vec2 r = a.position - b.position;
  const double growth_speed = 0.7, ma = 1.0, mb = 3.0;
  const auto closing = [&] {
    return -(dot(a.velocity - b.velocity, r) / std::sqrt(norm2(r)) - growth_speed);
  };
  const double before = closing();
  const Vec2 momentum = ma * a.velocity + mb * b.velocity;
  collide(a, b, r, Rule::elastic, 1.0, ma, mb, growth_speed);
  EXPECT_NEAR(closing(), -before, 1e-12);
  const Vec2 after = ma * a.velocity + mb * b.velocity;
  EXPECT_NEAR(after[0], momentum[0], 1e-12);
  EXPECT_NEAR(after[1], momentum[1], 1e-12);
}

TEST(Growth, AGrowingParticleReachesBothWallsAndLeavesFasterThanItGrows) {
  // At rest, radius 1 growing at speed 0.1: the nearer wall (x = 0, gap 1) at t = 10.
  const Particle<2> p = disk(2, 5, 0, 0, 1.0);
  const WallHit hit = growing_wall_hit(p, kBox, 0.1);
  EXPECT_DOUBLE_EQ(hit.time, 10.0);
  EXPECT_EQ(hit.label, -1);
  Particle<2> q = p;
  advance(q, hit.time);
  const double impulse = growing_bounce(q, hit.label, kBox, 2.0, 0.1);
  EXPECT_DOUBLE_EQ(q.position[0], 2.0);  // on the wall: radius 1 x (1 + 0.1 x 10)
  EXPECT_DOUBLE_EQ(q.velocity[0], 0.2);  // the gap closed at 0.1; it opens at 0.1
  EXPECT_DOUBLE_EQ(impulse, 2.0 * 0.2);
  // Moving away from a wall slower than it grows, it still reaches it.
  EXPECT_EQ(growing_wall_hit(disk(2, 5, -0.05, 0, 1.0), kBox, 0.1).label, -1);
  EXPECT_EQ(growing_wall_hit(disk(2, 5, 0.05, 0, 1.0), kBox, 0.1).label, -1);
  EXPECT_EQ(growing_wall_hit(disk(2, 5, 0.5, 0, 1.0), kBox, 0.1).label, -2);
}

}  // namespace
}  // namespace carom
