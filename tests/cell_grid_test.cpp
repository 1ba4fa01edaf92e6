#include "engine/cell_grid.hpp"

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

// The cell a crossing out of `cell` leads into.
template <std::size_t D>
std::uint32_t entered(const CellGrid<D>& grid, std::uint32_t cell,
                      const typename CellGrid<D>::Crossing& crossing) {
  return grid.adjacent(cell, crossing.axis, crossing.upward);
}

TEST(CellGrid, CellsAreAtLeastTheInteractionRange) {
  const CellGrid<2> grid(Box<2>{Vec2{{10, 4}}}, 2.0, 100);
  EXPECT_EQ(grid.cell_count(), 4u * 1u);  // 10 / 2 = 5 exactly, but cells are a hair wider
}

TEST(CellGrid, TheEdgeRowsAreTheFirstAndLastAlongYAndTheFarRowIsSearchedWhole) {
  // 10 x 10 cells of width 2 (a hair wider: 9 x 9), one particle a cell.
  Box<2> box{Vec2{{20, 20}}, Boundary::periodic};
  CellGrid<2> grid(box, 2.0, 200);
  const std::uint32_t columns = grid.cells_along(0), rows = grid.cells_along(1);
  ASSERT_GE(rows, 5u);
  std::uint32_t n = 0;
  for (std::uint32_t y = 0; y < rows; ++y) {
    for (std::uint32_t x = 0; x < columns; ++x) grid.insert(n++, y * columns + x);
  }
  std::set<std::uint32_t> edges;
  grid.for_each_in_edge_rows([&](std::uint32_t j) { EXPECT_TRUE(edges.insert(j).second); });
  EXPECT_EQ(edges.size(), 2u * columns);
  for (const std::uint32_t j : edges) EXPECT_TRUE(j < columns || j >= (rows - 1) * columns) << j;
  // A cell of the bottom row: with the block around it, the whole top row, each once.
  std::set<std::uint32_t> seen = near(grid, 3);
  grid.for_each_across_shear(3, [&](std::uint32_t j) { EXPECT_TRUE(seen.insert(j).second); });
  for (std::uint32_t x = 0; x < columns; ++x) EXPECT_TRUE(seen.count((rows - 1) * columns + x));
  // An inner row has no far row.
  std::size_t across = 0;
  grid.for_each_across_shear(2 * columns + 3, [&](std::uint32_t) { ++across; });
  EXPECT_EQ(across, 0u);
  // One row of cells: it is the edge row, visited once.
  CellGrid<2> flat(Box<2>{Vec2{{20, 2.5}}, Boundary::periodic}, 2.0, 20);
  ASSERT_EQ(flat.cells_along(1), 1u);
  for (std::uint32_t x = 0; x < flat.cells_along(0); ++x) flat.insert(x, x);
  std::size_t visited = 0;
  flat.for_each_in_edge_rows([&](std::uint32_t) { ++visited; });
  EXPECT_EQ(visited, flat.cells_along(0));
}

TEST(CellGrid, AHugeSparseBoxHasAboutTwoCellsPerParticle) {
  const CellGrid<2> grid(Box<2>{Vec2{{1e6, 1e6}}}, 1e-3, 10);
  EXPECT_LE(grid.cell_count(), 36u);
  EXPECT_GE(grid.cell_count(), 1u);
}

TEST(CellGrid, AThinSlabInThreeDimensionsIsCappedToo) {
  // Regression: the cap applied per axis, so a slab got (2N)^2 cells.
  const CellGrid<3> grid(Box<3>{Vec<3>{{1e9, 2.5, 1e9}}}, 2.0, 1000);
  EXPECT_LE(grid.cell_count(), 2016u);
}

// Event chains ask for three cells along every axis wide enough (least_cells): a sparse box
// with one narrow side gets them there, and cells stretched along the others, not the
// (long / narrow)^(D - 1) cells of one width, which for 3 spheres in 3.01 x 5000 x 5000 were 13 GB.
TEST(CellGrid, LeastCellsAlongANarrowSideKeepTheCap) {
  const CellGrid<3> slab(Box<3>{Vec<3>{{3.01, 5000, 5000}}}, 1.0, 6, 3);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_GE(slab.cells_along(k), 3u) << k;
  EXPECT_LE(slab.cell_count(), 2u * 6u + 16u);
  const CellGrid<2> strip(Box<2>{Vec2{{3.01, 1e6}}}, 1.0, 2, 3);
  EXPECT_EQ(strip.cells_along(0), 3u);
  EXPECT_LE(strip.cell_count(), 2u * 2u + 16u);
  // Where an axis holds fewer cells of the least width, it has what it holds.
  const CellGrid<2> narrow(Box<2>{Vec2{{2.5, 100}}}, 1.0, 50, 3);
  EXPECT_EQ(narrow.cells_along(0), 2u);
}

