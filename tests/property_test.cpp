// Property tests (rapidcheck) over random systems of disks and spheres, for every rule and
// boundary: no overlap, no particle out of the box, event times never decrease, elastic
// collisions conserve energy and momentum, the fast engine equals the reference, and runs are
// deterministic.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "carom/core/observables.hpp"
#include "carom/engine/engine.hpp"
#include "carom/engine/overlap.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

template <std::size_t D>
struct Case {
  System<D> system;
  CollisionRule rule;
};

// A random system: up to 25 particles (mono- or polydisperse) in a box with walls or a periodic
// one, under a random rule; or, one time in four, a lattice of touching particles whose events
// tie. The seed drives carom's own reproducible generator.
template <std::size_t D>
Case<D> random_case() {
  const auto seed = *rc::gen::arbitrary<std::uint32_t>();
  const bool periodic = *rc::gen::arbitrary<bool>();
  const int rule = *rc::gen::inRange(0, 3);
  const bool lattice = *rc::gen::inRange(0, 4) == 0;
  const bool polydisperse = *rc::gen::arbitrary<bool>();
  const auto n = static_cast<std::size_t>(1 + *rc::gen::inRange(0, 25));
  pcg32 rng(seed);
  Case<D> c;
  if (lattice) {
    // Three cells or more a side: a periodic box must exceed two diameters.
    c.system = testing::cubic_lattice<D>(rng, 3 + rng() % 2, 0.5, 0.0, rng() % 2 == 0);
  } else {
    const double r_max = testing::uniform(rng, 0.1, 0.8);
    const double r_min = polydisperse ? r_max / 3 : r_max;
    Vec<D> size;
    for (std::size_t k = 0; k < D; ++k)
      size[k] = testing::uniform(rng, 4.2 * r_max, D == 2 ? 20.0 : 10.0);
    if constexpr (D == 2) {
      c.system = testing::random_gas(rng, n, r_min, r_max, size[0], size[1]);
    } else {
      c.system = testing::random_spheres(rng, n, r_min, r_max, size);
    }
  }
  if (periodic) {
    c.system.box.boundary = Boundary::periodic;
    // The generators keep particles apart directly, not through the boundary.
    RC_PRE(!find_pair_overlap(c.system, 0.0).has_value());
  }
  c.rule = rule == 0   ? CollisionRule{Rule::swap}
           : rule == 1 ? CollisionRule{Rule::elastic}
                       : CollisionRule{Rule::elastic, testing::uniform(rng, 0.5, 0.99), 1e-4};
  return c;
}

constexpr int kEvents = 200;

template <std::size_t D>
void runs_keep_every_invariant() {
  const Case<D> c = random_case<D>();
  auto engine = make_engine(EngineKind::fast, c.system, c.rule);
  double last = 0.0;
  for (int e = 0; e < kEvents; ++e) {
    const auto event = engine->step(50.0);
    if (!event) break;
    RC_ASSERT(event->time >= last);
    last = event->time;
    const auto violation = find_violation(engine->system(), engine->stored_time());
    RC_ASSERT(!violation.has_value());
  }
}

template <std::size_t D>
void elastic_collisions_conserve_energy_and_momentum() {
  Case<D> c = random_case<D>();
  c.rule = {Rule::elastic};
  c.system.box.boundary = Boundary::periodic;
  RC_PRE(!find_pair_overlap(c.system, 0.0).has_value());
  auto engine = make_engine(EngineKind::fast, c.system, c.rule);
  const double e0 = kinetic_energy(engine->system());
  const Vec<D> p0 = momentum(engine->system());
  for (int e = 0; e < kEvents && engine->step(50.0); ++e) {
  }
  RC_ASSERT(std::abs(kinetic_energy(engine->system()) - e0) <= 1e-12 * std::max(e0, 1.0));
  const Vec<D> p1 = momentum(engine->system());
  for (std::size_t k = 0; k < D; ++k) {
    RC_ASSERT(std::abs(p1[k] - p0[k]) <= 1e-12 * (1 + std::sqrt(e0)));
  }
}

template <std::size_t D>
void fast_engine_equals_reference_and_is_deterministic() {
  const Case<D> c = random_case<D>();
  auto fast = make_engine(EngineKind::fast, c.system, c.rule);
  auto again = make_engine(EngineKind::fast, c.system, c.rule);
  auto reference = make_engine(EngineKind::reference, c.system, c.rule);
  // Both engines moved to a new epoch at the same events, as a Simulation does every so often.
  const int rebase_every = *rc::gen::inRange(1, kEvents + 1);
  for (int e = 0; e < kEvents; ++e) {
    const auto a = fast->step(50.0), b = reference->step(50.0), d = again->step(50.0);
    RC_ASSERT(a.has_value() == b.has_value());
    RC_ASSERT(a.has_value() == d.has_value());
    if (!a) break;
    RC_ASSERT(*a == *b);
    RC_ASSERT(*a == *d);
    if ((e + 1) % rebase_every == 0) {
      fast->rebase();
      reference->rebase();
      again->rebase();
    }
  }
  for (std::size_t i = 0; i < c.system.particles.size(); ++i) {
    RC_ASSERT(fast->system().particles[i].position == reference->system().particles[i].position);
    RC_ASSERT(fast->system().particles[i].velocity == reference->system().particles[i].velocity);
  }
}

RC_GTEST_PROP(Properties, DiskRunsKeepEveryInvariant, ()) {
  runs_keep_every_invariant<2>();
}
RC_GTEST_PROP(Properties, SphereRunsKeepEveryInvariant, ()) {
  runs_keep_every_invariant<3>();
}

RC_GTEST_PROP(Properties, ElasticDiskCollisionsConserveEnergyAndMomentum, ()) {
  elastic_collisions_conserve_energy_and_momentum<2>();
}
RC_GTEST_PROP(Properties, ElasticSphereCollisionsConserveEnergyAndMomentum, ()) {
  elastic_collisions_conserve_energy_and_momentum<3>();
}

RC_GTEST_PROP(Properties, FastEngineEqualsReferenceAndIsDeterministicForDisks, ()) {
  fast_engine_equals_reference_and_is_deterministic<2>();
}
RC_GTEST_PROP(Properties, FastEngineEqualsReferenceAndIsDeterministicForSpheres, ()) {
  fast_engine_equals_reference_and_is_deterministic<3>();
}

}  // namespace
}  // namespace carom
