#include "carom/engine/initial.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <pcg_random.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "carom/core/observables.hpp"
#include "carom/core/random.hpp"
#include "carom/engine/overlap.hpp"
#include "carom/engine/validation.hpp"
#include "cell_grid.hpp"

namespace carom {

namespace {

// Random sequential placement gives up when a particle finds no room in this many attempts.
constexpr int kAttemptsPerParticle = 10000;
// Lattice sites closer than the contact distance by this relative amount are taken as touching:
// a lattice at close packing computes its spacing and the radii with separate roundings. (The
// reader accepts overlaps up to kOverlapTolerance, 1e-9, as round-off.)
constexpr double kLatticeSlack = 1e-12;

}  // namespace

namespace {

template <std::size_t D>
void place_randomly(System<D>& system, pcg32& rng) {
  const Box<D>& box = system.box;
  CellGrid<D> grid(box, 2.0 * largest_radius(system), system.particles.size());
  const bool walls = !box.periodic();
  for (std::uint32_t i = 0; i < system.particles.size(); ++i) {
    Particle<D>& p = system.particles[i];
    const double margin = walls ? p.radius : 0.0;
    bool placed = false;
    for (int attempt = 0; attempt < kAttemptsPerParticle && !placed; ++attempt) {
      for (std::size_t k = 0; k < D; ++k) {
        p.position[k] = margin + (box.size[k] - 2.0 * margin) * uniform_deviate(rng);
      }
      placed = true;
      grid.for_each_near(grid.locate(p.position), [&](std::uint32_t j) {
        const double sigma = p.radius + system.particles[j].radius;
        if (norm2(separation(p, system.particles[j], box)) < sigma * sigma) placed = false;
      });
    }
    if (!placed) {
      throw InitialError(fmt::format("random placement jammed after {} of {} {}; use --lattice", i,
                                     system.particles.size(), kParticlesName<D>));
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
  if (!(best.closest >= 2.0 * largest * (1.0 - kLatticeSlack))) {
    throw InitialError(fmt::format(
        "{} disks of radius up to {} do not fit on a lattice in this {} x {} box (closest sites "
        "{} apart, need {}): lower --phi or choose --aspect to fit the rows",
        n, largest, system.box.size[0], system.box.size[1], best.closest, 2.0 * largest));
  }
  for (std::uint64_t i = 0; i < n; ++i) {
    system.particles[i].position = site(best, i, system.box, largest);
  }
}

// A face-centred cubic lattice: the sites (i sx, j sy, k sz) with i + j + k even, m[0] x m[1] x
// m[2] grid points. In a box with walls the points span [R, L - R] on each axis; in a periodic
// box they tile it (every m even, so the parity holds across the boundary). At equal spacings
// s = a / 2 this is FCC with cube side a, which reaches close packing.
struct CubicLattice {
  std::array<std::uint64_t, 3> m{};
  Vec<3> spacing;
  std::uint64_t sites = 0;
  double closest = 0.0;  // the smallest distance between two sites (through images if periodic)
};

CubicLattice fcc_lattice_for(const std::array<std::uint64_t, 3>& m, const Box<3>& box,
                             double radius) {
  CubicLattice l;
  l.m = m;
  const std::uint64_t points = m[0] * m[1] * m[2];
  const bool all_odd = m[0] % 2 == 1 && m[1] % 2 == 1 && m[2] % 2 == 1;
  l.sites = box.periodic() ? points / 2 : (points + (all_odd ? 1 : 0)) / 2;
  // Which offsets join two sites: two steps along an axis needs three points on it (or, in a
  // periodic box, two: the step wraps), a diagonal step one point more on each of two axes.
  std::array<bool, 3> two_steps{}, one_step{};
  for (std::size_t k = 0; k < 3; ++k) {
    if (box.periodic()) {
      l.spacing[k] = box.size[k] / static_cast<double>(m[k]);
    } else {
      const double span = box.size[k] - 2.0 * radius;
      if (span < 0.0) return l;  // closest 0: does not fit
      l.spacing[k] = m[k] > 1 ? span / static_cast<double>(m[k] - 1) : 0.0;
    }
    one_step[k] = m[k] >= 2;
    two_steps[k] = m[k] >= 3 || (box.periodic() && m[k] >= 2);
  }
  double closest = kNever;
  for (std::size_t a = 0; a < 3; ++a) {
    if (two_steps[a]) closest = std::min(closest, 2.0 * l.spacing[a]);
    for (std::size_t b = a + 1; b < 3; ++b) {
      if (one_step[a] && one_step[b]) {
        closest = std::min(closest, std::hypot(l.spacing[a], l.spacing[b]));
      }
    }
  }
  l.closest = closest;
  return l;
}

void place_on_lattice(System<3>& system) {
  const std::uint64_t n = system.particles.size();
  const double largest = largest_radius(system);
  const Box<3>& box = system.box;
  // Every shape of grid with room for n sites whose closest sites are farthest apart; ties go to
  // the first found (fewer points along x, then y). More points along z than needed only
  // bring sites closer, so z takes the fewest that give room.
  const std::uint64_t step = box.periodic() ? 2 : 1;
  const auto most = static_cast<std::uint64_t>(4.0 * std::cbrt(2.0 * n)) + 2;
  CubicLattice best;
  for (std::uint64_t mx = step; mx <= most; mx += step) {
    for (std::uint64_t my = step; my <= most; my += step) {
      std::uint64_t mz = std::max<std::uint64_t>(step, (2 * n / (mx * my)) / step * step);
      mz = mz > step ? mz - step : mz;
      CubicLattice l = fcc_lattice_for({mx, my, mz}, box, largest);
      while (l.sites < n) l = fcc_lattice_for({mx, my, mz += step}, box, largest);
      if (l.closest > best.closest) best = l;
    }
  }
  if (!(best.closest >= 2.0 * largest * (1.0 - kLatticeSlack))) {
    throw InitialError(fmt::format(
        "{} spheres of radius up to {} do not fit on a lattice in this {} x {} x {} box (closest "
        "sites {} apart, need {}): lower --phi{}",
        n, largest, box.size[0], box.size[1], box.size[2], best.closest, 2.0 * largest,
        box.periodic() ? ", or take N = 4 n^3 (500, 4000, 32000, ...) in a cube, which fills "
                         "whole FCC cells up to close packing"
                       : " (with walls the centres keep R from every wall, which leaves less room "
                         "than a periodic box)"));
  }
  // The n particles take sites spread evenly over the grid, so that vacancies are spread too.
  const auto [mx, my, mz] = best.m;
  std::uint64_t site = 0, placed = 0;
  for (std::uint64_t k = 0; k < mz && placed < n; ++k) {
    for (std::uint64_t j = 0; j < my && placed < n; ++j) {
      for (std::uint64_t i = 0; i < mx && placed < n; ++i) {
        if ((i + j + k) % 2 == 1) continue;
        // Particle `placed` takes site floor(placed * sites / n).
        if (site++ != placed * best.sites / n) continue;
        const std::array<std::uint64_t, 3> index{i, j, k};
        Vec<3>& position = system.particles[placed++].position;
        for (std::size_t a = 0; a < 3; ++a) {
          const double at = static_cast<double>(index[a]) * best.spacing[a];
          position[a] = box.periodic()   ? at + 0.25 * best.spacing[a]
                        : best.m[a] == 1 ? box.size[a] / 2.0
                                         : largest + at;
        }
      }
    }
  }
}

// Spreads the low bits of x so that D - 1 zero bits follow each: the bits of one coordinate of a
// Morton code (32 bits of it in 2D, 21 in 3D).
template <std::size_t D>
std::uint64_t spread(std::uint64_t x) {
  if constexpr (D == 2) {
    x &= 0xFFFFFFFFu;
    x = (x | (x << 16)) & 0x0000FFFF0000FFFFu;
    x = (x | (x << 8)) & 0x00FF00FF00FF00FFu;
    x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Fu;
    x = (x | (x << 2)) & 0x3333333333333333u;
    return (x | (x << 1)) & 0x5555555555555555u;
  } else {
    x &= 0x1FFFFFu;
    x = (x | (x << 32)) & 0x001F00000000FFFFu;
    x = (x | (x << 16)) & 0x001F0000FF0000FFu;
    x = (x | (x << 8)) & 0x100F00F00F00F00Fu;
    x = (x | (x << 4)) & 0x10C30C30C30C30C3u;
    return (x | (x << 2)) & 0x1249249249249249u;
  }
}

// Numbers the particles along a Z-order (Morton) curve of diameter-sized cells, so that particles
// close in space are close in memory: the engine then finds a particle's neighbours in cache.
// (A start file may number its particles freely.)
template <std::size_t D>
void sort_along_space_filling_curve(System<D>& system) {
  const double cell = 2.0 * largest_radius(system);
  const auto code = [&](const Particle<D>& p) {
    std::uint64_t morton = 0;
    for (std::size_t k = 0; k < D; ++k) {
      const auto c = static_cast<std::uint64_t>(std::max(0.0, p.position[k] / cell));
      morton |= spread<D>(c) << k;
    }
    return morton;
  };
  // An order of indices, applied to the particles and their records (types) alike.
  std::vector<std::uint32_t> order(system.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return code(system.particles[a]) < code(system.particles[b]);
  });
  std::vector<Particle<D>> particles(system.size());
  std::vector<ParticleRecord> records(system.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    particles[i] = system.particles[order[i]];
    records[i] = system.records[order[i]];
  }
  system.particles = std::move(particles);
  system.records = std::move(records);
}

template <std::size_t D>
void draw_velocities(System<D>& system, double temperature, pcg32& rng) {
  auto& particles = system.particles;
  double mass = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const double scale = std::sqrt(temperature / system.records[i].mass);
    for (std::size_t k = 0; k < D; ++k) particles[i].velocity[k] = scale * normal_deviate(rng);
    mass += system.records[i].mass;
  }
  const Vec<D> drift = (1.0 / mass) * momentum(system);
  for (Particle<D>& p : particles) p.velocity -= drift;
  // The temperature the observables measure: over D N degrees of freedom with walls, D (N - 1)
  // in a periodic box.
  const double current = kinetic_temperature(system);
  if (current > 0.0) {
    const double scale = std::sqrt(temperature / current);
    for (Particle<D>& p : particles) p.velocity *= scale;
  }
}

// The area of a disk, the volume of a sphere.
template <std::size_t D>
double volume_of(double radius) {
  if constexpr (D == 2) return std::numbers::pi * radius * radius;
  return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
}

template <std::size_t D>
double root(double x) {
  if constexpr (D == 2) return std::sqrt(x);
  return std::cbrt(x);
}

template <std::size_t D>
void check_options(const InitialOptions& o) {
  if (o.n < 1) throw InitialError("--n must be at least 1");
  if (o.n > 100'000'000) throw InitialError("--n above 100000000 is more than carom init makes");
  if (!(o.packing_fraction > 0.0)) throw InitialError("--phi must be greater than 0");
  if (!(o.packing_fraction <= close_packing(D))) {
    throw InitialError(
        fmt::format("--phi {} is above close packing of {} ({:.4f}): no such configuration exists",
                    o.packing_fraction, kParticlesName<D>, close_packing(D)));
  }
  if (!o.species.empty()) {
    if (o.polydispersity != 0.0) {
      throw InitialError(
          "give --species or --polydispersity, not both: each species has its own diameter");
    }
    if (o.radius) {
      throw InitialError("give --species or --radius, not both: the species give the diameters");
    }
    // Checked as parse_species does (a caller may fill them in directly).
    (void)parse_species(species_text(o.species));
  }
  if (!(o.polydispersity >= 0.0 && o.polydispersity <= 0.5)) {
    throw InitialError("--polydispersity must be between 0 and 0.5");
  }
  if (!(o.temperature >= 0.0) || !std::isfinite(o.temperature)) {
    throw InitialError("--kT must be a finite number >= 0");
  }
  if (!o.box.empty() && o.radius) {
    throw InitialError("give --box or --radius, not both: with --phi each fixes the other");
  }
  if (!(o.aspect > 0.0) || !std::isfinite(o.aspect)) throw InitialError("--aspect must be > 0");
  if (o.radius && !(*o.radius > 0.0 && std::isfinite(*o.radius))) {
    throw InitialError("--radius must be a finite number greater than 0");
  }
  if (!o.box.empty() && o.box.size() != D) {
    throw InitialError(
        fmt::format("--box needs {} sides for {}, not {}", D, kParticlesName<D>, o.box.size()));
  }
  for (double side : o.box) {
    if (!(side > 0.0) || !std::isfinite(side)) {
      throw InitialError("--box sides must be finite numbers greater than 0");
    }
  }
}

}  // namespace

void check_initial_options(std::size_t dimension, const InitialOptions& options) {
  if (dimension == 3) {
    check_options<3>(options);
  } else {
    check_options<2>(options);
  }
}

namespace {

// `text` as a number, the whole of it; nullopt if it is not one.
std::optional<double> number_of(std::string_view text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

std::vector<Species> parse_species(std::string_view text) {
  std::vector<Species> species;
  const auto fail = [&](const std::string& what) {
    throw InitialError(
        fmt::format("--species \"{}\": {} (give NAME:FRACTION:DIAMETER entries "
                    "separated by commas, as \"A:0.5:1.0,B:0.5:1.4\")",
                    text, what));
  };
  if (text.empty()) fail("no species");
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view entry = text.substr(start, comma - start);
    start = comma + 1;
    const std::size_t first = entry.find(':');
    const std::size_t second = first == std::string_view::npos ? first : entry.find(':', first + 1);
    if (second == std::string_view::npos || entry.find(':', second + 1) != std::string_view::npos) {
      fail(fmt::format("\"{}\" is not NAME:FRACTION:DIAMETER", entry));
    }
    Species s;
    s.name = std::string(entry.substr(0, first));
    if (!is_type_name(s.name)) {
      fail(fmt::format("the name \"{}\" must be letters, digits, _ . + or -", s.name));
    }
    for (const Species& other : species) {
      if (other.name == s.name) fail(fmt::format("the name {} appears twice", s.name));
    }
    const auto fraction = number_of(entry.substr(first + 1, second - first - 1));
    if (!fraction || !(*fraction > 0.0 && *fraction <= 1.0)) {
      fail(fmt::format("the fraction of {} must be a number in (0, 1]", s.name));
    }
    const auto diameter = number_of(entry.substr(second + 1));
    if (!diameter || !(*diameter > 0.0 && std::isfinite(*diameter))) {
      fail(fmt::format("the diameter of {} must be a finite number above 0", s.name));
    }
    s.fraction = *fraction;
    s.diameter = *diameter;
    species.push_back(std::move(s));
    if (comma == text.size()) break;
  }
  double sum = 0.0;
  for (const Species& s : species) sum += s.fraction;
  if (!(std::abs(sum - 1.0) <= 1e-12)) {
    fail(fmt::format("the fractions sum to {}, not 1", sum));
  }
  return species;
}

std::string species_text(const std::vector<Species>& species) {
  std::string text;
  for (const Species& s : species) {
    text += fmt::format("{}{}:{}:{}", text.empty() ? "" : ",", s.name, s.fraction, s.diameter);
  }
  return text;
}

std::vector<std::uint64_t> species_counts(const std::vector<Species>& species, std::uint64_t n) {
  std::vector<std::uint64_t> counts(species.size());
  std::vector<double> remainders(species.size());
  std::uint64_t given = 0;
  for (std::size_t t = 0; t < species.size(); ++t) {
    const double share = species[t].fraction * static_cast<double>(n);
    counts[t] = static_cast<std::uint64_t>(std::floor(share));
    remainders[t] = share - static_cast<double>(counts[t]);
    given += counts[t];
  }
  std::vector<std::size_t> order(species.size());
  for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return remainders[a] > remainders[b]; });
  for (std::size_t k = 0; given < n; k = (k + 1) % order.size(), ++given) ++counts[order[k]];
  while (given > n) {  // round-off in a sum above 1 by 1e-12 times a huge n
    for (std::size_t t = counts.size(); t-- > 0 && given > n;) {
      if (counts[t] > 0) --counts[t], --given;
    }
  }
  return counts;
}

