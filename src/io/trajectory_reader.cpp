#include "carom/io/trajectory_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>

#include "carom/io/input_error.hpp"
#include "carom/io/trajectory_kind.hpp"

namespace carom {

namespace {

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// The key=value pairs of an extended XYZ comment line; values may be "quoted with spaces".
std::map<std::string, std::string> comment_fields(const std::string& line) {
  std::map<std::string, std::string> fields;
  std::size_t at = 0;
  while (at < line.size()) {
    while (at < line.size() && std::isspace(static_cast<unsigned char>(line[at]))) ++at;
    const std::size_t equals = line.find('=', at);
    if (equals == std::string::npos) break;
    const std::string key = line.substr(at, equals - at);
    std::size_t end = 0;
    std::string value;
    if (equals + 1 < line.size() && line[equals + 1] == '"') {
      end = line.find('"', equals + 2);
      if (end == std::string::npos) end = line.size();
      value = line.substr(equals + 2, end - equals - 2);
      ++end;
    } else {
      end = line.find_first_of(" \t", equals + 1);
      if (end == std::string::npos) end = line.size();
      value = line.substr(equals + 1, end - equals - 1);
    }
    fields[key] = value;
    at = end;
  }
  return fields;
}

}  // namespace

namespace {

// Lines longer than this are not a trajectory's: reading stops there instead of buffering them.
constexpr std::size_t kMaxLineLength = 1 << 16;
// Property widths beyond this are not a trajectory carom can show (pos and velo have 2 or 3).
constexpr long long kMaxWidth = 1000;

// A whole number as a property width or a particle count: digits only, within [lo, hi].
std::optional<long long> whole(const std::string& token, long long lo, long long hi) {
  long long n = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), n);
  if (error != std::errc() || end != token.data() + token.size() || n < lo || n > hi) {
    return std::nullopt;
  }
  return n;
}

// A property of the Properties= spec: its first column, type letter and width.
struct Property {
  std::size_t first = 0;
  char type = 'R';
  std::size_t width = 0;
};

}  // namespace

