#include "carom/io/classic_input.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <variant>

#include "carom/core/physics.hpp"
#include "carom/engine/overlap.hpp"
#include "carom/io/input_error.hpp"

namespace carom {

namespace {

// Lines longer than this are not a classic file; reading stops there instead of buffering a
// file of garbage whole.
constexpr std::size_t kMaxLineLength = 4096;
constexpr double kLargest = kLargestMagnitude;
constexpr double kSmallest = kSmallestMagnitude;
// Particle indices are stored in 32 bits (see Event).
constexpr long long kMaxParticles = 0x7FFFFFF0;

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

// One `key=value` of a record line, stored into `slot` once.
template <class E>
void set_once(std::optional<E>& slot, std::string_view key, std::string_view value) {
  if (slot) throw std::invalid_argument(fmt::format("{} is given twice", key));
  slot = from_name<E>(value);
  if (!slot) {
    throw std::invalid_argument(
        fmt::format("{} is not a {}: {} are", quoted_token(value), key, names_list<E>()));
  }
}

// The settings of a `# carom:` line, tokens after the marker.
StartRecord parse_record(const std::vector<std::string_view>& settings) {
  StartRecord record;
  for (const std::string_view setting : settings) {
    const std::size_t equals = setting.find('=');
    const std::string_view key = setting.substr(0, equals);
    const std::string_view value =
        equals == std::string_view::npos ? std::string_view() : setting.substr(equals + 1);
    if (key == "boundary") {
      set_once(record.boundary, key, value);
    } else if (key == "rule") {
      set_once(record.rule, key, value);
    } else if (key == "types") {
      if (!record.types.empty()) throw std::invalid_argument("types is given twice");
      std::size_t at = 0;
      while (true) {
        const std::size_t comma = std::min(value.find(',', at), value.size());
        const std::string name(value.substr(at, comma - at));
        if (name.empty()) {
          throw std::invalid_argument(
              fmt::format("{} has an empty type name", quoted_token(setting)));
        }
        if (std::find(record.types.begin(), record.types.end(), name) != record.types.end()) {
          throw std::invalid_argument(fmt::format("the type {} is named twice", name));
        }
        record.types.push_back(name);
        if (comma == value.size()) break;
        at = comma + 1;
      }
    } else {
      throw std::invalid_argument(
          fmt::format("{} is not a setting carom records (boundary=..., rule=..., types=...)",
                      quoted_token(setting)));
    }
  }
  return record;
}

// Yields the lines that carry data, skipping blank and comment lines, with their numbers; a
// `# carom:` comment before the data is the file's StartRecord.
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
      if (tokens.size() >= 2 && tokens[0] == "#" && tokens[1] == "carom:") {
        read_record({tokens.begin() + 2, tokens.end()});
        continue;
      }
      if (tokens.empty() || tokens.front().front() == '#') continue;
      data_begun_ = true;
      return true;
    }
  }
  std::size_t number() const { return number_; }
  const StartRecord& record() const { return record_; }

 private:
  void read_record(const std::vector<std::string_view>& settings) {
    if (data_begun_) {
      throw InputError(name_, number_, "a '# carom:' line must come before the data");
    }
    if (record_line_ != 0) {
      throw InputError(
          name_, number_,
          fmt::format("a second '# carom:' line (the first is line {})", record_line_));
    }
    record_line_ = number_;
    try {
      record_ = parse_record(settings);
    } catch (const std::invalid_argument& e) {
      throw InputError(name_, number_, e.what());
    }
  }

  std::istream& in_;
  const std::string& name_;
  char buffer_[kMaxLineLength];
  std::size_t number_ = 0;
  bool data_begun_ = false;
  std::size_t record_line_ = 0;
  StartRecord record_;
};

}  // namespace

namespace {

// The data lines of one file, read as numbers with messages that name the file and the line.
class Reader {
 public:
  Reader(std::istream& in, const std::string& name) : lines_(in, name), name_(name) {}

  // The next data line, which must hold `fewest` to `most` numbers described by `what`.
  std::vector<double> numbers(std::size_t fewest, std::size_t most, const std::string& what,
                              const std::string& expected_text = "") {
    if (!lines_.next(tokens_)) {
      throw InputError(name_, lines_.number(),
                       fmt::format("the file ends where {} was expected", what));
    }
    if (tokens_.size() < fewest || tokens_.size() > most) {
      const std::string expected = !expected_text.empty() ? expected_text
                                   : fewest == most
                                       ? fmt::format("{} number{}", fewest, most == 1 ? "" : "s")
                                       : fmt::format("{} to {} numbers", fewest, most);
      throw InputError(name_, lines_.number(),
                       fmt::format("expected {} ({}), found {}", expected, what, tokens_.size()));
    }
    std::vector<double> values;
    for (std::string_view token : tokens_) {
      try {
        values.push_back(parse_finite_double(token));
      } catch (const std::invalid_argument& e) {
        throw InputError(name_, lines_.number(), fmt::format("{} (in {})", e.what(), what));
      }
    }
    return values;
  }

