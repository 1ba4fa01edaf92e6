#include "carom/engine/validation.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "carom/core/physics.hpp"
#include "carom/engine/overlap.hpp"

namespace carom {

namespace {

// "(x, y)" or "(x, y, z)".
template <std::size_t D>
std::string point(const Vec<D>& v) {
  return fmt::format("({})", fmt::join(v.c, ", "));
}

}  // namespace

bool is_type_name(std::string_view name) {
  return !name.empty() && std::ranges::all_of(name, [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '+' ||
           c == '-';
  });
}

void check_number(double value, const std::string& what) {
  if (!std::isfinite(value)) {
    throw std::invalid_argument(fmt::format("{} is not a finite number: {}", what, value));
  }
  if (!within_magnitudes(value)) {
    throw std::invalid_argument(
        fmt::format("{} is out of range: {} (carom takes magnitudes from {} to {})", what, value,
                    kSmallestMagnitude, kLargestMagnitude));
  }
}

template <std::size_t D>
std::optional<std::string> particle_problem(std::size_t i, const Particle<D>& p, double mass,
                                            const Box<D>& b) {
  if (!(p.radius > 0.0)) {
    return fmt::format("the radius of particle {} must be greater than 0, found {}", i, p.radius);
  }
  if (!(mass > 0.0)) {
    return fmt::format("the mass of particle {} must be greater than 0, found {}", i, mass);
  }
  for (std::size_t k = 0; k < D; ++k) {
    if (!(p.position[k] >= 0.0 && p.position[k] <= b.size[k])) {
      std::string box = fmt::format("[0, {}]", b.size[0]);
      for (std::size_t axis = 1; axis < D; ++axis) box += fmt::format(" x [0, {}]", b.size[axis]);
      return fmt::format("particle {} at {} is outside the box {}", i, point(p.position), box);
    }
    // In a periodic box a particle must not reach its own image or two images of another.
    if (b.periodic() && !(b.size[k] > 4.0 * p.radius)) {
      return fmt::format(
          "particle {} with radius {} is too large for the periodic box: each side must exceed "
          "two diameters ({})",
          i, p.radius, 4.0 * p.radius);
    }
  }
  // Positions are doubles: in a box of largest side L they are resolved to about L x 2^-52, and
  // contacts need a small fraction of a diameter. (Regression: a disk of radius 1 in a box of
  // 3e38, resolved to 7e22, ended its run in NaN with exit 0.)
  const double largest = *std::max_element(b.size.c.begin(), b.size.c.end());
  const double resolution = largest * std::numeric_limits<double>::epsilon();
  if (resolution > kFinestContact * 2.0 * p.radius) {
    return fmt::format(
        "particle {} with radius {} is too small for a box of side {}: a double places it to "
        "about {:.3g} there, and its contacts need {:g} of a diameter (the box may be at most "
        "{:.3g} diameters across)",
        i, p.radius, largest, resolution, kFinestContact,
        kFinestContact / std::numeric_limits<double>::epsilon());
  }
  for (std::size_t k = 0; k < D && !b.periodic(); ++k) {
    for (const bool upper : {false, true}) {
      const int label = wall_label(k, upper);
      if (overlaps_wall(p, b, label)) {
        return fmt::format(
            "particle {} at {} with radius {} overlaps the {} wall (its centre must be at least "
            "R from every wall)",
            i, point(p.position), p.radius, wall_name(label));
      }
    }
  }
  return std::nullopt;
}

template <std::size_t D>
std::string describe_overlap(const System<D>& system, std::size_t i, std::size_t j, double radius,
                             const std::string& where_i) {
  const auto& pi = system.particles[i];
  const auto& pj = system.particles[j];
  return fmt::format(
      "particle {} at {} overlaps particle {} at {}{}: their centres are {} apart, less than {}", j,
      point(pj.position), i, point(pi.position), where_i,
      std::sqrt(norm2(separation(pi, pj, system.box))),
      pi.radius == radius && pj.radius == radius
          ? fmt::format("2R = {}", 2.0 * radius)
          : fmt::format("the sum of their radii, {}", pi.radius + pj.radius));
}

template <std::size_t D>
void check_start(const System<D>& system) {
  if (system.size() < 1) throw std::invalid_argument("a system needs at least one particle");
  if (system.records.size() != system.size()) {
    throw std::invalid_argument("a system needs one record (mass) per particle");
  }
  for (std::size_t k = 0; k < D; ++k) {
    check_number(system.box.size[k], "a box side");
    if (!(system.box.size[k] > 0.0)) {
      throw std::invalid_argument(
          fmt::format("the box sides must be greater than 0, found {}", system.box.size[k]));
    }
  }
  const std::vector<std::string>& names = system.type_names;
  if (names.empty()) throw std::invalid_argument("a system needs at least one type name");
  for (auto name = names.begin(); name != names.end(); ++name) {
    if (!is_type_name(*name)) {
      throw std::invalid_argument(fmt::format(
          "the type name \"{}\" must be letters, digits, _ . + or -, at least one", *name));
    }
    if (std::find(names.begin(), name, *name) != name) {
      throw std::invalid_argument(fmt::format("the type name {} appears twice", *name));
    }
  }
  for (std::size_t i = 0; i < system.size(); ++i) {
    const Particle<D>& p = system.particles[i];
    for (std::size_t k = 0; k < D; ++k) {
      check_number(p.position[k], fmt::format("the position of particle {}", i));
      check_number(p.velocity[k], fmt::format("the velocity of particle {}", i));
    }
    check_number(p.radius, fmt::format("the radius of particle {}", i));
    check_number(system.records[i].mass, fmt::format("the mass of particle {}", i));
    if (system.records[i].type >= names.size()) {
      throw std::invalid_argument(fmt::format(
          "the type {} of particle {} is not the index of one of the {} types (0 to {})",
          system.records[i].type, i, names.size(), names.size() - 1));
    }
    if (const auto problem = particle_problem(i, p, system.records[i].mass, system.box)) {
      throw std::invalid_argument(*problem);
    }
  }
  if (const auto overlap = find_pair_overlap(system, 0.0)) {
    throw std::invalid_argument(describe_overlap(system, overlap->first, overlap->second,
                                                 system.particles[overlap->first].radius));
  }
}

template std::optional<std::string> particle_problem(std::size_t, const Particle<2>&, double,
                                                     const Box<2>&);
template std::optional<std::string> particle_problem(std::size_t, const Particle<3>&, double,
                                                     const Box<3>&);
template std::string describe_overlap(const System<2>&, std::size_t, std::size_t, double,
                                      const std::string&);
template std::string describe_overlap(const System<3>&, std::size_t, std::size_t, double,
                                      const std::string&);
template void check_start(const System<2>&);
template void check_start(const System<3>&);

}  // namespace carom
