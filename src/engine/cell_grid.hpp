// A uniform grid of cells over the box, at least one interaction range wide, so that the
// partners a particle can touch are all in its own cell or the 3^D cells around it (wrapping
// around a periodic box). Each cell holds an intrusive doubly linked list of particle indices:
// moving a particle is O(1).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "carom/core/physics.hpp"
#include "carom/core/system.hpp"
#include "large_pages.hpp"

namespace carom {

template <std::size_t D>
class CellGrid {
 public:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  static constexpr std::size_t kBlock = [] {  // 3^D: the cells around one, its own included
    std::size_t cells = 1;
    for (std::size_t k = 0; k < D; ++k) cells *= 3;
    return cells;
  }();

  // `min_width` is the largest distance at which two particles can touch. Cells are a hair
  // wider still, so that a particle whose cell was assigned at a crossing time (subject to
  // round-off) still finds every possible partner in the block around it. The number of cells is
  // capped at about two per particle, so a huge sparse box costs no memory. `least_cells`: at
  // least that many cells along every axis wide enough for them (cells then stretch along the
  // others: a sparse box of one narrow side needs no more cells than particles).
  CellGrid(const Box<D>& box, double min_width, std::size_t particles,
           std::uint32_t least_cells = 1)
      : box_(box), next_(particles, kNone), prev_(particles, kNone), cell_of_(particles, kNone) {
    std::array<double, D> fewest{};
    double fewest_total = 1.0;
    for (std::size_t k = 0; k < D; ++k) {
      fewest[k] = std::clamp(std::floor(box.size[k] / hair_wider(min_width)), 1.0,
                             static_cast<double>(std::max(least_cells, 1u)));
      fewest_total *= fewest[k];
    }
    const double max_cells = std::max(most_cells(particles), fewest_total);
    double width = least_width(box, min_width, particles);
    // Per axis the cap alone is not enough (a thin slab in 3D): widen until the product fits.
    double total = 0.0;
    do {
      total = 1.0;
      for (std::size_t k = 0; k < D; ++k) {
        count_[k] = static_cast<std::uint32_t>(
            std::clamp(std::floor(box.size[k] / width), fewest[k], max_cells));
        total *= count_[k];
      }
      width *= 1.25;
    } while (total > max_cells);
    std::uint64_t stride = 1;
    for (std::size_t k = 0; k < D; ++k) {
      width_[k] = box.size[k] / count_[k];
      stride_[k] = static_cast<std::uint32_t>(stride);
      inverse_stride_[k] = stride_[k] > 1 ? ~std::uint64_t{0} / stride_[k] + 1 : 0;
      stride *= count_[k];
    }
    head_.assign(static_cast<std::size_t>(total), kNone);
    // The block around a cell away from every edge: the cell's index plus these.
    for (std::size_t c = 0; c < kBlock; ++c) {
      std::int64_t offset = 0;
      for (std::size_t k = 0, rest = c; k < D; ++k, rest /= 3) {
        offset += (static_cast<std::int64_t>(rest % 3) - 1) * stride_[k];
      }
      inner_block_[c] = static_cast<std::int32_t>(offset);
    }
    // The layers ahead of such a cell: along one axis one cell on, along the others -1, 0, +1.
    for (std::size_t axis = 0; axis < D; ++axis) {
      for (const bool upward : {false, true}) {
        std::size_t count = 0;
        for (std::size_t c = 0; c < kBlock; ++c) {
          const auto step = static_cast<std::int64_t>(c / power_of_three(axis) % 3) - 1;
          if (step == (upward ? 1 : -1)) inner_layer_[2 * axis + upward][count++] = inner_block_[c];
        }
      }
    }
  }

  // No cell of such a grid is narrower than this (the cap on their number may widen them).
  static double least_width(const Box<D>& box, double min_width, std::size_t particles) {
    return std::max(hair_wider(min_width), std::pow(box_volume(box) / most_cells(particles),
                                                    1.0 / static_cast<double>(D)));
  }

  std::size_t cell_count() const { return head_.size(); }
  std::uint32_t cells_along(std::size_t axis) const { return count_[axis]; }
  std::uint32_t cell_of(std::uint32_t particle) const { return cell_of_[particle]; }
  void prefetch_cell_of(std::uint32_t particle) const { __builtin_prefetch(&cell_of_[particle]); }