  // The particle count N on the first data line.
  long long count() {
    if (!lines_.next(tokens_)) {
      throw InputError(name_, 0, "the file is empty (expected N on line 1)");
    }
    if (tokens_.size() >= 2 && tokens_[0] == "particle" && tokens_[1] == "id:") {
      // A result table names no box and no radius, so it cannot start a run.
      throw InputError(name_, lines_.number(),
                       "this is a run's result table (`carom run -o`), not a start; write the "
                       "state a run ends in with `--final FILE` and start from that");
    }
    if (tokens_.size() != 1) {
      throw InputError(
          name_, lines_.number(),
          fmt::format("expected 1 number (the particle count N), found {}", tokens_.size()));
    }
    long long count = 0;
    const std::string_view token = tokens_.front();
    const std::string_view digits = token.size() > 1 && token[0] == '+' ? token.substr(1) : token;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), count);
    if (error != std::errc() || end != digits.data() + digits.size()) {
      throw InputError(name_, lines_.number(),
                       fmt::format("the particle count N must be a whole number, found {}",
                                   quoted_token(token)));
    }
    if (count < 1) {
      throw InputError(name_, lines_.number(),
                       fmt::format("the particle count N must be at least 1, found {}", count));
    }
    if (count > kMaxParticles) {
      throw InputError(name_, lines_.number(),
                       fmt::format("the particle count N = {} is more than carom supports ({})",
                                   count, kMaxParticles));
    }
    return count;
  }

  // Anything after the particles is an error.
  void expect_end(long long count) {
    if (lines_.next(tokens_)) {
      throw InputError(
          name_, lines_.number(),
          fmt::format("unexpected data after the {} particle lines that N announced", count));
    }
  }

  std::size_t line() const { return lines_.number(); }
  const std::string& name() const { return name_; }
  const StartRecord& record() const { return lines_.record(); }

 private:
  DataLines lines_;
  const std::string& name_;
  std::vector<std::string_view> tokens_;
};

// What to add to a particle's problem in a box with walls when it would be no problem in a
// periodic box: the file is likely meant for one.
template <std::size_t D>
std::string periodic_hint(const Particle<D>& p, double mass, const Box<D>& b) {
  if (b.periodic()) return "";
  Box<D> periodic = b;
  periodic.boundary = Boundary::periodic;
  if (particle_problem(0, p, mass, periodic)) return "";
  return "; if the file is for a periodic box, run it with --boundary periodic "
         "(boundary=\"periodic\" in Python)";
}

// The particle lines of a file whose header said N = `count`, R = `radius` and the box.
template <std::size_t D>
ClassicInput<D> read_particles(Reader& reader, long long count, double radius, const Box<D>& b) {
  const std::string& name = reader.name();
  ClassicInput<D> input;
  input.record = reader.record();
  input.radius = radius;
  input.system.box = b;
  const bool typed = !input.record.types.empty();
  if (typed) input.system.type_names = input.record.types;
  const char* columns = typed    ? (D == 3 ? "x y z vx vy vz r m type" : "x y vx vy r m type")
                        : D == 3 ? "x y z vx vy vz [r [m]]"
                                 : "x y vx vy [r [m]]";
  // Particles are added as their lines arrive, never reserved from the header's N, so a header
  // that promises more than the file holds costs no memory.
  for (long long i = 0; i < count; ++i) {
    const std::vector<double> v =
        reader.numbers(typed ? 2 * D + 3 : 2 * D, typed ? 2 * D + 3 : 2 * D + 2,
                       fmt::format("{} of particle {}", columns, i));
    std::uint32_t type = 0;
    if (typed) {
      const double t = v[2 * D + 2];
      if (!(t >= 0.0 && t < static_cast<double>(input.record.types.size()) && t == std::floor(t))) {
        throw InputError(
            name, reader.line(),
            fmt::format("the type {} of particle {} is not the index of one of the "
                        "{} types the record line names (0 to {})",
                        t, i, input.record.types.size(), input.record.types.size() - 1));
      }
      type = static_cast<std::uint32_t>(t);
    }
    Particle<D> p;
    for (std::size_t k = 0; k < D; ++k) {
      p.position[k] = v[k];
      p.velocity[k] = v[D + k];
    }
    p.radius = v.size() > 2 * D ? v[2 * D] : radius;
    const double mass = v.size() > 2 * D + 1 ? v[2 * D + 1] : 1.0;
    if (const auto problem = particle_problem(i, p, mass, b)) {
      throw InputError(name, reader.line(), *problem + periodic_hint(p, mass, b));
    }
    input.system.add(p, mass);
    input.system.records.back().type = type;
    input.line_of.push_back(reader.line());
  }
  reader.expect_end(count);
  if (const auto overlap = find_pair_overlap(input.system, 0.0)) {
    const auto [i, j] = *overlap;
    throw InputError(
        name, input.line_of[j],
        describe_overlap(input.system, i, j, radius, fmt::format(" on line {}", input.line_of[i])));
  }
  // Grown line by line, the arrays hold up to twice what they need: a run keeps them throughout.
  input.system.particles.shrink_to_fit();
  input.system.records.shrink_to_fit();
  return input;
}

}  // namespace

