// Whether a start is one carom can run: every number in range, each particle inside its box and
// clear of the walls, no two overlapping. The readers of every start format (classic, GSD,
// checkpoints) and the makers of starts (carom init, arrays from Python) check with these.
#pragma once

#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "carom/core/system.hpp"

namespace carom {

// The magnitudes a start file's numbers may have (or 0): lengths and speeds are squared in
// predictions, and beyond these the squares overflow or underflow.
inline constexpr double kLargestMagnitude = 1e100;
inline constexpr double kSmallestMagnitude = 1e-100;
// Whether a finite number's magnitude is one carom takes: 0, or from kSmallestMagnitude to
// kLargestMagnitude.
inline bool within_magnitudes(double value) {
  return value == 0.0 ||
         (std::abs(value) >= kSmallestMagnitude && std::abs(value) <= kLargestMagnitude);
}
// The spacing of doubles across the box, as a fraction of a particle's diameter, beyond which its
// contacts cannot be resolved: a box at most about 4.5e9 diameters across.
inline constexpr double kFinestContact = 1e-6;

// Checks a number a program supplies as the reader checks one it parses: finite, and a magnitude
// from kSmallestMagnitude to kLargestMagnitude (or 0); throws std::invalid_argument naming
// `what`.
void check_number(double value, const std::string& what);

// What is wrong with particle i of a start, if anything: a radius or mass not above 0, a centre
// outside the box, too large for a periodic box, or reaching through a wall.
template <std::size_t D>
std::optional<std::string> particle_problem(std::size_t i, const Particle<D>& p, double mass,
                                            const Box<D>& box);

// The message for particles i and j of `system` overlapping (R: the file's shared radius;
// `where_i`: where particle i comes from, as " on line 4").
template <std::size_t D>
std::string describe_overlap(const System<D>& system, std::size_t i, std::size_t j, double radius,
                             const std::string& where_i = "");

// Whether `name` can name a type: letters, digits, _ . + or -, at least one. Every file carom
// writes holds the names as they are (a classic start's types=A,B, an XYZ species column), so
// none may hold a space or a comma.
bool is_type_name(std::string_view name);

// Checks a system a program built (not read from a file) as the reader checks a file: every
// number, the box, each particle (particle_problem), its types (named by is_type_name, each name
// once, every particle's an index into them), then overlaps. Throws std::invalid_argument.
template <std::size_t D>
void check_start(const System<D>& system);

}  // namespace carom