  // The cell that contains `position` (wrapped into a periodic box); positions on or beyond the
  // edge of a box with walls go to the edge cell.
  std::uint32_t locate(Vec<D> position) const {
    wrap(position, box_);
    std::uint32_t cell = 0;
    for (std::size_t k = 0; k < D; ++k) cell += stride_[k] * along_axis(position[k], k);
    return cell;
  }

  void insert(std::uint32_t particle, std::uint32_t cell) {
    cell_of_[particle] = cell;
    prev_[particle] = kNone;
    next_[particle] = head_[cell];
    if (head_[cell] != kNone) prev_[head_[cell]] = particle;
    head_[cell] = particle;
  }

  void move(std::uint32_t particle, std::uint32_t cell) {
    remove(particle);
    insert(particle, cell);
  }

  // Calls visit(j) once for every particle j in `cell` and the cells around it, `cell`'s own
  // included; first look_ahead(j) for the first particle of every cell, which may start fetching
  // it.
  template <class Visit>
  void for_each_near(std::uint32_t cell, Visit&& visit) const {
    for_each_near(
        cell, [](std::uint32_t) {}, visit);
  }

  template <class LookAhead, class Visit>
  void for_each_near(std::uint32_t cell, LookAhead&& look_ahead, Visit&& visit) const {
    std::array<std::uint32_t, kBlock> cells;
    visit_cells(cells, block(cell, cells), look_ahead, visit);
  }

  // Calls visit(j) once for every particle j in the cells around `cell` that lie level with it or
  // one further up along `axis`: the block less the layer behind. What a particle moving up along
  // `axis` can touch while inside `cell` (event-chain Monte Carlo's lifts). The whole block on an
  // axis of fewer than three cells, whose layers are not apart.
  template <class Visit>
  void for_each_ahead(std::uint32_t cell, std::size_t axis, Visit&& visit) const {
    std::array<std::uint32_t, kBlock> cells;
    std::size_t count = 0;
    if (count_[axis] < 3) {
      count = block(cell, cells);
    } else {
      std::array<std::uint32_t, kBlock> ahead;
      count = layer(adjacent(cell, axis, false), axis, true, cells);
      const std::size_t more = layer(cell, axis, true, ahead);
      for (std::size_t c = 0; c < more; ++c) cells[count++] = ahead[c];
    }
    visit_cells(
        cells, count, [](std::uint32_t) {}, visit);
  }

  // The cells for_each_ahead(cell, axis, ...) visits, each once, into `cells`; returns how many.
  std::size_t cells_ahead(std::uint32_t cell, std::size_t axis,
                          std::array<std::uint32_t, kBlock>& cells) const {
    if (count_[axis] < 3) return block(cell, cells);
    std::array<std::uint32_t, kBlock> ahead;
    std::size_t count = layer(adjacent(cell, axis, false), axis, true, cells);
    const std::size_t more = layer(cell, axis, true, ahead);
    for (std::size_t c = 0; c < more; ++c) cells[count++] = ahead[c];
    return count;
  }

  // A cell's width along `axis`, and its place along each axis (0 .. cells_along - 1).
  double width(std::size_t axis) const { return width_[axis]; }
  std::array<std::uint32_t, D> coordinates_of(std::uint32_t cell) const {
    return coordinates(cell);
  }