template <std::size_t D>
System<D> make_initial(const InitialOptions& o) {
  check_options<D>(o);
  pcg32 rng(o.seed);
  System<D> system;
  system.box.boundary = o.boundary;
  system.particles.resize(o.n);
  system.records.resize(o.n);
  double volume = 0.0;
  if (o.species.empty()) {
    // Radii relative to their mean, uniform with the requested relative standard deviation.
    for (Particle<D>& p : system.particles) {
      p.radius = 1.0 + o.polydispersity * std::sqrt(3.0) * (2.0 * uniform_deviate(rng) - 1.0);
      volume += volume_of<D>(p.radius);
    }
  } else {
    // Each species' count in order, then shuffled (Fisher-Yates on the seed's stream); radii
    // relative to diameter 1's (the default radius 0.5 scales them to the diameters asked for).
    const std::vector<std::uint64_t> counts = species_counts(o.species, o.n);
    system.type_names.clear();
    std::size_t next = 0;
    for (std::uint32_t t = 0; t < counts.size(); ++t) {
      system.type_names.push_back(o.species[t].name);
      for (std::uint64_t c = 0; c < counts[t]; ++c) system.records[next++].type = t;
    }
    for (std::size_t i = system.size() - 1; i > 0; --i) {
      const std::size_t j = rng(static_cast<std::uint32_t>(i + 1));
      std::swap(system.records[i].type, system.records[j].type);
    }
    for (std::size_t i = 0; i < system.size(); ++i) {
      Particle<D>& p = system.particles[i];
      p.radius = o.species[system.records[i].type].diameter;
      volume += volume_of<D>(p.radius);
    }
  }
  double scale = 0.0;
  if (!o.box.empty()) {
    double covered = o.packing_fraction;
    for (std::size_t k = 0; k < D; ++k) {
      system.box.size[k] = o.box[k];
      covered *= o.box[k];
    }
    scale = root<D>(covered / volume);
  } else {
    scale = o.radius.value_or(kDefaultRadius);
    const double box_volume = volume * scale * scale * (D == 3 ? scale : 1.0) / o.packing_fraction;
    // Lx = aspect Ly, and in 3D Lz = Ly.
    if constexpr (D == 2) {
      const double lx = std::sqrt(box_volume * o.aspect);
      system.box.size = {{lx, box_volume / lx}};
    } else {
      const double side = std::cbrt(box_volume / o.aspect);
      system.box.size = {{o.aspect * side, side, side}};
    }
  }
  for (Particle<D>& p : system.particles) p.radius *= scale;
  // Sizes carom run could not read back (a packing fraction of 1e-200 makes a box of 1e100) or
  // that degenerate (a radius that underflows to 0) are refused before any placement is tried.
  const double largest = largest_radius(system);
  try {
    for (std::size_t k = 0; k < D; ++k) check_number(system.box.size[k], "a box side");
    for (const Particle<D>& p : system.particles) check_number(p.radius, "a radius");
  } catch (const std::invalid_argument& e) {
    throw InitialError(fmt::format(
        "these options give a box of sides {} and radii up to {}: {}; change --phi, --box or "
        "--radius",
        fmt::join(system.box.size.c, " x "), largest, e.what()));
  }
  if (!(largest > 0.0)) throw InitialError("these options give particles of radius 0");
  for (std::size_t k = 0; k < D && !system.box.periodic(); ++k) {
    if (!(system.box.size[k] >= 2.0 * largest)) {
      throw InitialError(fmt::format(
          "a box of sides {} cannot hold {} of radius {} between its walls; change --aspect, "
          "--box or --phi",
          fmt::join(system.box.size.c, " x "), kParticlesName<D>, largest));
    }
  }
  // carom run refuses a periodic box that a particle could touch two images of another across.
  if (system.box.periodic() && !(shortest_side(system.box) > 4.0 * largest)) {
    throw InitialError(fmt::format(
        "a periodic box of sides {} is too small for {} of radius {}: each side must exceed "
        "two diameters; ask for more {} or a lower --phi",
        fmt::join(system.box.size.c, " x "), kParticlesName<D>, largest, kParticlesName<D>));
  }

  // Automatic placement tries random placement at low packing fractions and falls back on the
  // lattice when it jams (a few particles in a small box can).
  const bool try_random =
      o.placement == Placement::random ||
      (o.placement == Placement::automatic && o.packing_fraction <= random_placement_limit(D));
  bool placed = false;
  if (try_random) {
    try {
      place_randomly(system, rng);
      placed = true;
    } catch (const InitialError&) {
      if (o.placement == Placement::random) throw;
    }
  }
  if (!placed) place_on_lattice(system);
  sort_along_space_filling_curve(system);
  draw_velocities(system, o.temperature, rng);
  // What carom init writes, carom run accepts: the reader's own checks, as a last guard.
  try {
    check_start(system);
  } catch (const std::invalid_argument& e) {
    throw InitialError(fmt::format("carom init made a start carom run would refuse: {}", e.what()));
  }
  return system;
}