TEST(CellGrid, FindsEveryParticleWithinRangeAndOnlyNearbyOnes) {
  pcg32 rng(1);
  const Vec2 box{{13.7, 9.1}};
  const double range = 1.3;
  CellGrid<2> grid(Box<2>{box}, range, 300);
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

// for_each_within visits every particle within reach of any point (the nearest image in a
// periodic box, the point itself anywhere, even outside the box), each once, and fewer than the
// whole block around the point's cell.
template <std::size_t D>
void check_within(const Vec<D>& side, Boundary boundary, double reach, std::uint64_t seed) {
  pcg32 rng(seed);
  const Box<D> box{side, boundary};
  const std::uint32_t n = 400;
  CellGrid<D> grid(box, reach, n);
  std::vector<Vec<D>> at(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < D; ++k) at[i][k] = testing::uniform(rng, 0, side[k]);
    grid.insert(i, grid.locate(at[i]));
  }
  std::size_t within_visits = 0, block_visits = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Vec<D> point;
    const double beyond = box.periodic() ? 1.5 : 0.0;  // unwrapped points of a periodic box
    for (std::size_t k = 0; k < D; ++k) {
      point[k] = testing::uniform(rng, -beyond * side[k], (1 + beyond) * side[k]);
    }
    std::set<std::uint32_t> found;
    const std::uint32_t cell = grid.for_each_within(point, reach, [&](std::uint32_t j) {
      EXPECT_TRUE(found.insert(j).second) << j << " visited twice";
    });
    EXPECT_EQ(cell, grid.locate(point));
    for (std::uint32_t j = 0; j < n; ++j) {
      Vec<D> apart = point - at[j];
      apart -= image_offset(apart, box);
      if (norm2(apart) <= reach * reach) {
        EXPECT_TRUE(found.count(j)) << trial << " " << j;
      }
    }
    within_visits += found.size();
    grid.for_each_near(cell, [&](std::uint32_t) { ++block_visits; });
  }
  EXPECT_LT(within_visits, block_visits);
}

TEST(CellGrid, WithinReachFindsEveryParticleThereAndSkipsFarCorners) {
  check_within<2>(Vec<2>{{13.7, 9.1}}, Boundary::walls, 1.3, 1);
  check_within<2>(Vec<2>{{13.7, 9.1}}, Boundary::periodic, 1.3, 2);
  check_within<2>(Vec<2>{{5.0, 2.7}}, Boundary::periodic, 1.3, 3);  // two cells along y
  check_within<3>(Vec<3>{{7.1, 6.3, 9.8}}, Boundary::walls, 1.1, 4);
  check_within<3>(Vec<3>{{7.1, 6.3, 9.8}}, Boundary::periodic, 1.1, 5);
  check_within<3>(Vec<3>{{7.1, 2.5, 3.9}}, Boundary::periodic, 1.1, 6);  // two and three cells
}

TEST(CellGrid, MovingKeepsTheListsConsistent) {
  CellGrid<2> grid(Box<2>{Vec2{{10, 10}}}, 1.0, 4);
  for (std::uint32_t i = 0; i < 4; ++i) grid.insert(i, 0);
  grid.move(2, grid.locate(Vec2{{9.5, 9.5}}));
  grid.move(0, grid.locate(Vec2{{9.5, 9.5}}));
  EXPECT_EQ(near(grid, 0), (std::set<std::uint32_t>{1, 3}));
  EXPECT_EQ(near(grid, grid.cell_of(2)), (std::set<std::uint32_t>{0, 2}));
}

