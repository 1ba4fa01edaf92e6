#include "carom/engine/overlap.hpp"

#include <gtest/gtest.h>

#include "test_systems.hpp"

namespace carom {
namespace {

using carom::testing::boxed;
using carom::testing::disk;

TEST(Overlap, FindViolationNamesOverlapsAndWalls) {
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

}  // namespace
}  // namespace carom
