// Property tests (rapidcheck) over random systems, for every rule and boundary: no overlap, no
// disk out of the box, event times never decrease, elastic collisions conserve energy and
// momentum, the fast engine equals the reference, and runs are deterministic.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "carom/engine.hpp"
#include "carom/observables.hpp"
#include "carom/overlap.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

struct Case {
  System<2> system;
  CollisionRule rule;
};

// A random system: up to 25 disks (mono- or polydisperse) in a box with walls or a periodic one,
// under a random rule. The seed drives carom's own reproducible generator.
Case random_case() {
  const auto seed = *rc::gen::arbitrary<std::uint32_t>();
  const bool periodic = *rc::gen::arbitrary<bool>();
  const int rule = *rc::gen::inRange(0, 3);
  pcg32 rng(seed);
  const double r_max = testing::uniform(rng, 0.1, 0.8);
  const double r_min = *rc::gen::arbitrary<bool>() ? r_max : r_max / 3;
  const double lx = testing::uniform(rng, 4.2 * r_max, 20),
               ly = testing::uniform(rng, 4.2 * r_max, 20);
  Case c{testing::random_gas(rng, 1 + *rc::gen::inRange(0, 25), r_min, r_max, lx, ly), {}};
  if (periodic) {
    c.system.box.boundary = Boundary::periodic;
    // random_gas keeps disks apart directly, not through the boundary.
    RC_PRE(!find_pair_overlap(c.system, 0.0).has_value());
  }
  c.rule = rule == 0   ? CollisionRule{Rule::swap}
           : rule == 1 ? CollisionRule{Rule::elastic}
                       : CollisionRule{Rule::elastic, testing::uniform(rng, 0.5, 0.99), 1e-4};
  return c;
}

constexpr int kEvents = 200;

RC_GTEST_PROP(Properties, RunsKeepEveryInvariant, ()) {
  const Case c = random_case();
  auto engine = make_engine(EngineKind::fast, c.system, c.rule);
  double last = 0.0;
  for (int e = 0; e < kEvents; ++e) {
    const auto event = engine->step(50.0);
    if (!event) break;
    RC_ASSERT(event->time >= last);
    last = event->time;
    const auto violation = find_violation(engine->system(), event->time);
    RC_ASSERT(!violation.has_value());
  }
}

RC_GTEST_PROP(Properties, ElasticCollisionsConserveEnergyAndMomentum, ()) {
  Case c = random_case();
  c.rule = {Rule::elastic};
  c.system.box.boundary = Boundary::periodic;
  RC_PRE(!find_pair_overlap(c.system, 0.0).has_value());
  auto engine = make_engine(EngineKind::fast, c.system, c.rule);
  const double e0 = kinetic_energy(engine->system());
  const Vec2 p0 = momentum(engine->system());
  for (int e = 0; e < kEvents && engine->step(50.0); ++e) {
  }
  RC_ASSERT(std::abs(kinetic_energy(engine->system()) - e0) <= 1e-12 * std::max(e0, 1.0));
  const Vec2 p1 = momentum(engine->system());
  RC_ASSERT(std::abs(p1[0] - p0[0]) <= 1e-12 * (1 + std::sqrt(e0)));
  RC_ASSERT(std::abs(p1[1] - p0[1]) <= 1e-12 * (1 + std::sqrt(e0)));
}

RC_GTEST_PROP(Properties, FastEngineEqualsReferenceAndIsDeterministic, ()) {
  const Case c = random_case();
  auto fast = make_engine(EngineKind::fast, c.system, c.rule);
  auto again = make_engine(EngineKind::fast, c.system, c.rule);
  auto reference = make_engine(EngineKind::reference, c.system, c.rule);
  for (int e = 0; e < kEvents; ++e) {
    const auto a = fast->step(50.0), b = reference->step(50.0), d = again->step(50.0);
    RC_ASSERT(a.has_value() == b.has_value());
    RC_ASSERT(a.has_value() == d.has_value());
    if (!a) break;
    RC_ASSERT(*a == *b);
    RC_ASSERT(*a == *d);
  }
  for (std::size_t i = 0; i < c.system.particles.size(); ++i) {
    RC_ASSERT(fast->system().particles[i].position == reference->system().particles[i].position);
    RC_ASSERT(fast->system().particles[i].velocity == reference->system().particles[i].velocity);
  }
}

}  // namespace
}  // namespace carom
