#include "carom/overlap.hpp"

#include <algorithm>

#include "carom/physics.hpp"
#include "cell_grid.hpp"

namespace carom {

template <std::size_t D>
std::optional<std::pair<std::size_t, std::size_t>> find_pair_overlap(const System<D>& system,
                                                                     double time) {
  const auto& particles = system.particles;
  const auto n = static_cast<std::uint32_t>(particles.size());
  double largest = 0.0;
  for (const Particle<D>& p : particles) largest = std::max(largest, p.radius);
  CellGrid<D> grid(system.box.size, 2.0 * largest, n);
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
      if (norm2(at[i] - at[j]) < sigma * sigma * keep) partner = j;
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

template std::optional<std::pair<std::size_t, std::size_t>> find_pair_overlap(const System<2>&,
                                                                              double);
template std::optional<std::pair<std::size_t, std::size_t>> find_pair_overlap(const System<3>&,
                                                                              double);
template bool overlaps_wall(const Particle<2>&, const Box<2>&, int);
template bool overlaps_wall(const Particle<3>&, const Box<3>&, int);

}  // namespace carom
