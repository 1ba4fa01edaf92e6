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
Vec<D> separation(const Particle<D>& a, const Particle<D>& b, const Box<D>& box) {
  const Vec<D> r = a.position - b.position;
  return r - image_offset(r, box);
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
template Vec<2> separation(const Particle<2>&, const Particle<2>&, const Box<2>&);
template Vec<3> separation(const Particle<3>&, const Particle<3>&, const Box<3>&);
template bool overlaps_wall(const Particle<2>&, const Box<2>&, int);
template bool overlaps_wall(const Particle<3>&, const Box<3>&, int);

}  // namespace carom
