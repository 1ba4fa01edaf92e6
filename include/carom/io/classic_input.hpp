// The classic input format the classic assignment and its users' files use: whitespace-separated
// numbers, line 1 `N`, line 2 the radius `R`, line 3 `Lx Ly`, then N lines `x y vx vy`. A particle
// line may carry a radius and a mass of its own: `x y vx vy [r [m]]` (default R and 1). Three
// numbers on line 3, `Lx Ly Lz`, make a system of spheres, with lines `x y z vx vy vz [r [m]]`.
#pragma once

#include <cstddef>
#include <fstream>
#include <istream>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "carom/core/physics.hpp"
#include "carom/core/system.hpp"
#include "carom/engine/validation.hpp"
#include "carom/io/input_error.hpp"

namespace carom {

// How a start file is meant to be run. carom records it in a comment line before the data,
// `# carom: boundary=periodic rule=elastic`, which other readers of the classic format skip; a
// plain classic file records nothing, and the classic assignment's box and rule apply.
struct StartRecord {
  std::optional<Boundary> boundary;
  std::optional<Rule> rule;
  // types=A,B: the names of a mixture's species; each particle line then ends with r, m and its
  // type's index (x y vx vy r m t). Empty: one species, "A".
  std::vector<std::string> types;
};

// The record's line, as carom writes it before a start's data (no newline); `types` only for a
// mixture (has_types).
std::string start_record_line(Boundary boundary, Rule rule,
                              const std::vector<std::string>& types = {});

// The rule a run of a start takes when none is asked for: elastic when collisions lose energy
// (a restitution below 1, which only it has), else the one its file records, else the classic
// assignment's swap in a box with walls and elastic (the physical rule) in a periodic box, which
// the classic assignment never had.
Rule default_rule(const StartRecord& record, Boundary boundary, double restitution = 1.0);

template <std::size_t D>
struct ClassicInput {
  System<D> system;
  double radius = 0.0;               // the file's R, shared by every particle
  std::vector<std::size_t> line_of;  // the line each particle was read from
  StartRecord record;                // what the file says about how to run it
};

// A file of disks or of spheres: which, its line 3 says.
using AnyClassicInput = std::variant<ClassicInput<2>, ClassicInput<3>>;

// Reads and validates a classic file: CRLF or LF line endings, tabs and repeated spaces, numbers
// such as `-.02`, `+1` or `1e-3`, blank lines and `#` comment lines, and no final newline are all
// accepted. Two box sides on line 3 make disks (particle lines `x y vx vy [r [m]]`), three make
// spheres (`x y z vx vy vz [r [m]]`). Anything else (wrong counts, non-numbers, NaN or infinity,
// N < 1, R <= 0, a box that is not positive, a particle outside the box or overlapping a wall or
// another particle beyond round-off) throws InputError naming `name` and the line. Touching is
// allowed. Every particle starts at t = 0. In a periodic box walls do not count, overlaps are
// measured through the nearest image, and each side must exceed two diameters. The box's
// boundary is `boundary` when given, else the one the file records (StartRecord), else walls; a
// `# carom:` line that is malformed, or comes after the data has begun, is an InputError.
AnyClassicInput read_any_classic(std::istream& in, const std::string& name,
                                 std::optional<Boundary> boundary = std::nullopt);

// As above for a program that takes one dimension only: a file of the other is an InputError.
template <std::size_t D>
ClassicInput<D> read_classic(std::istream& in, const std::string& name,
                             std::optional<Boundary> boundary = std::nullopt);

// As above from a file; "-" reads standard input.
AnyClassicInput read_any_classic_file(const std::string& path,
                                      std::optional<Boundary> boundary = std::nullopt);
template <std::size_t D>
ClassicInput<D> read_classic_file(const std::string& path,
                                  std::optional<Boundary> boundary = std::nullopt);

}  // namespace carom
