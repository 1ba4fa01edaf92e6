#include "carom/viewer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "carom/classic_input.hpp"
#include "carom/viewer_html.hpp"

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

std::string base64(const void* data, std::size_t size) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const unsigned v =
        bytes[i] << 16 | (i + 1 < size ? bytes[i + 1] << 8 : 0) | (i + 2 < size ? bytes[i + 2] : 0);
    out += kDigits[v >> 18 & 63];
    out += kDigits[v >> 12 & 63];
    out += i + 1 < size ? kDigits[v >> 6 & 63] : '=';
    out += i + 2 < size ? kDigits[v & 63] : '=';
  }
  return out;
}

}  // namespace

std::vector<Frame> read_xyz_frames(std::istream& in, const std::string& name) {
  std::vector<Frame> frames;
  std::string line;
  std::size_t number = 0;
  bool spheres = false;  // a nonzero z seen anywhere
  const auto next = [&](const char* what) {
    if (!std::getline(in, line)) {
      throw InputError(name, number, fmt::format("the file ends where {} was expected", what));
    }
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
  };
  const auto value = [&](const std::string& token) {
    try {
      return parse_finite_double(token);
    } catch (const std::invalid_argument& e) {
      throw InputError(name, number, e.what());
    }
  };
  while (true) {
    if (!std::getline(in, line)) break;
    ++number;
    if (words(line).empty()) continue;
    const std::vector<std::string> count = words(line);
    long long n = 0;
    const auto [end, error] =
        std::from_chars(count[0].data(), count[0].data() + count[0].size(), n);
    if (count.size() != 1 || error != std::errc() || end != count[0].data() + count[0].size() ||
        n < 1 || n > 100'000'000) {
      throw InputError(name, number, "expected the number of disks of a frame (extended XYZ)");
    }
    if (!frames.empty() && static_cast<std::size_t>(n) != frames.front().radius.size()) {
      throw InputError(name, number, "the number of disks changes between frames");
    }
    next("the frame's comment line");
    const auto fields = comment_fields(line);
    Frame f;
    const auto lattice = fields.find("Lattice");
    if (lattice == fields.end() || words(lattice->second).size() != 9) {
      throw InputError(name, number, "no Lattice=\"Lx 0 0 0 Ly 0 0 0 Lz\" box on the comment line");
    }
    const auto box = words(lattice->second);
    f.box = {{value(box[0]), value(box[4]), value(box[8])}};
    if (const auto pbc = fields.find("pbc"); pbc != fields.end())
      f.periodic = pbc->second[0] == 'T';
    if (const auto time = fields.find("Time"); time != fields.end()) f.time = value(time->second);
    // First column and column count of each property, from Properties=name:type:count:...
    std::map<std::string, std::pair<std::size_t, std::size_t>> column;
    std::size_t columns = 0;
    {
      const auto properties = fields.find("Properties");
      const std::string spec =
          properties == fields.end() ? "species:S:1:pos:R:3" : properties->second;
      std::vector<std::string> parts;
      std::stringstream split(spec);
      for (std::string part; std::getline(split, part, ':');) parts.push_back(part);
      for (std::size_t i = 0; i + 2 < parts.size(); i += 3) {
        const auto count = static_cast<std::size_t>(std::max(0.0, value(parts[i + 2])));
        column[parts[i]] = {columns, count};
        columns += count;
      }
    }
    if (!column.count("pos")) throw InputError(name, number, "no pos property");
    for (long long i = 0; i < n; ++i) {
      next("a disk line");
      const std::vector<std::string> w = words(line);
      if (w.size() != columns) {
        throw InputError(name, number,
                         fmt::format("expected {} columns, found {}", columns, w.size()));
      }
      const auto at = [&](const char* property, std::size_t k, double otherwise) {
        const auto c = column.find(property);
        return c == column.end() || k >= c->second.second ? otherwise
                                                          : value(w[c->second.first + k]);
      };
      f.position.push_back({{at("pos", 0, 0), at("pos", 1, 0), at("pos", 2, 0)}});
      f.velocity.push_back({{at("velo", 0, 0), at("velo", 1, 0), at("velo", 2, 0)}});
      if (f.position.back()[2] != 0.0 || f.velocity.back()[2] != 0.0) spheres = true;
      f.radius.push_back(at("radius", 0, 0.5));
      f.collisions.push_back(static_cast<std::uint32_t>(std::max(0.0, at("collisions", 0, 0))));
    }
    frames.push_back(std::move(f));
  }
  if (frames.empty()) throw InputError(name, number, "no frames");
  for (Frame& f : frames) f.dimension = spheres ? 3 : 2;
  return frames;
}

void write_viewer_html(std::ostream& out, const std::vector<Frame>& frames) {
  const Frame& first = frames.front();
  const std::size_t n = first.radius.size();
  const auto d = static_cast<std::size_t>(first.dimension == 3 ? 3 : 2);
  std::vector<float> radius(first.radius.begin(), first.radius.end());
  std::vector<float> state;  // per frame and particle: d position components, d velocity ones
  std::vector<std::uint32_t> collisions;
  std::vector<double> times;
  state.reserve(frames.size() * n * 2 * d);
  for (const Frame& f : frames) {
    times.push_back(f.time);
    for (std::size_t i = 0; i < n; ++i) {
      for (const Vec<3>* v : {&f.position[i], &f.velocity[i]}) {
        for (std::size_t k = 0; k < d; ++k) state.push_back(static_cast<float>((*v)[k]));
      }
      collisions.push_back(f.collisions[i]);
    }
  }
  nlohmann::json box = {first.box[0], first.box[1]};
  if (d == 3) box.push_back(first.box[2]);
  const nlohmann::json data = {
      {"n", n},
      {"dimension", d},
      {"box", box},
      {"periodic", first.periodic},
      {"times", times},
      {"radius", base64(radius.data(), radius.size() * sizeof(float))},
      {"state", base64(state.data(), state.size() * sizeof(float))},
      {"collisions", base64(collisions.data(), collisions.size() * sizeof(std::uint32_t))},
  };
  constexpr std::string_view kSlot = "/*CAROM_DATA*/";
  const std::size_t slot = kViewerHtml.find(kSlot);
  out << kViewerHtml.substr(0, slot) << data.dump() << kViewerHtml.substr(slot + kSlot.size());
}

}  // namespace carom
