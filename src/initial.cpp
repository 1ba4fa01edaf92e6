#include "carom/initial.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <pcg_random.hpp>
#include <vector>

#include "carom/observables.hpp"
#include "carom/overlap.hpp"
#include "cell_grid.hpp"

namespace carom {

namespace {

// Random sequential placement gives up when a disk finds no room in this many attempts.
constexpr int kAttemptsPerDisk = 10000;
// Above this packing fraction random placement slows down sharply (it jams near 0.547).
constexpr double kRandomUpTo = 0.4;

// Uniform in [0, 1) with 53 random bits; pcg32 gives 32 a call. (std:: distributions differ
// between standard libraries; this does not.)
double uniform(pcg32& rng) {
  const std::uint64_t hi = rng() >> 5, lo = rng() >> 6;
  return (static_cast<double>(hi) * 67108864.0 + static_cast<double>(lo)) / 9007199254740992.0;
}

// A standard normal deviate (Box-Muller; one of the pair, so each deviate costs two draws).
double normal(pcg32& rng) {
  const double u = 1.0 - uniform(rng);  // in (0, 1]: the logarithm is finite
  return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * std::numbers::pi * uniform(rng));
}

void place_randomly(System<2>& system, pcg32& rng) {
  const Box<2>& box = system.box;
  CellGrid<2> grid(box, 2.0 * largest_radius(system), system.particles.size());
  const bool walls = !box.periodic();
  for (std::uint32_t i = 0; i < system.particles.size(); ++i) {
    Particle<2>& p = system.particles[i];
    const double margin = walls ? p.radius : 0.0;
    bool placed = false;
    for (int attempt = 0; attempt < kAttemptsPerDisk && !placed; ++attempt) {
      for (std::size_t k = 0; k < 2; ++k) {
        p.position[k] = margin + (box.size[k] - 2.0 * margin) * uniform(rng);
      }
      placed = true;
      grid.for_each_near(grid.locate(p.position), [&](std::uint32_t j) {
        const double sigma = p.radius + system.particles[j].radius;
        if (norm2(separation(p, system.particles[j], box)) < sigma * sigma) placed = false;
      });
    }
    if (!placed) {
      throw InitialError(fmt::format("random placement jammed after {} of {} disks; use --lattice",
                                     i, system.particles.size()));
    }
    grid.insert(i, grid.locate(p.position));
  }
}

// A triangular lattice of `columns` x `rows` sites (odd rows shifted by half a spacing) filling
// the box: in a box with walls the sites span [R, L - R], in a periodic box they tile it.
struct Lattice {
  std::uint64_t columns = 0, rows = 0;
  double dx = 0.0, dy = 0.0;
  double closest = 0.0;  // the smallest distance between two sites (through images if periodic)
};

Lattice lattice_for(std::uint64_t columns, std::uint64_t rows, const Box<2>& box, double radius) {
  Lattice l{columns, rows};
  constexpr double kInf = kNever;
  if (box.periodic()) {
    l.dx = box.size[0] / columns;
    l.dy = box.size[1] / rows;
    const double diagonal = std::hypot(l.dx / 2.0, rows > 1 ? l.dy : box.size[1]);
    // With an odd number of rows the last row lines up with the first through the boundary.
    const double stacked = rows % 2 == 1 ? (rows > 1 ? l.dy : box.size[1]) : 2.0 * l.dy;
    l.closest = std::min({l.dx, diagonal, stacked});
    return l;
  }
  const double width = box.size[0] - 2.0 * radius, height = box.size[1] - 2.0 * radius;
  if (width < 0.0 || height < 0.0) return l;  // closest 0: does not fit
  l.dy = rows > 1 ? height / (rows - 1) : 0.0;
  if (columns == 1) {
    l.closest = rows > 1 ? l.dy : kInf;
  } else {
    l.dx = width / (rows > 1 ? columns - 0.5 : columns - 1.0);
    // Neighbours in a row, in the next row (shifted by half) and two rows up (straight above).
    const double above = rows > 2 ? 2.0 * l.dy : kInf;
    l.closest = rows > 1 ? std::min({l.dx, std::hypot(l.dx / 2.0, l.dy), above}) : l.dx;
  }
  return l;
}

Vec<2> site(const Lattice& l, std::uint64_t index, const Box<2>& box, double radius) {
  const std::uint64_t i = index % l.columns, j = index / l.columns;
  const double shift = l.rows > 1 && j % 2 == 1 ? 0.5 : 0.0;
  if (box.periodic()) return {{(i + 0.25 + shift) * l.dx, (j + 0.5) * l.dy}};
  const double x = l.columns == 1 ? box.size[0] / 2.0 : radius + (i + shift) * l.dx;
  const double y = l.rows == 1 ? box.size[1] / 2.0 : radius + j * l.dy;
  return {{x, y}};
}

void place_on_lattice(System<2>& system) {
  const std::uint64_t n = system.particles.size();
  const double largest = largest_radius(system);
  // The shape whose closest sites are farthest apart; ties go to fewer columns.
  Lattice best;
  for (std::uint64_t columns = 1; columns <= n; ++columns) {
    const std::uint64_t rows = (n + columns - 1) / columns;
    const Lattice l = lattice_for(columns, rows, system.box, largest);
    if (l.closest > best.closest) best = l;
  }
  if (!(best.closest >= 2.0 * largest)) {
    throw InitialError(fmt::format(
        "{} disks of radius up to {} do not fit on a lattice in this {} x {} box (closest sites "
        "{} apart, need {}): lower --phi or choose --aspect to fit the rows",
        n, largest, system.box.size[0], system.box.size[1], best.closest, 2.0 * largest));
  }
  for (std::uint64_t i = 0; i < n; ++i) {
    system.particles[i].position = site(best, i, system.box, largest);
  }
}

// Spreads the low 32 bits of x to the even bits of the result.
std::uint64_t spread(std::uint64_t x) {
  x &= 0xFFFFFFFFu;
  x = (x | (x << 16)) & 0x0000FFFF0000FFFFu;
  x = (x | (x << 8)) & 0x00FF00FF00FF00FFu;
  x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Fu;
  x = (x | (x << 2)) & 0x3333333333333333u;
  return (x | (x << 1)) & 0x5555555555555555u;
}

// Numbers the disks along a Z-order (Morton) curve of diameter-sized cells, so that disks close
// in space are close in memory: the engine then finds a disk's neighbours in cache. (A start file
// may number its disks freely.)
void sort_along_space_filling_curve(System<2>& system) {
  const double cell = 2.0 * largest_radius(system);
  const auto code = [&](const Particle<2>& p) {
    const auto cx = static_cast<std::uint64_t>(std::max(0.0, p.position[0] / cell));
    const auto cy = static_cast<std::uint64_t>(std::max(0.0, p.position[1] / cell));
    return spread(cx) | (spread(cy) << 1);
  };
  std::stable_sort(system.particles.begin(), system.particles.end(),
                   [&](const Particle<2>& a, const Particle<2>& b) { return code(a) < code(b); });
}

void draw_velocities(System<2>& system, double temperature, pcg32& rng) {
  auto& particles = system.particles;
  double mass = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const double scale = std::sqrt(temperature / system.records[i].mass);
    particles[i].velocity = {{scale * normal(rng), scale * normal(rng)}};
    mass += system.records[i].mass;
  }
  const Vec<2> drift = (1.0 / mass) * momentum(system);
  for (Particle<2>& p : particles) p.velocity -= drift;
  // The temperature the observables measure: over D N degrees of freedom with walls, D (N - 1)
  // in a periodic box.
  const double current = kinetic_temperature(system);
  if (current > 0.0) {
    const double scale = std::sqrt(temperature / current);
    for (Particle<2>& p : particles) p.velocity *= scale;
  }
}

}  // namespace