TEST(CellGrid, CrossingLeadsToTheNextCellInTheDirectionOfMotion) {
  const CellGrid<2> grid(Box<2>{Vec2{{10, 10}}}, 2.0, 100);  // 4 x 4 cells of 2.5
  const std::uint32_t cell = grid.locate(Vec2{{3, 3}});
  const auto right = grid.next_crossing(cell, Vec2{{3, 3}}, Vec2{{1, 0.1}});
  EXPECT_DOUBLE_EQ(right.delay, 2.0);
  EXPECT_EQ(entered(grid, cell, right), grid.locate(Vec2{{5.5, 3}}));
  EXPECT_EQ(right.axis, 0u);
  EXPECT_TRUE(right.upward);
  const auto down = grid.next_crossing(cell, Vec2{{3, 3}}, Vec2{{0, -1}});
  EXPECT_DOUBLE_EQ(down.delay, 0.5);
  EXPECT_EQ(entered(grid, cell, down), grid.locate(Vec2{{3, 2}}));
  EXPECT_EQ(down.axis, 1u);
  EXPECT_FALSE(down.upward);
  // Past the boundary by round-off: cross at once, never with a negative delay.
  EXPECT_EQ(grid.next_crossing(cell, Vec2{{5.0 + 1e-15, 3}}, Vec2{{1, 0}}).delay, 0.0);
}

// After a crossing from A into B, the fast engine predicts only against the layer of cells ahead
// of B: together with those around A (predicted before), they must cover every cell around B.
template <std::size_t D>
void expect_layers_cover_the_new_cells(const Box<D>& box, double width) {
  CellGrid<D> grid(box, width, 1000);
  const auto cells = static_cast<std::uint32_t>(grid.cell_count());
  for (std::uint32_t c = 0; c < cells; ++c) grid.insert(c, c);  // particle c in cell c
  const auto collect = [](auto&& walk) {
    std::set<std::uint32_t> found;
    walk([&](std::uint32_t j) { EXPECT_TRUE(found.insert(j).second) << "visited twice: " << j; });
    return found;
  };
  const auto no_look_ahead = [](std::uint32_t) {};
  for (std::uint32_t from = 0; from < cells; ++from) {
    const auto around_from = collect([&](auto visit) { grid.for_each_near(from, visit); });
    for (std::size_t axis = 0; axis < D; ++axis) {
      for (const bool upward : {false, true}) {
        const std::uint32_t n = grid.cells_along(axis);
        std::uint32_t stride = 1;
        for (std::size_t k = 0; k < axis; ++k) stride *= grid.cells_along(k);
        const std::uint32_t at = from / stride % n;
        if (!box.periodic() && (upward ? at + 1 == n : at == 0)) continue;  // a wall: no crossing
        const std::uint32_t to = grid.adjacent(from, axis, upward);
        const auto around_to = collect([&](auto visit) { grid.for_each_near(to, visit); });
        const auto layer = collect(
            [&](auto visit) { grid.for_each_in_layer(to, axis, upward, no_look_ahead, visit); });
        for (const std::uint32_t c : around_to) {
          EXPECT_TRUE(around_from.count(c) || layer.count(c))
              << "cell " << c << " around " << to << " (from " << from << ", axis " << axis
              << (upward ? " up" : " down") << ") is in no layer";
        }
        for (const std::uint32_t c : layer) EXPECT_TRUE(around_to.count(c)) << c;
      }
    }
  }
}

TEST(CellGrid, TheLayerAheadOfACrossingCoversTheCellsItBringsWithinReach) {
  for (const double side : {1.0, 2.0, 3.0, 4.0, 5.0, 7.0}) {
    for (const Boundary boundary : {Boundary::walls, Boundary::periodic}) {
      expect_layers_cover_the_new_cells(Box<2>{Vec2{{side, 6.0}}, boundary}, 1.0);
      expect_layers_cover_the_new_cells(Box<3>{Vec<3>{{side, 4.0, 3.0}}, boundary}, 1.0);
    }
  }
}

TEST(CellGrid, NoCrossingThroughTheBoxWalls) {
  const CellGrid<2> grid(Box<2>{Vec2{{10, 10}}}, 2.0, 100);
  const std::uint32_t corner = grid.locate(Vec2{{9, 9}});
  EXPECT_EQ(grid.next_crossing(corner, Vec2{{9, 9}}, Vec2{{1, 1}}).delay, kNever);
  EXPECT_EQ(grid.next_crossing(corner, Vec2{{9, 9}}, Vec2{{0, 0}}).delay, kNever);
}