template <std::size_t D>
void draw_velocities(System<D>& system, double temperature, std::uint64_t seed) {
  if (!(temperature > 0.0)) {
    throw std::invalid_argument(fmt::format("kT must be greater than 0, got {}", temperature));
  }
  check_number(temperature, "kT");
  pcg32 rng(seed);
  draw_velocities(system, temperature, rng);
}

template <std::size_t D>
double mean_diameter(const System<D>& system) {
  double sum = 0.0;
  for (const Particle<D>& p : system.particles) sum += 2.0 * p.radius;
  return sum / static_cast<double>(system.size());
}

template <std::size_t D>
void scale_lengths(System<D>& system, double factor) {
  if (!(factor > 0.0 && std::isfinite(factor))) {
    throw std::invalid_argument(fmt::format("a length factor must be above 0, got {}", factor));
  }
  // Multiplying by one factor keeps every order (inside the box, clear of a wall) that held;
  // sums of scaled lengths may differ from scaled sums by an ulp, which readers count as touching.
  system.box.size *= factor;
  for (Particle<D>& p : system.particles) {
    p.position *= factor;
    p.radius *= factor;
  }
}

template System<2> make_initial(const InitialOptions&);
template System<3> make_initial(const InitialOptions&);
template void draw_velocities(System<2>&, double, std::uint64_t);
template void draw_velocities(System<3>&, double, std::uint64_t);
template double mean_diameter(const System<2>&);
template double mean_diameter(const System<3>&);
template void scale_lengths(System<2>&, double);
template void scale_lengths(System<3>&, double);

}  // namespace carom