  // Calls visit(j) once for every particle j in the cells around the one containing `point` (its
  // own included) that come within `reach` of it: the block's corners and edges lie beyond when
  // `point` is far from them, and are skipped (about a quarter of the particles of a block of
  // cells one reach wide). Conservative by a hair: a cell is skipped only when it is farther than
  // `reach` even with the round-off of locating its particles allowed for.
  // Returns the cell containing `point` (locate(point)).
  template <class Visit>
  std::uint32_t for_each_within(Vec<D> point, double reach, Visit&& visit) const {
    wrap(point, box_);
    std::uint32_t cell = 0;
    // Per axis, the cells to look at (a coordinate times the stride) and the square of the gap
    // between `point` and each.
    std::array<std::array<std::uint32_t, 3>, D> along{};
    std::array<std::array<double, 3>, D> gap2{};
    std::array<std::uint32_t, D> size{};
    for (std::size_t k = 0; k < D; ++k) {
      const std::uint32_t n = count_[k], stride = stride_[k];
      const double width = width_[k];
      const std::uint32_t at = along_axis(point[k], k);
      cell += at * stride;
      if (box_.periodic() && n < 3) {  // every cell of the axis, once
        for (std::uint32_t c = 0; c < n; ++c) along[k][size[k]++] = c * stride;
        continue;
      }
      const double slack = kLocatingSlack * width;
      const double below = std::max(0.0, point[k] - at * width - slack);
      const double above = std::max(0.0, (at + 1.0) * width - point[k] - slack);
      if (at > 0 || box_.periodic()) {
        gap2[k][size[k]] = below * below;
        along[k][size[k]++] = (at > 0 ? at - 1 : n - 1) * stride;
      }
      along[k][size[k]++] = at * stride;
      if (at + 1 < n || box_.periodic()) {
        gap2[k][size[k]] = above * above;
        along[k][size[k]++] = (at + 1 < n ? at + 1 : 0) * stride;
      }
    }
    // The cells first, then their particles: a flat walk.
    const double reach2 = reach * reach;
    std::array<std::uint32_t, kBlock> cells;
    std::size_t count = 0;
    const auto add_row = [&](std::uint32_t row, double row_gap2) {
      for (std::uint32_t x = 0; x < size[0]; ++x) {
        cells[count] = row + along[0][x];
        count += row_gap2 + gap2[0][x] <= reach2;
      }
    };
    static_assert(D == 2 || D == 3);
    if constexpr (D == 2) {
      for (std::uint32_t y = 0; y < size[1]; ++y) add_row(along[1][y], gap2[1][y]);
    } else {
      for (std::uint32_t z = 0; z < size[2]; ++z) {
        for (std::uint32_t y = 0; y < size[1]; ++y) {
          add_row(along[2][z] + along[1][y], gap2[2][z] + gap2[1][y]);
        }
      }
    }
    for (std::size_t c = 0; c < count; ++c) {
      for (std::uint32_t j = head_[cells[c]]; j != kNone; j = next_[j]) visit(j);
    }
    return cell;
  }

  // The same for the particles of layer(cell, axis, upward) only.
  template <class LookAhead, class Visit>
  void for_each_in_layer(std::uint32_t cell, std::size_t axis, bool upward, LookAhead&& look_ahead,
                         Visit&& visit) const {
    std::array<std::uint32_t, kBlock> cells;
    visit_cells(cells, layer(cell, axis, upward, cells), look_ahead, visit);
  }

  // In a sheared box (Box::sheared) the images across the y edge slide along x, so a particle in
  // an edge row of cells may touch the image of one anywhere in the far edge row: this visits
  // every particle there that for_each_near(cell) does not (the whole row, less the columns
  // around `cell`'s, within one cell in z). Nothing for a cell of an inner row.
  template <class Visit>
  void for_each_across_shear(std::uint32_t cell, Visit&& visit) const {
    const std::array<std::uint32_t, D> at = coordinates(cell);
    const std::uint32_t rows = count_[1], columns = count_[0];
    if (at[1] != 0 && at[1] + 1 != rows) return;
    if (columns < 3) return;  // every column is around it already
    const std::uint32_t far = at[1] == 0 ? rows - 1 : 0;
    std::array<std::uint32_t, 3> planes{0, 0, 0};
    std::uint32_t plane_count = 1;
    if constexpr (D == 3) {
      const std::uint32_t n = count_[2];
      if (n < 3) {
        plane_count = n;
        for (std::uint32_t z = 0; z < n; ++z) planes[z] = z;
      } else {
        planes = {at[2] == 0 ? n - 1 : at[2] - 1, at[2], at[2] + 1 == n ? 0 : at[2] + 1};
        plane_count = 3;
      }
    }
    const std::uint32_t left = at[0] == 0 ? columns - 1 : at[0] - 1;
    const std::uint32_t right = at[0] + 1 == columns ? 0 : at[0] + 1;
    for (std::uint32_t z = 0; z < plane_count; ++z) {
      const std::uint32_t row = far * stride_[1] + (D == 3 ? planes[z] * stride_[D - 1] : 0);
      for (std::uint32_t x = 0; x < columns; ++x) {
        if (x == left || x == at[0] || x == right) continue;
        for (std::uint32_t j = head_[row + x]; j != kNone; j = next_[j]) visit(j);
      }
    }
  }