TEST(CellGrid, PeriodicCrossingWrapsAround) {
  const CellGrid<2> grid(Box<2>{Vec2{{10, 10}}, Boundary::periodic}, 2.0, 100);
  const std::uint32_t last = grid.locate(Vec2{{9, 5}});
  const auto right = grid.next_crossing(last, Vec2{{9, 5}}, Vec2{{1, 0}});
  EXPECT_DOUBLE_EQ(right.delay, 1.0);
  EXPECT_EQ(entered(grid, last, right), grid.locate(Vec2{{0.5, 5}}));
  // Unwrapped positions (a particle wraps only when it collides) are understood.
  EXPECT_DOUBLE_EQ(
      grid.next_crossing(entered(grid, last, right), Vec2{{10.5, 5}}, Vec2{{1, 0}}).delay, 2.0);
  EXPECT_EQ(grid.locate(Vec2{{-0.5, 5}}), last);
}

TEST(CellGrid, PeriodicAxisWithTwoCellsNeverPingPongs) {
  // Regression: a particle exactly on the boundary between the two cells of a periodic axis was
  // sent back and forth between them forever with zero delay.
  const CellGrid<2> grid(Box<2>{Vec2{{12, 1.9}}, Boundary::periodic}, 0.92, 14);
  ASSERT_EQ(grid.cells_along(1), 2u);
  const Vec2 at{{5.0, 0.0}}, down{{0.0, -1.0}};
  const std::uint32_t lower = grid.locate(Vec2{{5.0, 0.5}});
  const auto leave_lower = grid.next_crossing(lower, at, down);
  EXPECT_EQ(leave_lower.delay, 0.0);
  EXPECT_EQ(entered(grid, lower, leave_lower), grid.locate(Vec2{{5.0, 1.5}}));
  // Now at the top of the upper cell (y = 0 is y = 1.9): a whole cell to go.
  EXPECT_DOUBLE_EQ(grid.next_crossing(entered(grid, lower, leave_lower), at, down).delay, 0.95);
  // Every particle is visited once however few cells an axis has.
  CellGrid<2> tiny(Box<2>{Vec2{{2.5, 2.5}}, Boundary::periodic}, 1.0, 3);
  for (std::uint32_t i = 0; i < 3; ++i) tiny.insert(i, tiny.locate(Vec2{{0.5 + i, 0.5 + i}}));
  EXPECT_EQ(near(tiny, 0), (std::set<std::uint32_t>{0, 1, 2}));
}

}  // namespace
}  // namespace carom

namespace carom {
namespace {

// adjacent() finds a cell's place along an axis by multiplying by the stride's inverse, not
// dividing: checked against division on grids of one to seven cells an axis (an axis of one cell
// makes the next axis's stride 1, which has no 64-bit inverse).
template <std::size_t D>
void check_adjacent_cells(Boundary boundary) {
  for (std::uint32_t shape = 0; shape < (D == 2 ? 49u : 343u); ++shape) {
    Box<D> box;
    box.boundary = boundary;
    std::array<std::uint32_t, D> count{};
    for (std::size_t k = 0, rest = shape; k < D; ++k, rest /= 7) {
      count[k] = 1 + static_cast<std::uint32_t>(rest % 7);
      box.size[k] = 1.001 * count[k];
    }
    const CellGrid<D> grid(box, 1.0, 1000);
    for (std::size_t k = 0; k < D; ++k) ASSERT_EQ(grid.cells_along(k), count[k]);
    for (std::uint32_t cell = 0; cell < grid.cell_count(); ++cell) {
      std::uint32_t stride = 1;
      for (std::size_t axis = 0; axis < D; ++axis) {
        const std::uint32_t at = cell / stride % count[axis], n = count[axis];
        for (const bool upward : {false, true}) {
          const std::uint32_t to = upward ? (at + 1) % n : (at + n - 1) % n;
          EXPECT_EQ(grid.adjacent(cell, axis, upward), cell - at * stride + to * stride)
              << "cell " << cell << " axis " << axis;
        }
        stride *= n;
      }
    }
  }
}

TEST(CellGrid, AdjacentCellsAreFoundWithoutDividing) {
  check_adjacent_cells<2>(Boundary::periodic);
  check_adjacent_cells<3>(Boundary::periodic);
}

}  // namespace
}  // namespace carom
