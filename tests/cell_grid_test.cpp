#include "cell_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "test_systems.hpp"

namespace carom {
namespace {

std::set<std::uint32_t> near(const CellGrid<2>& grid, std::uint32_t cell) {
  std::set<std::uint32_t> found;
  grid.for_each_near(cell, [&](std::uint32_t j) { EXPECT_TRUE(found.insert(j).second); });
  return found;
}

TEST(CellGrid, CellsAreAtLeastTheInteractionRange) {
  const CellGrid<2> grid(Vec2{{10, 4}}, 2.0, 100);
  EXPECT_EQ(grid.cell_count(), 4u * 1u);  // 10 / 2 = 5 exactly, but cells are a hair wider
}

TEST(CellGrid, AHugeSparseBoxHasAboutTwoCellsPerParticle) {
  const CellGrid<2> grid(Vec2{{1e6, 1e6}}, 1e-3, 10);
  EXPECT_LE(grid.cell_count(), 36u);
  EXPECT_GE(grid.cell_count(), 1u);
}

TEST(CellGrid, FindsEveryParticleWithinRangeAndOnlyNearbyOnes) {
  pcg32 rng(1);
  const Vec2 box{{13.7, 9.1}};
  const double range = 1.3;
  CellGrid<2> grid(box, range, 300);
  std::vector<Vec2> at;
  for (std::uint32_t i = 0; i < 300; ++i) {
    at.push_back({{testing::uniform(rng, 0, box[0]), testing::uniform(rng, 0, box[1])}});
    grid.insert(i, grid.locate(at[i]));
  }
  for (std::uint32_t i = 0; i < 300; ++i) {
    const std::set<std::uint32_t> found = near(grid, grid.cell_of(i));
    EXPECT_TRUE(found.count(i));
    for (std::uint32_t j = 0; j < 300; ++j) {
      if (norm2(at[i] - at[j]) <= range * range) {
        EXPECT_TRUE(found.count(j)) << i << " " << j;
      }
    }
  }
}

TEST(CellGrid, MovingKeepsTheListsConsistent) {
  CellGrid<2> grid(Vec2{{10, 10}}, 1.0, 4);
  for (std::uint32_t i = 0; i < 4; ++i) grid.insert(i, 0);
  grid.move(2, grid.locate(Vec2{{9.5, 9.5}}));
  grid.move(0, grid.locate(Vec2{{9.5, 9.5}}));
  EXPECT_EQ(near(grid, 0), (std::set<std::uint32_t>{1, 3}));
  EXPECT_EQ(near(grid, grid.cell_of(2)), (std::set<std::uint32_t>{0, 2}));
}

TEST(CellGrid, CrossingLeadsToTheNextCellInTheDirectionOfMotion) {
  const CellGrid<2> grid(Vec2{{10, 10}}, 2.0, 100);  // 4 x 4 cells of 2.5
  const std::uint32_t cell = grid.locate(Vec2{{3, 3}});
  const auto right = grid.next_crossing(cell, Vec2{{3, 3}}, Vec2{{1, 0.1}});
  EXPECT_DOUBLE_EQ(right.delay, 2.0);
  EXPECT_EQ(right.cell, grid.locate(Vec2{{5.5, 3}}));
  const auto down = grid.next_crossing(cell, Vec2{{3, 3}}, Vec2{{0, -1}});
  EXPECT_DOUBLE_EQ(down.delay, 0.5);
  EXPECT_EQ(down.cell, grid.locate(Vec2{{3, 2}}));
  // Past the boundary by round-off: cross at once, never with a negative delay.
  EXPECT_EQ(grid.next_crossing(cell, Vec2{{5.0 + 1e-15, 3}}, Vec2{{1, 0}}).delay, 0.0);
}

TEST(CellGrid, NoCrossingThroughTheBoxWalls) {
  const CellGrid<2> grid(Vec2{{10, 10}}, 2.0, 100);
  const std::uint32_t corner = grid.locate(Vec2{{9, 9}});
  EXPECT_EQ(grid.next_crossing(corner, Vec2{{9, 9}}, Vec2{{1, 1}}).delay, kNever);
  EXPECT_EQ(grid.next_crossing(corner, Vec2{{9, 9}}, Vec2{{0, 0}}).delay, kNever);
}

}  // namespace
}  // namespace carom
