#include "engine/list_engine.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "carom/engine/engine.hpp"
#include "carom/engine/initial.hpp"
#include "carom/io/classic_input.hpp"
#include "engine/fast_engine.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

using carom::testing::boxed;
using carom::testing::case_system;
using carom::testing::disk;
using carom::testing::random_gas;
using carom::testing::square_lattice;
using carom::testing::uniform;

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
    const Vec<3> moved =
        position_at(system.particles[i], engine.stored_time()) - engine.shell_centre(i);
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

// The list engine keeps no pending event beside the calendar: what an entry is comes back from
// its key alone, for every kind and either order of a pair.
TEST(KeyedEntry, ReadsEveryKindOfEntryFromItsKey) {
  const auto read = [](std::uint32_t i, const EventKey& key) { return keyed_entry<3>(i, key); };
  const KeyedEntry own = read(7, {1.0, after_collisions(7)});
  EXPECT_EQ(own.kind, EntryKind::crossing);
  for (std::int32_t wall = -1; wall >= -6; --wall) {
    const KeyedEntry hit = read(7, key_of<3>({1.0, 7, wall}));
    EXPECT_EQ(hit.kind, EntryKind::wall);
    EXPECT_EQ(hit.partner, wall);
  }
  for (std::uint32_t j : {0u, 6u, 8u, 2000000000u}) {
    const KeyedEntry pair = read(7, key_of<3>(pair_event(1.0, 7, j)));
    EXPECT_EQ(pair.kind, EntryKind::pair);
    EXPECT_EQ(pair.partner, static_cast<std::int32_t>(j)) << j;
  }
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

}  // namespace
}  // namespace carom