  // Calls visit(j) for every particle in the first and the last row of cells along y.
  template <class Visit>
  void for_each_in_edge_rows(Visit&& visit) const {
    const std::uint32_t rows = count_[1];
    const std::uint32_t planes = D == 3 ? count_[D - 1] : 1;
    const std::uint32_t last = rows > 1 ? 2 : 1;  // one row: visited once
    for (std::uint32_t edge = 0; edge < last; ++edge) {
      const std::uint32_t row = edge == 0 ? 0 : rows - 1;
      for (std::uint32_t z = 0; z < planes; ++z) {
        const std::uint32_t first = row * stride_[1] + (D == 3 ? z * stride_[D - 1] : 0);
        for (std::uint32_t x = 0; x < count_[0]; ++x) {
          for (std::uint32_t j = head_[first + x]; j != kNone; j = next_[j]) visit(j);
        }
      }
    }
  }

  // Whether `cell` is in the first or the last row along y (a sheared box's edge rows).
  bool in_edge_row(std::uint32_t cell) const {
    const std::uint32_t row = coordinate(cell, 1);
    return row == 0 || row + 1 == count_[1];
  }

  // Whether a particle of `cell` leaving it along y (up or down) leaves the box.
  bool leaves_along_y(std::uint32_t cell, bool upward) const {
    const std::uint32_t row = coordinate(cell, 1);
    return upward ? row + 1 == count_[1] : row == 0;
  }

  // Starts fetching what for_each_near(cell) will read first, for an event a few steps away.
  void prefetch_near(std::uint32_t cell) const {
    std::array<std::uint32_t, kBlock> cells;
    const std::size_t count = block(cell, cells);
    for (std::size_t c = 0; c < count; ++c) __builtin_prefetch(&head_[cells[c]]);
  }

  // The cell next to `cell` along `axis`, up or down (wrapping around a periodic box).
  std::uint32_t adjacent(std::uint32_t cell, std::size_t axis, bool upward) const {
    const std::uint32_t at = coordinate(cell, axis), n = count_[axis];
    if (upward) return at + 1 < n ? cell + stride_[axis] : cell - (n - 1) * stride_[axis];
    return at > 0 ? cell - stride_[axis] : cell + (n - 1) * stride_[axis];
  }

  struct Crossing {
    double delay = kNever;  // time from now until the particle leaves its cell
    std::uint8_t axis = 0;  // into adjacent(cell, axis, upward)
    bool upward = false;
  };

  // When a particle of `cell`, now at `position` and moving with `velocity`, enters another cell,
  // and which. In a box with walls, edge cells have no exit through the walls: the wall is hit
  // first. In a periodic box the position may lie outside the box (it is wrapped only when the
  // particle collides); it is taken relative to the cell, so round-off in wrapping cannot send a
  // particle to the far side of the box.
  Crossing next_crossing(std::uint32_t cell, const Vec<D>& position, const Vec<D>& velocity) const {
    const std::array<std::uint32_t, D> at = coordinates(cell);
    Crossing first;
    for (std::size_t k = 0; k < D; ++k) {
      const double v = velocity[k];
      const std::uint32_t n = count_[k];
      if (v == 0.0 || (box_.periodic() && n == 1)) continue;
      // From the cell's centre, wrapped to the nearest image: at most about half a cell, and so
      // unambiguous even when the axis has only two cells.
      double offset = position[k] - (at[k] + 0.5) * width_[k];
      // Within half a box (nearly always) the nearest image is this one: no division, no libm.
      if (box_.periodic() && !(std::abs(offset) <= 0.5 * box_.size[k])) {
        offset -= box_.size[k] * std::nearbyint(offset / box_.size[k]);
      }
      const double half = 0.5 * width_[k];
      double delay = kNever;
      if (v > 0.0 && (box_.periodic() || at[k] + 1 < n)) {
        delay = (half - offset) / v;
      } else if (v < 0.0 && (box_.periodic() || at[k] > 0)) {
        delay = (offset + half) / -v;
      }
      delay = std::max(delay, 0.0);
      if (delay < first.delay) {
        first = {delay, static_cast<std::uint8_t>(k), v > 0.0};
      }
    }
    return first;
  }

