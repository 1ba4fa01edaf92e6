// The one neighbour search of the analyses (g(r), psi6, the Steinhardt bond order), private to
// the analysis layer.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nanoflann.hpp>
#include <utility>
#include <vector>

#include "carom/io/trajectory_reader.hpp"

namespace carom {

// The particles of one frame in a k-d tree (nanoflann), for the pairs within a range (g(r), the
// Steinhardt bond order's neighbours) and the nearest neighbours (psi6). Its cost does not depend
// on how the particles are spread: a cluster in a corner of a huge box (a clustering granular gas)
// costs what a uniform fluid does, O(log N) a query, where cells sized from the mean density held
// the cluster in one cell. Searches give candidates; distances are then taken by separation(), the
// minimum image, so the results do not depend on the tree's own rounding.
template <std::size_t D>
class Neighbours {
 public:
  explicit Neighbours(const Frame& frame)
      : frame_(frame), points_{wrapped(frame)}, tree_(D, points_), seen_(frame.position.size(), 0) {
    tree_.buildIndex();
  }

  std::size_t size() const { return points_.at.size(); }

  // The displacement from particle i to particle j (minimum image in a periodic box; in a
  // sheared one, y first, whose image carries the shift along x).
  Vec<D> separation(std::size_t i, std::size_t j) const {
    Vec<D> r;
    for (std::size_t k = 0; k < D; ++k) r[k] = frame_.position[j][k] - frame_.position[i][k];
    if (frame_.periodic) {
      take_whole_sides(frame_, r, [](double sides) { return std::nearbyint(sides); });
    }
    return r;
  }

  // Calls f(j) once for every particle j other than i that may be within `reach` of it (every
  // one that is, and maybe a few just beyond): in a periodic box, the images of i whose ball
  // reaches into the box are searched too.
  template <class F>
  void for_each_candidate(std::size_t i, double reach, F&& f) {
    // Slack for the difference between the tree's distances and separation()'s.
    const double r = reach * (1.0 + 1e-9) + 1e-300;
    ++stamp_;
    std::array<int, D> shift{};
    shift.fill(frame_.periodic ? -1 : 0);
    const int last = frame_.periodic ? 1 : 0;
    while (true) {
      std::array<double, D> q{};
      bool reaches = true;
      for (std::size_t k = 0; k < D; ++k) q[k] = points_.at[i][k] + shift[k] * frame_.box[k];
      // A sheared box's images one box up lie shear_shift further along x (within half a side of
      // 0 as carom writes it, so that shifts of -1, 0 and 1 sides along x still cover the box).
      q[0] += shift[1] * wrapped_shift_;
      for (std::size_t k = 0; k < D; ++k) {
        reaches = reaches && q[k] + r >= 0.0 && q[k] - r <= frame_.box[k];
      }
      if (reaches) {
        found_.clear();
        tree_.radiusSearch(q.data(), r * r, found_, nanoflann::SearchParams(32, 0.0, false));
        for (const auto& [j, distance2] : found_) {
          if (j == i || seen_[j] == stamp_) continue;
          seen_[j] = stamp_;
          f(static_cast<std::size_t>(j));
        }
      }
      std::size_t k = 0;
      while (k < D && shift[k] == last) shift[k++] = frame_.periodic ? -1 : 0;
      if (k == D) break;
      ++shift[k];
    }
  }

  // A distance within which particle i has at least `k` other particles (its k-th nearest in
  // the tree, which the minimum image can only bring closer); infinite with fewer than k others.
  double reach_of_nearest(std::size_t i, std::size_t k) const {
    if (size() <= k) return std::numeric_limits<double>::infinity();
    nearest_.resize(k + 1);
    distance2_.resize(k + 1);
    tree_.knnSearch(points_.at[i].data(), k + 1, nearest_.data(), distance2_.data());
    return std::sqrt(*std::max_element(distance2_.begin(), distance2_.end()));
  }

 private:
  // The positions as the tree reads them: in [0, L) in a periodic box.
  struct Points {
    std::vector<std::array<double, D>> at;
    std::size_t kdtree_get_point_count() const { return at.size(); }
    double kdtree_get_pt(std::size_t i, std::size_t k) const { return at[i][k]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Points>,
                                                   Points, static_cast<int>(D), std::uint32_t>;

  // In a sheared box, the images' shift within half a side of 0 (any multiple of Lx names the
  // same lattice), so that for_each_candidate's images along x reach every part of the box.
  static double nearest_shift(const Frame& frame) {
    return frame.shear_shift - frame.box[0] * std::nearbyint(frame.shear_shift / frame.box[0]);
  }

  static Points wrapped(const Frame& frame) {
    Points points;
    points.at.resize(frame.position.size());
    for (std::size_t i = 0; i < frame.position.size(); ++i) {
      std::array<double, D>& x = points.at[i];
      for (std::size_t k = 0; k < D; ++k) x[k] = frame.position[i][k];
      if (frame.periodic) {
        take_whole_sides(frame, x, [](double sides) { return std::floor(sides); });
      }
    }
    return points;
  }

  // x less whole sides of the periodic box, as many along each axis as `whole` makes of x's
  // sides there: y first, as a move by whole layers of a sheared box moves x by the shift as well.
  // Rounded to the nearest, a separation's minimum image; rounded down, a position in the box.
  template <class Point, class Whole>
  static void take_whole_sides(const Frame& frame, Point& x, Whole whole) {
    const double layers = whole(x[1] / frame.box[1]);
    x[1] -= layers * frame.box[1];
    x[0] -= layers * frame.shear_shift;
    for (std::size_t k = 0; k < D; ++k) {
      if (k != 1) x[k] -= frame.box[k] * whole(x[k] / frame.box[k]);
    }
  }

  const Frame& frame_;
  double wrapped_shift_ = nearest_shift(frame_);
  Points points_;
  Tree tree_;
  std::vector<std::uint64_t> seen_;  // the stamp of the search that last found each particle
  std::uint64_t stamp_ = 0;
  std::vector<std::pair<std::uint32_t, double>> found_;
  mutable std::vector<std::uint32_t> nearest_;
  mutable std::vector<double> distance2_;
};

}  // namespace carom
