// A uniform grid of cells over the box, at least one interaction range wide, so that the
// partners a particle can touch are all in its own cell or the 3^D cells around it. Each cell
// holds an intrusive doubly linked list of particle indices: moving a particle is O(1).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "carom/physics.hpp"
#include "carom/vec.hpp"

namespace carom {

template <std::size_t D>
class CellGrid {
 public:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;

  // `min_width` is the largest distance at which two particles can touch. Cells are a hair
  // wider still, so that a particle whose cell was assigned at a crossing time (subject to
  // round-off) still finds every possible partner in the block around it. The number of cells is
  // capped at about two per particle, so a huge sparse box costs no memory.
  CellGrid(const Vec<D>& box, double min_width, std::size_t particles)
      : next_(particles, kNone), prev_(particles, kNone), cell_of_(particles, kNone) {
    const double max_cells = std::min(2.0 * static_cast<double>(particles) + 16.0, 0x1p31);
    double width = min_width * (1.0 + 1e-6);
    double volume = 1.0;
    for (std::size_t k = 0; k < D; ++k) volume *= box[k];
    width = std::max(width, std::pow(volume / max_cells, 1.0 / static_cast<double>(D)));
    std::size_t total = 1;
    for (std::size_t k = 0; k < D; ++k) {
      const double fit = std::floor(box[k] / width);
      count_[k] = static_cast<std::uint32_t>(std::clamp(fit, 1.0, max_cells));
      width_[k] = box[k] / count_[k];
      stride_[k] = static_cast<std::uint32_t>(total);
      total *= count_[k];
    }
    head_.assign(total, kNone);
  }

  std::size_t cell_count() const { return head_.size(); }
  std::uint32_t cell_of(std::uint32_t particle) const { return cell_of_[particle]; }

  // The cell that contains `position`; positions on or beyond the box edge go to the edge cell.
  std::uint32_t locate(const Vec<D>& position) const {
    std::uint32_t cell = 0;
    for (std::size_t k = 0; k < D; ++k) {
      const double at = std::floor(position[k] / width_[k]);
      const double last = count_[k] - 1.0;
      cell += stride_[k] * static_cast<std::uint32_t>(std::clamp(at, 0.0, last));
    }
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

  // Calls visit(j) for every particle j in `cell` and the cells around it, `cell`'s own included.
  template <class Visit>
  void for_each_near(std::uint32_t cell, Visit&& visit) const {
    const std::array<std::uint32_t, D> at = coordinates(cell);
    std::array<std::uint32_t, D> lo{}, hi{};
    for (std::size_t k = 0; k < D; ++k) {
      lo[k] = at[k] > 0 ? at[k] - 1 : 0;
      hi[k] = std::min(at[k] + 1, count_[k] - 1);
    }
    std::array<std::uint32_t, D> c = lo;
    while (true) {
      std::uint32_t index = 0;
      for (std::size_t k = 0; k < D; ++k) index += c[k] * stride_[k];
      for (std::uint32_t j = head_[index]; j != kNone; j = next_[j]) visit(j);
      std::size_t k = 0;
      while (k < D && c[k] == hi[k]) {
        c[k] = lo[k];
        ++k;
      }
      if (k == D) break;
      ++c[k];
    }
  }

  struct Crossing {
    double delay = kNever;  // time from now until the particle leaves its cell
    std::uint32_t cell = kNone;
  };

  // When a particle of `cell`, now at `position` and moving with `velocity`, enters another cell,
  // and which. Edge cells have no exit through the box walls: the wall is hit first.
  Crossing next_crossing(std::uint32_t cell, const Vec<D>& position, const Vec<D>& velocity) const {
    const std::array<std::uint32_t, D> at = coordinates(cell);
    Crossing first;
    for (std::size_t k = 0; k < D; ++k) {
      const double v = velocity[k];
      double delay = kNever;
      std::uint32_t target = kNone;
      if (v > 0.0 && at[k] + 1 < count_[k]) {
        delay = ((at[k] + 1) * width_[k] - position[k]) / v;
        target = cell + stride_[k];
      } else if (v < 0.0 && at[k] > 0) {
        delay = (position[k] - at[k] * width_[k]) / -v;
        target = cell - stride_[k];
      }
      delay = std::max(delay, 0.0);
      if (delay < first.delay) first = {delay, target};
    }
    return first;
  }

 private:
  std::array<std::uint32_t, D> coordinates(std::uint32_t cell) const {
    std::array<std::uint32_t, D> at{};
    for (std::size_t k = 0; k < D; ++k) at[k] = (cell / stride_[k]) % count_[k];
    return at;
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

  std::array<std::uint32_t, D> count_{};
  std::array<std::uint32_t, D> stride_{};
  Vec<D> width_;
  std::vector<std::uint32_t> head_;
  std::vector<std::uint32_t> next_, prev_, cell_of_;
};

}  // namespace carom
