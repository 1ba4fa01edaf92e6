#include "carom/overlap.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "carom/physics.hpp"
#include "cell_grid.hpp"

namespace carom {

template <std::size_t D>
std::optional<std::pair<std::size_t, std::size_t>> find_pair_overlap(const System<D>& system,
                                                                     double time) {
  const auto& particles = system.particles;
  const auto n = static_cast<std::uint32_t>(particles.size());
  CellGrid<D> grid(system.box, 2.0 * largest_radius(system), n);
  std::vector<Vec<D>> at(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    at[i] = position_at(particles[i], time);
    grid.insert(i, grid.locate(at[i]));
  }
  const double keep = (1.0 - kOverlapTolerance) * (1.0 - kOverlapTolerance);
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t partner = n;
    grid.for_each_near(grid.cell_of(i), [&](std::uint32_t j) {
      if (j <= i || j >= partner) return;
      const double sigma = particles[i].radius + particles[j].radius;
      Vec<D> r = at[i] - at[j];
      r -= image_offset(r, system.box);
      if (norm2(r) < sigma * sigma * keep) partner = j;
    });
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
    if (box.periodic()) {
      wrap(p.position, box);
      continue;
    }
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
