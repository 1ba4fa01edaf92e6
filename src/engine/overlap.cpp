#include "carom/engine/overlap.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "carom/core/physics.hpp"
#include "cell_grid.hpp"

namespace carom {

template <std::size_t D>
std::optional<std::pair<std::size_t, std::size_t>> find_pair_overlap(const System<D>& system,
                                                                     double time) {
  const auto& particles = system.particles;
  const auto n = static_cast<std::uint32_t>(particles.size());
  CellGrid<D> grid(system.box, 2.0 * largest_radius(system), n);
  std::vector<Vec<D>> at(n);
  const Box<D>& box = system.box;
  for (std::uint32_t i = 0; i < n; ++i) {
    Particle<D> p = particles[i];
    advance(p, time);
    std::array<std::int32_t, 3> image{};
    if (box.sheared()) wrap(p, box, image);  // inside along y: the grid's row is its own
    at[i] = p.position;
    grid.insert(i, grid.locate(at[i]));
  }
  const double keep = (1.0 - kOverlapTolerance) * (1.0 - kOverlapTolerance);
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t partner = n;
    const auto check = [&](std::uint32_t j) {
      if (j <= i || j >= partner) return;
      const double sigma = particles[i].radius + particles[j].radius;
      Vec<D> r = at[i] - at[j];
      r -= box.sheared() ? sheared_offset(sheared_cells(r, box, time), box, time)
                         : image_offset(r, box);
      if (norm2(r) < sigma * sigma * keep) partner = j;
    };
    grid.for_each_near(grid.cell_of(i), check);
    if (box.sheared()) grid.for_each_across_shear(grid.cell_of(i), check);
    if (partner != n) return std::pair<std::size_t, std::size_t>{i, partner};
  }
  return std::nullopt;
}

template <std::size_t D>
bool overlaps_wall(const Particle<D>& p, const Box<D>& box, int label) {
  const std::size_t k = wall_axis(label);
  const double gap =
      wall_is_upper(label) ? box.size[k] - p.position[k] - p.radius : p.position[k] - p.radius;
  return gap < -kOverlapTolerance * p.radius;
}

template <std::size_t D>
std::optional<std::string> find_violation(const System<D>& system, double time) {
  const Box<D>& box = system.box;
  for (std::size_t i = 0; i < system.particles.size(); ++i) {
    Particle<D> p = system.particles[i];
    advance(p, time);
    if (box.periodic()) continue;
    for (std::size_t k = 0; k < D; ++k) {
      for (const bool upper : {false, true}) {
        const int wall = wall_label(k, upper);
        if (overlaps_wall(p, box, wall)) {
          return fmt::format("particle {} at {} reaches through the {} wall", i,
                             fmt::join(p.position.c, ", "), wall_name(wall));
        }
      }
    }
  }
  if (const auto pair = find_pair_overlap(system, time)) {
    Particle<D> a = system.particles[pair->first], b = system.particles[pair->second];
    advance(a, time);
    advance(b, time);
    std::array<std::int32_t, 3> image{};
    wrap(a, box, image);
    wrap(b, box, image);
    const double distance = std::sqrt(norm2(separation(a, b, box)));
    return fmt::format("particles {} and {} overlap: centres {} apart, contact at {}", pair->first,
                       pair->second, distance, a.radius + b.radius);
  }
  return std::nullopt;
}

template std::optional<std::string> find_violation(const System<2>&, double);
template std::optional<std::string> find_violation(const System<3>&, double);
template std::optional<std::pair<std::size_t, std::size_t>> find_pair_overlap(const System<2>&,
                                                                              double);
template std::optional<std::pair<std::size_t, std::size_t>> find_pair_overlap(const System<3>&,
                                                                              double);
template bool overlaps_wall(const Particle<2>&, const Box<2>&, int);
template bool overlaps_wall(const Particle<3>&, const Box<3>&, int);

}  // namespace carom