std::vector<Frame> read_xyz_frames(std::istream& in, const std::string& name) {
  std::vector<Frame> frames;
  std::vector<bool>
      z_periodic_of_frame;  // each frame's pbc along z, checked once the dimension is known
  std::string line;
  std::vector<char> buffer(kMaxLineLength);
  std::size_t number = 0;
  bool spheres = false;  // a nonzero z seen anywhere
  const auto fail = [&](const std::string& what) { throw InputError(name, number, what); };
  // The next line (without its CR), or false at the end of the input.
  const auto read_line = [&]() {
    in.getline(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (in.bad()) throw InputError(name, number + 1, "read error");
    const auto extracted = static_cast<std::size_t>(in.gcount());
    if (extracted == 0 && in.eof()) return false;
    ++number;
    if (in.fail()) fail(fmt::format("line longer than {} characters", kMaxLineLength - 1));
    const std::size_t length = in.eof() ? extracted : extracted - 1;
    if (std::strlen(buffer.data()) != length) fail("contains a NUL byte: this is not a text file");
    line.assign(buffer.data(), length);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  const auto next = [&](const char* what) {
    if (!read_line()) {
      throw InputError(name, number, fmt::format("the file ends where {} was expected", what));
    }
  };
  const auto value = [&](const std::string& token, const std::string& what) {
    try {
      return parse_finite_double(token);
    } catch (const std::invalid_argument& e) {
      throw InputError(name, number, fmt::format("{} (in {})", e.what(), what));
    }
  };
  while (read_line()) {
    const std::vector<std::string> count = words(line);
    if (count.empty()) continue;
    const std::optional<long long> n =
        count.size() == 1 ? whole(count[0], 1, 100'000'000) : std::nullopt;
    if (!n) fail("expected the number of particles of a frame (extended XYZ), from 1 to 10^8");
    if (!frames.empty() && static_cast<std::size_t>(*n) != frames.front().radius.size()) {
      fail(fmt::format("the number of particles changes between frames ({}, then {})",
                       frames.front().radius.size(), *n));
    }
    next("the frame's comment line");
    const auto fields = comment_fields(line);
    Frame f;
    const auto lattice = fields.find("Lattice");
    if (lattice == fields.end() || words(lattice->second).size() != 9) {
      fail("no Lattice=\"Lx 0 0 0 Ly 0 0 0 Lz\" box on the comment line");
    }
    const auto box = words(lattice->second);
    for (std::size_t k = 0; k < 9; ++k) {
      const double x = value(box[k], "the Lattice");
      if (k % 4 == 0) {
        if (!(x > 0.0) && !(k == 8 && x == 0.0)) {
          fail(fmt::format("the Lattice's box sides must be greater than 0, found {}", x));
        }
        f.box[k / 4] = x;
      } else if (k == 3) {
        f.shear_shift = x;  // a sheared run's images one box up: (shift, Ly, 0)
      } else if (x != 0.0) {
        fail(
            "the Lattice must be a rectangular box (Lx 0 0 0 Ly 0 0 0 Lz) or a sheared one "
            "(Lx 0 0 shift Ly 0 0 0 Lz)");
      }
    }
    // pbc="T T F" (periodic disks: carom writes z F) or all alike; a slab periodic in some
    // directions only is not a box carom knows.
    bool z_periodic = false;
    if (const auto pbc = fields.find("pbc"); pbc != fields.end()) {
      const std::vector<std::string> flags = words(pbc->second);
      const auto is_true = [](const std::string& flag) {
        return !flag.empty() && (flag[0] == 'T' || flag[0] == 't');
      };
      if (flags.size() != 3 || is_true(flags[0]) != is_true(flags[1])) {
        fail(
            fmt::format("pbc=\"{}\": carom's boxes are periodic along x and y alike "
                        "(pbc=\"T T T\", \"T T F\" or \"F F F\")",
                        pbc->second));
      }
      f.periodic = is_true(flags[0]);
      z_periodic = is_true(flags[2]);
    }
    if (f.shear_shift != 0.0 && !f.periodic) {
      fail("the Lattice is tilted (a sheared box) but the box is not periodic (pbc)");
    }
    // Without a Time, frames count in whole units, as GSD's steps do.
    f.time = static_cast<double>(frames.size());
    if (const auto time = fields.find("Time"); time != fields.end()) {
      f.time = value(time->second, "Time");
    }
    // First column, type and width of each property, from Properties=name:type:width:...
    std::map<std::string, Property> column;
    std::size_t columns = 0;
    {
      const auto properties = fields.find("Properties");
      const std::string spec =
          properties == fields.end() ? "species:S:1:pos:R:3" : properties->second;
      std::vector<std::string> parts;
      std::stringstream split(spec);
      for (std::string part; std::getline(split, part, ':');) parts.push_back(part);
      if (!spec.empty() && spec.back() == ':') parts.emplace_back();
      if (parts.empty() || parts.size() % 3 != 0) {
        fail(fmt::format("Properties={} is not a list of name:type:width", spec));
      }
      for (std::size_t i = 0; i < parts.size(); i += 3) {
        const std::string& key = parts[i];
        const std::string& type = parts[i + 1];
        if (key.empty() || column.count(key)) {
          fail(fmt::format("Properties names '{}' {}", key, key.empty() ? "(empty)" : "twice"));
        }
        if (type.size() != 1 || std::string_view("SRILsril").find(type[0]) == std::string::npos) {
          fail(fmt::format("property {} has type '{}' (expected S, R, I or L)", key, type));
        }
        const std::optional<long long> width = whole(parts[i + 2], 1, kMaxWidth);
        if (!width) {
          fail(fmt::format("property {} has width '{}' (expected a whole number from 1 to {})", key,
                           parts[i + 2], kMaxWidth));
        }
        column[key] = {columns, static_cast<char>(std::toupper(type[0])),
                       static_cast<std::size_t>(*width)};
        columns += static_cast<std::size_t>(*width);
      }
    }
    // What carom reads, with the widths and types it can use.
    const auto expect = [&](const char* key, bool required, std::size_t fewest, std::size_t most) {
      const auto c = column.find(key);
      if (c == column.end()) {
        if (required) fail(fmt::format("no {} property", key));
        return;
      }
      if (c->second.type != 'R' && c->second.type != 'I') {
        fail(fmt::format("property {} must be numbers (type R or I)", key));
      }
      if (c->second.width < fewest || c->second.width > most) {
        fail(fmt::format(
            "property {} has width {} (expected {})", key, c->second.width,
            fewest == most ? fmt::format("{}", fewest) : fmt::format("{} to {}", fewest, most)));
      }
    };
    expect("pos", true, 2, 3);
    expect("velo", false, 2, 3);
    expect("radius", false, 1, 1);
    expect("collisions", false, 1, 1);
    expect("image", false, 2, 3);
    const bool has_image = column.count("image") != 0;
    // The types: carom's type column (names) for a mixture, else the species column's symbols
    // (one symbol throughout, as a one-type file's H: no types).
    const auto type_column = column.find("type");
    const auto species_column = column.find("species");
    const auto types_from =
        type_column != column.end() && type_column->second.type == 'S'         ? type_column
        : species_column != column.end() && species_column->second.type == 'S' ? species_column
                                                                               : column.end();
    std::vector<std::string> names;
    std::vector<std::uint32_t> types;
    // carom names a mixture's types in their order on the comment line: types=A,B.
    if (const auto listed = fields.find("types");
        listed != fields.end() && types_from == type_column) {
      std::stringstream split(listed->second);
      for (std::string name; std::getline(split, name, ',');) {
        if (!name.empty() && std::find(names.begin(), names.end(), name) == names.end()) {
          names.push_back(name);
        }
      }
    }
    for (long long i = 0; i < *n; ++i) {
      next("a particle line");
      const std::vector<std::string> w = words(line);
      if (w.size() != columns) {
        fail(fmt::format("expected {} columns, found {}", columns, w.size()));
      }
      // Component k of a property, or `otherwise` if the property has no such component.
      const auto at = [&](const char* property, std::size_t k, double otherwise) {
        const auto c = column.find(property);
        if (c == column.end() || k >= c->second.width) return otherwise;
        const std::size_t index = c->second.first + k;
        if (index >= w.size()) fail("a property reaches past the end of the line");
        return value(w[index], property);
      };
      f.position.push_back({{at("pos", 0, 0), at("pos", 1, 0), at("pos", 2, 0)}});
      f.velocity.push_back({{at("velo", 0, 0), at("velo", 1, 0), at("velo", 2, 0)}});
      if (f.position.back()[2] != 0.0 || f.velocity.back()[2] != 0.0) spheres = true;
      const double radius = at("radius", 0, 0.5);
      if (!(radius > 0.0)) fail(fmt::format("the radius must be greater than 0, found {}", radius));
      f.radius.push_back(radius);
      const double collisions = at("collisions", 0, 0);
      if (!(collisions >= 0.0) || collisions != std::floor(collisions)) {
        fail(fmt::format("the collision count must be a whole number >= 0, found {}", collisions));
      }
      // More than 2^32 - 1 (a very long run) is shown as the most the page holds.
      f.collisions.push_back(static_cast<std::uint32_t>(std::min(collisions, 4294967295.0)));
      if (has_image) {
        std::array<std::int32_t, 3> flags{};
        for (std::size_t k = 0; k < 3; ++k) {
          const double flag = at("image", k, 0);
          if (!(std::abs(flag) <= 2147483647.0) || flag != std::floor(flag)) {
            fail(fmt::format("an image flag must be a whole number of 32 bits, found {}", flag));
          }
          flags[k] = static_cast<std::int32_t>(flag);
        }
        f.image.push_back(flags);
      }
      if (types_from != column.end()) {
        const std::string& name_of_type = w[types_from->second.first];
        const auto found = std::find(names.begin(), names.end(), name_of_type);
        types.push_back(static_cast<std::uint32_t>(found - names.begin()));
        if (found == names.end()) names.push_back(name_of_type);
      }
    }
    if (names.size() > 1 || (types_from == type_column && !names.empty())) {
      f.type_names = std::move(names);
      f.type = std::move(types);
    }
    z_periodic_of_frame.push_back(z_periodic);
    frames.push_back(std::move(f));
  }
  if (frames.empty()) throw InputError(name, number, "no frames");
  for (std::size_t k = 0; k < frames.size(); ++k) {
    Frame& f = frames[k];
    f.dimension = spheres ? 3 : 2;
    if (spheres && !(f.box[2] > 0.0)) {
      throw InputError(name, 0, "the file holds spheres, but a frame's Lattice has Lz = 0");
    }
    if (spheres && z_periodic_of_frame[k] != f.periodic) {
      throw InputError(name, 0,
                       fmt::format("frame {} holds spheres in a box periodic along some axes only "
                                   "(pbc): carom's boxes are periodic along all three or none",
                                   k));
    }
  }
  return frames;
}

std::vector<Frame> read_trajectory_frames(const std::string& path,
                                          const FrameSelection& selection) {
  const std::optional<TrajectoryKind> kind = trajectory_kind_of(path);
  if (kind == TrajectoryKind::gsd) return read_gsd_frames(path, selection);
  if (kind == TrajectoryKind::lammpstrj) {
    throw InputError(path, 0,
                     "carom reads .gsd and .xyz trajectories back, not LAMMPS dumps: dump the run "
                     "to FILE.gsd or FILE.xyz");
  }
  std::ifstream in = open_input(path);
  std::vector<Frame> all = read_xyz_frames(in, path);
  std::vector<Frame> kept;
  const std::size_t last = std::min(selection.last.value_or(all.size()), all.size());
  for (std::size_t f = selection.first; f < last; f += selection.stride) {
    kept.push_back(std::move(all[f]));
  }
  return kept;
}

}  // namespace carom