 private:
  // A cell's least width: a hair wider than the range at which particles touch (above).
  static constexpr double hair_wider(double min_width) { return min_width * (1.0 + 1e-6); }

  static constexpr std::size_t power_of_three(std::size_t k) {
    return k == 0 ? 1 : 3 * power_of_three(k - 1);
  }

  // How far (relative to a cell's width) a particle may lie outside the cell it was located in,
  // by the round-off of wrapping and dividing: far less than this.
  static constexpr double kLocatingSlack = 1e-6;

  // The place along `axis` of the cell containing a coordinate inside a periodic box; one beyond
  // the edges of a box with walls goes to the edge cell.
  std::uint32_t along_axis(double coordinate, std::size_t axis) const {
    const double at = std::floor(coordinate / width_[axis]);
    return static_cast<std::uint32_t>(std::clamp(at, 0.0, count_[axis] - 1.0));
  }

  static double most_cells(std::size_t particles) {
    return std::min(2.0 * static_cast<double>(particles) + 16.0, 0x1p31);
  }

  // The cell's place along each axis. Divisions by the grid's constant strides are done as
  // multiplications (Lemire, Kaser and Kurz, "Faster remainder by direct computation", 2019:
  // exact for every 32-bit numerator and divisor), which cost a tenth of a division.
  std::array<std::uint32_t, D> coordinates(std::uint32_t cell) const {
    std::array<std::uint32_t, D> at{};
    std::uint32_t rest = cell;
    for (std::size_t k = D; k-- > 1;) {
      at[k] = divide(rest, k);
      rest -= at[k] * stride_[k];
    }
    at[0] = rest;
    return at;
  }

  // coordinates(cell)[axis] alone.
  std::uint32_t coordinate(std::uint32_t cell, std::size_t axis) const {
    const std::uint32_t along = divide(cell, axis);
    return axis + 1 < D ? along - divide(cell, axis + 1) * count_[axis] : along;
  }

  // n / stride_[axis]. (A stride of 1, the first axis's or that of an axis after single cells,
  // has no 64-bit inverse.)
  std::uint32_t divide(std::uint32_t n, std::size_t axis) const {
    __extension__ using Wide = unsigned __int128;
    if (stride_[axis] == 1) return n;
    return static_cast<std::uint32_t>((static_cast<Wide>(inverse_stride_[axis]) * n) >> 64);
  }

  template <class LookAhead, class Visit>
  void visit_cells(std::array<std::uint32_t, kBlock>& heads, std::size_t cells,
                   LookAhead&& look_ahead, Visit&& visit) const {
    // First every list's head, then the lists: the heads are loaded side by side rather than each
    // after the last list's walk (at a million particles each is a cache miss).
    for (std::size_t c = 0; c < cells; ++c) {
      heads[c] = head_[heads[c]];
      if (heads[c] != kNone) {
        __builtin_prefetch(&next_[heads[c]]);
        look_ahead(heads[c]);
      }
    }
    for (std::size_t c = 0; c < cells; ++c) {
      for (std::uint32_t j = heads[c]; j != kNone; j = next_[j]) visit(j);
    }
  }

  // The cells around `cell`, its own included, each once: per axis at - 1 .. at + 1, wrapped in
  // a periodic box (all of them, once each, when the axis has fewer than three cells), clipped by
  // walls. Returns how many.
  std::size_t block(std::uint32_t cell, std::array<std::uint32_t, kBlock>& out) const {
    return block(cell, out, D, false);
  }

  // The same restricted to the cells one further along `axis` (up or down) than `cell`: the cells
  // around `cell` that were not around the cell it was entered from. None beyond a wall, and none
  // on a periodic axis of fewer than three cells (all of them were around it already).
  std::size_t layer(std::uint32_t cell, std::size_t axis, bool upward,
                    std::array<std::uint32_t, kBlock>& out) const {
    return block(cell, out, axis, upward);
  }