System<2> make_initial(const InitialOptions& o) {
  if (o.n < 1) throw InitialError("--n must be at least 1");
  if (o.n > 100'000'000) throw InitialError("--n above 100000000 is more than carom init makes");
  if (!(o.packing_fraction > 0.0)) throw InitialError("--phi must be greater than 0");
  if (!(o.packing_fraction <= kClosePacking)) {
    throw InitialError(fmt::format(
        "--phi {} is above close packing of disks ({:.4f}): no such configuration exists",
        o.packing_fraction, kClosePacking));
  }
  if (!(o.polydispersity >= 0.0 && o.polydispersity <= 0.5)) {
    throw InitialError("--polydispersity must be between 0 and 0.5");
  }
  if (!(o.temperature >= 0.0) || !std::isfinite(o.temperature)) {
    throw InitialError("--kT must be a finite number >= 0");
  }
  if (o.box && o.radius) {
    throw InitialError("give --box or --radius, not both: with --phi each fixes the other");
  }
  if (!(o.aspect > 0.0) || !std::isfinite(o.aspect)) throw InitialError("--aspect must be > 0");
  if (o.radius && !(*o.radius > 0.0)) throw InitialError("--radius must be greater than 0");
  if (o.box && !((*o.box)[0] > 0.0 && (*o.box)[1] > 0.0)) {
    throw InitialError("--box sides must be greater than 0");
  }

  pcg32 rng(o.seed);
  System<2> system;
  system.box.boundary = o.boundary;
  system.particles.resize(o.n);
  system.records.resize(o.n);
  // Radii relative to their mean, uniform with the requested relative standard deviation.
  double area = 0.0;
  for (Particle<2>& p : system.particles) {
    p.radius = 1.0 + o.polydispersity * std::sqrt(3.0) * (2.0 * uniform(rng) - 1.0);
    area += std::numbers::pi * p.radius * p.radius;
  }
  double scale = 0.0;
  if (o.box) {
    system.box.size = *o.box;
    scale = std::sqrt(o.packing_fraction * (*o.box)[0] * (*o.box)[1] / area);
  } else {
    scale = o.radius.value_or(0.5);
    const double box_area = area * scale * scale / o.packing_fraction;
    const double lx = std::sqrt(box_area * o.aspect);
    system.box.size = {{lx, box_area / lx}};
  }
  for (Particle<2>& p : system.particles) p.radius *= scale;
  // carom run refuses a periodic box that a particle could touch two images of another across.
  const double largest = largest_radius(system);
  if (system.box.periodic() && !(shortest_side(system.box) > 4.0 * largest)) {
    throw InitialError(fmt::format(
        "a periodic box of {} x {} is too small for disks of radius {}: each side must exceed "
        "two diameters; ask for more disks or a lower --phi",
        system.box.size[0], system.box.size[1], largest));
  }

  const bool random = o.placement == Placement::random ||
                      (o.placement == Placement::automatic && o.packing_fraction <= kRandomUpTo);
  if (random) {
    place_randomly(system, rng);
  } else {
    place_on_lattice(system);
  }
  sort_along_space_filling_curve(system);
  draw_velocities(system, o.temperature, rng);
  return system;
}

}  // namespace carom
