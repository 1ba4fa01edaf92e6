#include "carom/classic_input.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "carom/overlap.hpp"
#include "carom/physics.hpp"

namespace carom {

namespace {

// Lines longer than this are not a classic file; reading stops there instead of buffering a
// file of garbage whole.
constexpr std::size_t kMaxLineLength = 4096;
// Lengths and speeds are squared in predictions; beyond these magnitudes the squares overflow or
// underflow and contact times become meaningless.
constexpr double kLargest = 1e100;
constexpr double kSmallest = 1e-100;
// Particle indices are stored in 32 bits (see Event).
constexpr long long kMaxParticles = 0x7FFFFFF0;

std::string location(const std::string& file, std::size_t line) {
  return line == 0 ? file : fmt::format("{}:{}", file, line);
}

// A token as it may be shown in a message: short, printable.
std::string shown(std::string_view token) {
  std::string out;
  for (char ch : token.substr(0, 24))
    out += std::isprint(static_cast<unsigned char>(ch)) ? ch : '?';
  if (token.size() > 24) out += "...";
  return "'" + out + "'";
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> tokens;
  constexpr std::string_view kSpace = " \t\r\v\f";
  std::size_t at = line.find_first_not_of(kSpace);
  while (at != std::string_view::npos) {
    const std::size_t end = std::min(line.find_first_of(kSpace, at), line.size());
    tokens.push_back(line.substr(at, end - at));
    at = line.find_first_not_of(kSpace, end);
  }
  return tokens;
}

// Yields the lines that carry data, skipping blank and comment lines, with their numbers.
class DataLines {
 public:
  DataLines(std::istream& in, const std::string& name) : in_(in), name_(name) {}

  // The next data line's tokens, or false at the end of the input.
  bool next(std::vector<std::string_view>& tokens) {
    while (true) {
      in_.getline(buffer_, sizeof buffer_);
      if (in_.bad()) throw InputError(name_, number_ + 1, "read error");
      const auto extracted = static_cast<std::size_t>(in_.gcount());
      if (extracted == 0 && in_.eof()) return false;
      ++number_;
      if (in_.fail()) {  // filled the buffer without meeting the end of the line
        throw InputError(name_, number_,
                         fmt::format("line longer than {} characters: this is not a classic "
                                     "input file",
                                     kMaxLineLength - 1));
      }
      const std::size_t length = in_.eof() ? extracted : extracted - 1;
      if (std::strlen(buffer_) != length) {
        throw InputError(name_, number_, "contains a NUL byte: this is not a text file");
      }
      std::string_view text(buffer_, length);
      if (number_ == 1 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 BOM
      tokens = split(text);
      if (tokens.empty() || tokens.front().front() == '#') continue;
      return true;
    }
  }
  std::size_t number() const { return number_; }

 private:
  std::istream& in_;
  const std::string& name_;
  char buffer_[kMaxLineLength];
  std::size_t number_ = 0;
};

}  // namespace

InputError::InputError(const std::string& file, std::size_t line, const std::string& message)
    : std::runtime_error(location(file, line) + ": " + message), file_(file), line_(line) {}

double parse_finite_double(std::string_view token) {
  // from_chars takes no '+' sign; strtod, which users' files were written for, does.
  std::string_view digits = token;
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-' && digits[1] != '+') {
    digits.remove_prefix(1);
  }
  double value = 0.0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error == std::errc::result_out_of_range) {
    throw std::invalid_argument(
        fmt::format("{} is out of range: carom takes magnitudes from {} to {}", shown(token),
                    kSmallest, kLargest));
  }
  if (error != std::errc() || end != digits.data() + digits.size() || digits.empty()) {
    throw std::invalid_argument(shown(token) + " is not a number");
  }
  if (!std::isfinite(value)) throw std::invalid_argument(shown(token) + " is not a finite number");
  if (std::abs(value) > kLargest || (value != 0.0 && std::abs(value) < kSmallest)) {
    throw std::invalid_argument(
        fmt::format("{} is out of range: carom takes magnitudes from {} to {}", shown(token),
                    kSmallest, kLargest));
  }
  return value;
}