  // The cells around `cell` (or, for an axis below D, the layer ahead along it; see layer()).
  std::size_t block(std::uint32_t cell, std::array<std::uint32_t, kBlock>& out, std::size_t axis,
                    bool upward) const {
    const std::array<std::uint32_t, D> at = coordinates(cell);
    bool inner = true;
    for (std::size_t k = 0; k < D; ++k) inner = inner && at[k] >= 1 && at[k] + 2 <= count_[k];
    if (inner) {  // most cells: no wrapping, no clipping
      const auto offsets = axis == D
                               ? std::span<const std::int32_t>(inner_block_)
                               : std::span<const std::int32_t>(inner_layer_[2 * axis + upward]);
      for (std::size_t c = 0; c < offsets.size(); ++c) {
        out[c] = static_cast<std::uint32_t>(static_cast<std::int64_t>(cell) + offsets[c]);
      }
      return offsets.size();
    }
    std::array<std::array<std::uint32_t, 3>, D> along{};
    std::array<std::uint32_t, D> size{};
    for (std::size_t k = 0; k < D; ++k) {
      const std::uint32_t n = count_[k];
      if (k == axis) {
        if (box_.periodic() && n >= 3) {
          along[k][size[k]++] =
              upward ? (at[k] + 1 == n ? 0 : at[k] + 1) : (at[k] == 0 ? n - 1 : at[k] - 1);
        } else if (!box_.periodic() && (upward ? at[k] + 1 < n : at[k] > 0)) {
          along[k][size[k]++] = upward ? at[k] + 1 : at[k] - 1;
        }
        if (size[k] == 0) return 0;
      } else if (box_.periodic() && n < 3) {
        for (std::uint32_t c = 0; c < n; ++c) along[k][size[k]++] = c;
      } else if (box_.periodic()) {
        along[k] = {at[k] == 0 ? n - 1 : at[k] - 1, at[k], at[k] + 1 == n ? 0 : at[k] + 1};
        size[k] = 3;
      } else {
        for (std::uint32_t c = at[k] > 0 ? at[k] - 1 : 0; c <= std::min(at[k] + 1, n - 1); ++c) {
          along[k][size[k]++] = c;
        }
      }
    }
    // Every combination, the first axis fastest.
    for (std::size_t k = 0; k < D; ++k) {
      for (std::uint32_t c = 0; c < size[k]; ++c) along[k][c] *= stride_[k];
    }
    static_assert(D == 2 || D == 3);
    std::size_t count = 0;
    const std::uint32_t layers = D == 3 ? size[D - 1] : 1;
    for (std::uint32_t z = 0; z < layers; ++z) {
      const std::uint32_t plane = D == 3 ? along[D - 1][z] : 0;
      for (std::uint32_t y = 0; y < size[1]; ++y) {
        for (std::uint32_t x = 0; x < size[0]; ++x)
          out[count++] = plane + along[1][y] + along[0][x];
      }
    }
    return count;
  }

  void remove(std::uint32_t particle) {
    const std::uint32_t p = prev_[particle], n = next_[particle];
    if (p != kNone) {
      next_[p] = n;
    } else {
      head_[cell_of_[particle]] = n;
    }
    if (n != kNone) prev_[n] = p;
  }

  Box<D> box_;
  std::array<std::uint32_t, D> count_{};
  std::array<std::uint32_t, D> stride_{};
  std::array<std::uint64_t, D> inverse_stride_{};  // see divide()
  Vec<D> width_;
  std::array<std::int32_t, kBlock> inner_block_{};
  std::array<std::array<std::int32_t, kBlock / 3>, 2 * D> inner_layer_{};
  std::vector<std::uint32_t> head_;
  std::vector<std::uint32_t> next_, prev_, cell_of_;

 public:
  // Its lists in large pages (large_pages.hpp).
  void prefer_large_pages() const {
    for (const auto* entries : {&head_, &next_, &prev_, &cell_of_}) carom::prefer_large_pages(*entries);
  }
};

}  // namespace carom