std::string start_record_line(Boundary boundary, Rule rule, const std::vector<std::string>& types) {
  std::string line = fmt::format("# carom: boundary={} rule={}", name_of(boundary), name_of(rule));
  if (!types.empty()) line += fmt::format(" types={}", fmt::join(types, ","));
  return line;
}

Rule default_rule(const StartRecord& record, Boundary boundary, double restitution) {
  if (restitution < 1.0) return Rule::elastic;
  if (record.rule) return *record.rule;
  return boundary == Boundary::periodic ? Rule::elastic : Rule::swap;
}

AnyClassicInput read_any_classic(std::istream& in, const std::string& name,
                                 std::optional<Boundary> asked) {
  Reader reader(in, name);
  const long long count = reader.count();
  const double radius = reader.numbers(1, 1, "the radius R").front();
  if (!(radius > 0.0)) {
    throw InputError(name, reader.line(),
                     fmt::format("the radius R must be greater than 0, found {}", radius));
  }
  // Two sides make disks, three spheres.
  const std::vector<double> sides =
      reader.numbers(2, 3, "the box size: Lx Ly for disks, Lx Ly Lz for spheres", "2 or 3 numbers");
  for (const double side : sides) {
    if (!(side > 0.0)) {
      throw InputError(
          name, reader.line(),
          fmt::format("the box size must be positive, found {}", fmt::join(sides, " x ")));
    }
  }
  // The record is complete here: the data has begun.
  const Boundary boundary = asked.value_or(reader.record().boundary.value_or(Boundary::walls));
  if (sides.size() == 3) {
    return read_particles<3>(reader, count, radius, {{{sides[0], sides[1], sides[2]}}, boundary});
  }
  return read_particles<2>(reader, count, radius, {{{sides[0], sides[1]}}, boundary});
}

template <std::size_t D>
ClassicInput<D> read_classic(std::istream& in, const std::string& name,
                             std::optional<Boundary> boundary) {
  AnyClassicInput input = read_any_classic(in, name, boundary);
  if (auto* wanted = std::get_if<ClassicInput<D>>(&input)) return std::move(*wanted);
  throw InputError(
      name, 0,
      fmt::format("holds {} (its line 3 has {} box sides); {} were expected",
                  D == 2 ? "spheres" : "disks", D == 2 ? 3 : 2, D == 2 ? "disks" : "spheres"));
}

AnyClassicInput read_any_classic_file(const std::string& path, std::optional<Boundary> boundary) {
  if (path == "-") return read_any_classic(std::cin, "<stdin>", boundary);
  std::ifstream file = open_input(path);
  return read_any_classic(file, path, boundary);
}

template <std::size_t D>
ClassicInput<D> read_classic_file(const std::string& path, std::optional<Boundary> boundary) {
  if (path == "-") return read_classic<D>(std::cin, "<stdin>", boundary);
  std::ifstream file = open_input(path);
  return read_classic<D>(file, path, boundary);
}

template ClassicInput<2> read_classic(std::istream&, const std::string&, std::optional<Boundary>);
template ClassicInput<3> read_classic(std::istream&, const std::string&, std::optional<Boundary>);
template ClassicInput<2> read_classic_file(const std::string&, std::optional<Boundary>);
template ClassicInput<3> read_classic_file(const std::string&, std::optional<Boundary>);

}  // namespace carom