ClassicInput read_classic(std::istream& in, const std::string& name, Boundary boundary) {
  DataLines lines(in, name);
  std::vector<std::string_view> tokens;

  // Reads the next data line, which must hold `fewest` to `most` numbers described by `what`.
  const auto numbers = [&](std::size_t fewest, std::size_t most, const std::string& what) {
    if (!lines.next(tokens)) {
      throw InputError(name, lines.number(),
                       fmt::format("the file ends where {} was expected", what));
    }
    if (tokens.size() < fewest || tokens.size() > most) {
      const std::string expected =
          fewest == most ? fmt::format("{}", fewest) : fmt::format("{} to {}", fewest, most);
      throw InputError(name, lines.number(),
                       fmt::format("expected {} number{} ({}), found {}", expected,
                                   most == 1 ? "" : "s", what, tokens.size()));
    }
    std::vector<double> values;
    for (std::string_view token : tokens) {
      try {
        values.push_back(parse_finite_double(token));
      } catch (const std::invalid_argument& e) {
        throw InputError(name, lines.number(), fmt::format("{} (in {})", e.what(), what));
      }
    }
    return values;
  };

  if (!lines.next(tokens)) throw InputError(name, 0, "the file is empty (expected N on line 1)");
  if (tokens.size() != 1) {
    throw InputError(
        name, lines.number(),
        fmt::format("expected 1 number (the particle count N), found {}", tokens.size()));
  }
  long long count = 0;
  {
    const std::string_view token = tokens.front();
    const std::string_view digits = token.size() > 1 && token[0] == '+' ? token.substr(1) : token;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), count);
    if (error != std::errc() || end != digits.data() + digits.size()) {
      throw InputError(
          name, lines.number(),
          fmt::format("the particle count N must be a whole number, found {}", shown(token)));
    }
    if (count < 1) {
      throw InputError(name, lines.number(),
                       fmt::format("the particle count N must be at least 1, found {}", count));
    }
    if (count > kMaxParticles) {
      throw InputError(name, lines.number(),
                       fmt::format("the particle count N = {} is more than carom supports ({})",
                                   count, kMaxParticles));
    }
  }

  ClassicInput input;
  input.radius = numbers(1, 1, "the radius R").front();
  if (!(input.radius > 0.0)) {
    throw InputError(name, lines.number(),
                     fmt::format("the radius R must be greater than 0, found {}", input.radius));
  }
  const std::vector<double> box = numbers(2, 2, "the box size Lx Ly");
  if (!(box[0] > 0.0 && box[1] > 0.0)) {
    throw InputError(
        name, lines.number(),
        fmt::format("the box size must be positive, found Lx = {}, Ly = {}", box[0], box[1]));
  }
  input.system.box.size = {box[0], box[1]};
  input.system.box.boundary = boundary;
  const Box<2>& b = input.system.box;

  // Particles are added as their lines arrive, never reserved from the header's N, so a header
  // that promises more than the file holds costs no memory.
  for (long long i = 0; i < count; ++i) {
    const std::string what = fmt::format("x y vx vy [r [m]] of particle {}", i);
    const std::vector<double> v = numbers(4, 6, what);
    Particle<2> p;
    p.position = {v[0], v[1]};
    p.velocity = {v[2], v[3]};
    p.radius = v.size() > 4 ? v[4] : input.radius;
    const double mass = v.size() > 5 ? v[5] : 1.0;
    if (!(p.radius > 0.0)) {
      throw InputError(
          name, lines.number(),
          fmt::format("the radius of particle {} must be greater than 0, found {}", i, p.radius));
    }
    if (!(mass > 0.0)) {
      throw InputError(
          name, lines.number(),
          fmt::format("the mass of particle {} must be greater than 0, found {}", i, mass));
    }
    for (std::size_t k = 0; k < 2; ++k) {
      if (p.position[k] < 0.0 || p.position[k] > b.size[k]) {
        throw InputError(name, lines.number(),
                         fmt::format("particle {} at ({}, {}) is outside the box [0, {}] x [0, {}]",
                                     i, v[0], v[1], b.size[0], b.size[1]));
      }
      // In a periodic box a particle must not reach its own image or two images of another.
      if (b.periodic() && !(b.size[k] > 4.0 * p.radius)) {
        throw InputError(
            name, lines.number(),
            fmt::format("particle {} with radius {} is too large for the periodic box: "
                        "each side must exceed two diameters ({})",
                        i, p.radius, 4.0 * p.radius));
      }
    }
    for (int label = -1; label >= -4 && !b.periodic(); --label) {
      if (overlaps_wall(p, b, label)) {
        throw InputError(name, lines.number(),
                         fmt::format("particle {} at ({}, {}) with radius {} overlaps the {} wall "
                                     "(its centre must be at least R from every wall)",
                                     i, v[0], v[1], p.radius, wall_name(label)));
      }
    }
    input.system.add(p, mass);
    input.line_of.push_back(lines.number());
  }
  if (lines.next(tokens)) {
    throw InputError(
        name, lines.number(),
        fmt::format("unexpected data after the {} particle lines that N announced", count));
  }
  if (const auto overlap = find_pair_overlap(input.system, 0.0)) {
    const auto [i, j] = *overlap;
    const auto& pi = input.system.particles[i];
    const auto& pj = input.system.particles[j];
    throw InputError(
        name, input.line_of[j],
        fmt::format("particle {} at ({}, {}) overlaps particle {} at ({}, {}) on line {}: their "
                    "centres are {} apart, less than {}",
                    j, pj.position[0], pj.position[1], i, pi.position[0], pi.position[1],
                    input.line_of[i], std::sqrt(norm2(separation(pi, pj, input.system.box))),
                    pi.radius == input.radius && pj.radius == input.radius
                        ? fmt::format("2R = {}", 2.0 * input.radius)
                        : fmt::format("the sum of their radii, {}", pi.radius + pj.radius)));
  }
  return input;
}

std::ifstream open_input(const std::string& path) {
  if (std::filesystem::is_directory(path)) throw InputError(path, 0, "is a directory, not a file");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path, 0, fmt::format("cannot open: {}", std::strerror(errno)));
  return file;
}

ClassicInput read_classic_file(const std::string& path, Boundary boundary) {
  if (path == "-") return read_classic(std::cin, "<stdin>", boundary);
  std::ifstream file = open_input(path);
  return read_classic(file, path, boundary);
}

}  // namespace carom
