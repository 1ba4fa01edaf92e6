// The GSD reader: a start from one frame (read_gsd_start, gsd.hpp) and a trajectory's frames
// (read_gsd_frames, trajectory_reader.hpp), every number checked as a start's are.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "carom/core/physics.hpp"
#include "carom/engine/validation.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/gsd.hpp"
#include "carom/io/trajectory_reader.hpp"
#include "gsd_format.hpp"

namespace carom {

namespace {

using gsd::kHeaderSize;
using gsd::kMagic;
using gsd::kNameBlock;
using gsd::kTypeSize;

// Elements a start may read from one chunk: far beyond any system carom runs, far below memory.
constexpr std::uint64_t kMostElements = std::uint64_t{1} << 30;

class GsdReader {
 public:
  // `purpose` begins every failure's message: "not a usable GSD start", ...
  GsdReader(const std::string& path, std::string purpose)
      : path_(path), purpose_(std::move(purpose)), in_(open_input(path)) {
    in_.seekg(0, std::ios::end);
    size_ = static_cast<std::uint64_t>(in_.tellg());
    std::array<char, kHeaderSize> header{};
    read_at(0, header.data(), header.size(), "the header");
    const auto field = [&](std::size_t offset, auto value) {
      std::memcpy(&value, header.data() + offset, sizeof(value));
      return value;
    };
    if (field(0, std::uint64_t{}) != kMagic) fail("it does not start as a GSD file does");
    const std::uint32_t file_version = field(44, std::uint32_t{});
    if (file_version >> 16 < 1 || file_version >> 16 > 2) {
      fail(fmt::format("GSD file version {}.{} (carom reads 1.x and 2.x)", file_version >> 16,
                       file_version & 0xFFFF));
    }
    if (std::string(header.data() + 112, strnlen(header.data() + 112, 64)) != "hoomd") {
      fail("its schema is not HOOMD's (\"hoomd\")");
    }
    // The names, null-separated (one terminator each in version 2, 64-byte slots in version 1).
    const std::uint64_t names_at = field(24, std::uint64_t{}), blocks = field(32, std::uint64_t{});
    if (blocks > size_ / kNameBlock) fail("its name list runs past the end of the file");
    std::string names(blocks * kNameBlock, '\0');
    read_at(names_at, names.data(), names.size(), "the name list");
    for (std::size_t from = 0; from < names.size();) {
      const std::size_t end = std::min(names.find('\0', from), names.size());
      if (end > from) ids_[names.substr(from, end - from)] = static_cast<std::uint16_t>(count_++);
      from = end + 1;
    }
    // The index: entries sorted by frame, up to the first with location 0.
    const std::uint64_t index_at = field(8, std::uint64_t{}), capacity = field(16, std::uint64_t{});
    if (capacity > size_ / sizeof(GsdEntry)) fail("its index runs past the end of the file");
    std::vector<GsdEntry> all(capacity);
    read_at(index_at, reinterpret_cast<char*>(all.data()), capacity * sizeof(GsdEntry),
            "the index");
    for (const GsdEntry& e : all) {
      if (e.location == 0) break;
      const std::uint64_t element = e.type < kTypeSize.size() ? kTypeSize[e.type] : 0;
      // Every frame has a chunk of its own (its step, at least), so frame numbers stay below the
      // number of entries: a corrupt huge one would otherwise make up endless empty frames.
      if (element == 0 || e.m == 0 || e.id >= count_ || e.location < 0 ||
          (!entries_.empty() && e.frame < entries_.back().frame) || e.frame >= capacity ||
          e.n > kMostElements || e.m > kMostElements / std::max<std::uint64_t>(e.n, 1) ||
          static_cast<std::uint64_t>(e.location) > size_ ||
          e.n * e.m * element > size_ - static_cast<std::uint64_t>(e.location)) {
        fail(fmt::format("index entry {} is corrupt", entries_.size()));
      }
      entries_.push_back(e);
    }
    if (entries_.empty()) fail("it holds no frames");
  }

  std::uint64_t frames() const { return entries_.back().frame + 1; }

  // The values of chunk `name` in `frame` (else frame 0) as doubles, row by row, with its shape;
  // nullopt when neither has it.
  struct Values {
    std::vector<double> data;
    std::uint64_t rows = 0, columns = 0;
  };
  std::optional<Values> values(const std::string& name, std::uint64_t frame) {
    const GsdEntry* e = entry(name, frame);
    if (e == nullptr) e = entry(name, 0);
    if (e == nullptr) return std::nullopt;
    const std::uint64_t element = kTypeSize[e->type];
    std::vector<char> raw(e->n * e->m * element);
    read_at(static_cast<std::uint64_t>(e->location), raw.data(), raw.size(), name);
    Values v{std::vector<double>(e->n * e->m), e->n, e->m};
    for (std::size_t i = 0; i < v.data.size(); ++i) v.data[i] = element_at(raw, i, e->type);
    return v;
  }

  // Whether `frame` itself holds chunk `name` (without frame 0's fallback); reads only the index.
  bool has(const std::string& name, std::uint64_t frame) const {
    return entry(name, frame) != nullptr;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_, 0, purpose_ + ": " + what);
  }

 private:
  using GsdEntry = typename GsdFormat<2>::Entry;

  // The index entry of chunk `name` in `frame` itself, or nullptr.
  const GsdEntry* entry(const std::string& name, std::uint64_t frame) const {
    const auto id = ids_.find(name);
    if (id == ids_.end()) return nullptr;
    // The entries are sorted by frame.
    const auto first = std::partition_point(entries_.begin(), entries_.end(),
                                            [&](const GsdEntry& e) { return e.frame < frame; });
    for (auto it = first; it != entries_.end() && it->frame == frame; ++it) {
      if (it->id == id->second) return &*it;
    }
    return nullptr;
  }

  void read_at(std::uint64_t offset, char* data, std::uint64_t bytes, const std::string& what) {
    if (offset > size_ || bytes > size_ - offset) fail(what + " runs past the end of the file");
    in_.seekg(static_cast<std::streamoff>(offset));
    in_.read(data, static_cast<std::streamsize>(bytes));
    if (!in_) fail("cannot read " + what);
  }

  static double element_at(const std::vector<char>& raw, std::size_t i, std::uint8_t type) {
    const auto get = [&](auto value) {
      std::memcpy(&value, raw.data() + i * sizeof(value), sizeof(value));
      return static_cast<double>(value);
    };
    switch (type) {
      case 1:
        return get(std::uint8_t{});
      case 2:
        return get(std::uint16_t{});
      case 3:
        return get(std::uint32_t{});
      case 4:
        return get(std::uint64_t{});
      case 5:
        return get(std::int8_t{});
      case 6:
        return get(std::int16_t{});
      case 7:
        return get(std::int32_t{});
      case 8:
        return get(std::int64_t{});
      case 9:
        return get(float{});
      default:
        return get(double{});
    }
  }

  std::string path_, purpose_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
  std::map<std::string, std::uint16_t> ids_;
  std::size_t count_ = 0;
  std::vector<GsdEntry> entries_;
};

// The particles of frame `frame`: the count and every per-particle chunk carom uses, in the
// schema's shapes (a missing chunk from frame 0, else HOOMD's default), every number checked.
// Image flags are taken from frame 0 only when `images_from_frame_zero`: HOOMD writes them in
// frame 0 alone unless asked, and frame 0's flags are not a later frame's (`has_image` false then).
struct FrameChunks {
  std::uint64_t n = 0;
  std::vector<std::string> type_names{"A"};  // particles/types
  std::vector<std::uint32_t> type;           // particles/typeid, each below type_names.size()
  std::vector<double> position, velocity, diameter, mass;
  std::vector<std::array<std::int32_t, 3>> image;
  bool has_image = true;
  bool exact = false;  // positions in [0, L) and every value carom's double (take_exact_values)
};

FrameChunks read_frame_chunks(GsdReader& gsd, std::uint64_t frame, bool images_from_frame_zero) {
  const auto n_values = gsd.values("particles/N", frame);
  const double count = n_values && n_values->data.size() == 1 ? n_values->data[0] : 0.0;
  if (!(count >= 1.0 && count <= static_cast<double>(kMostElements)) ||
      count != std::floor(count)) {
    gsd.fail(fmt::format("frame {} has no particle count (particles/N) from 1 to {}", frame,
                         kMostElements));
  }
  FrameChunks chunks;
  const auto n = chunks.n = static_cast<std::uint64_t>(count);
  // A chunk neither the frame nor frame 0 has takes the schema's default value.
  const auto column = [&](const std::string& name, std::uint64_t columns, double fallback) {
    std::optional<GsdReader::Values> v = gsd.values(name, frame);
    if (!v) return std::vector<double>(n * columns, fallback);
    if (v->rows != n || v->columns != columns) {
      gsd.fail(fmt::format("{} has {} x {} values for {} particles", name, v->rows, v->columns, n));
    }
    // Every number as the classic reader checks one (finite, sensible magnitudes), before use;
    // the message is made only for a number that fails.
    for (std::size_t i = 0; i < v->data.size(); ++i) {
      try {
        check_number(v->data[i], std::string());
      } catch (const std::invalid_argument&) {
        try {
          check_number(v->data[i], fmt::format("{} of particle {}", name, i / columns));
        } catch (const std::invalid_argument& e) {
          gsd.fail(fmt::format("frame {}: {}", frame, e.what()));
        }
      }
    }
    return std::move(v->data);
  };
  // A chunk equal to the schema's default may be left out (gsd.hoomd does): position 0 too.
  chunks.position = column("particles/position", 3, 0.0);
  chunks.velocity = column("particles/velocity", 3, 0.0);
  chunks.diameter = column("particles/diameter", 1, 1.0);
  chunks.mass = column("particles/mass", 1, 1.0);
  chunks.has_image = images_from_frame_zero || frame == 0 || gsd.has("particles/image", frame);
  const std::vector<double> image = column("particles/image", 3, 0.0);
  // The species: particles/types (rows of null-padded names) and particles/typeid.
  if (const auto names = gsd.values("particles/types", frame)) {
    chunks.type_names.clear();
    for (std::uint64_t r = 0; r < names->rows; ++r) {
      std::string name;
      for (std::uint64_t c = 0; c < names->columns; ++c) {
        const double code = names->data[r * names->columns + c];
        if (code == 0.0) break;
        name.push_back(static_cast<char>(static_cast<int>(code)));
      }
      chunks.type_names.push_back(name);
    }
    if (chunks.type_names.empty()) chunks.type_names = {"A"};
  }
  const std::vector<double> typeid_ = column("particles/typeid", 1, 0.0);
  chunks.type.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = typeid_[i];
    if (!(t >= 0.0 && t < static_cast<double>(chunks.type_names.size())) || t != std::floor(t)) {
      gsd.fail(
          fmt::format("frame {}: particle {} has typeid {}, not one of the {} types of "
                      "particles/types",
                      frame, i, t, chunks.type_names.size()));
    }
    chunks.type[i] = static_cast<std::uint32_t>(t);
  }
  chunks.image.resize(n);
  for (std::size_t i = 0; i < image.size(); ++i) {
    const double f = image[i];
    if (!(std::abs(f) <= 2147483647.0) || f != std::floor(f)) {
      gsd.fail(fmt::format("particle {} has image flag {}", i / 3, f));
    }
    chunks.image[i / 3][i % 3] = static_cast<std::int32_t>(f);
  }
  return chunks;
}

// The dimension and box of frame `frame`, which carom's boxes can be; periodic unless carom
// wrote it for a box with walls (log/carom/periodic = 0).
struct FrameBox {
  int dimension = 3;
  std::array<double, 3> size{};
  bool periodic = true;
  double shear_shift = 0.0;  // xy Ly: a sheared run's images one box up lie at (xy Ly, Ly)
};

FrameBox read_frame_box(GsdReader& gsd, std::uint64_t frame) {
  const auto dimensions = gsd.values("configuration/dimensions", frame);
  const double dim = dimensions && dimensions->data.size() == 1 ? dimensions->data[0] : 3.0;
  if (dim != 2.0 && dim != 3.0) gsd.fail(fmt::format("{} dimensions", dim));
  const auto box_values = gsd.values("configuration/box", frame);
  std::vector<double> box = box_values ? box_values->data : std::vector<double>{1, 1, 1, 0, 0, 0};
  if (box.size() != 6) gsd.fail("configuration/box does not hold 6 values");
  if (box[4] != 0.0 || box[5] != 0.0) {
    gsd.fail(
        "its box is tilted in xz or yz: carom's boxes are rectangular, or sheared along x "
        "(tilt xy only)");
  }
  for (std::size_t k = 0; k < static_cast<std::size_t>(dim); ++k) {
    if (!(box[k] > 0.0) || !std::isfinite(box[k])) {
      gsd.fail(fmt::format("box side {} is {}: sides must be positive numbers", k, box[k]));
    }
  }
  const auto periodic = gsd.values("log/carom/periodic", frame);
  FrameBox frame_box{static_cast<int>(dim),
                     {box[0], box[1], box[2]},
                     !(periodic && periodic->data.size() == 1 && periodic->data[0] == 0.0),
                     box[3] * box[1]};
  if (!std::isfinite(frame_box.shear_shift)) gsd.fail(fmt::format("its tilt xy is {}", box[3]));
  if (frame_box.shear_shift != 0.0 && !frame_box.periodic) {
    gsd.fail("its box is tilted (xy) but has walls (log/carom/periodic = 0)");
  }
  return frame_box;
}

// The double-precision copies carom's full-precision frames carry (GsdFormat's full_precision),
// in place of `chunks`' and `box`'s single-precision values, when frame `frame` has them: each
// must round to the single-precision value beside it as the writer rounded it, or the file was
// changed by a program that left them behind, and they are refused rather than trusted.
template <std::size_t D>
void take_exact_values(GsdReader& gsd, std::uint64_t frame, FrameChunks& chunks,
                       std::array<double, 3>& box) {
  constexpr std::array<const char*, 5> kExact = {"log/carom/box", "log/carom/position",
                                                 "log/carom/velocity", "log/carom/diameter",
                                                 "log/carom/mass"};
  std::size_t present = 0;
  for (const char* name : kExact) present += gsd.has(name, frame) ? 1 : 0;
  if (present == 0) return;
  const std::uint64_t n = chunks.n;
  const auto exact = [&](const char* name, std::uint64_t rows, std::uint64_t columns) {
    std::optional<GsdReader::Values> v = gsd.values(name, frame);
    if (present < kExact.size() || !v || v->rows != rows || v->columns != columns) {
      gsd.fail(fmt::format(
          "frame {} has some of carom's double-precision chunks (log/carom/box, position, "
          "velocity, diameter, mass) but not all of them in their shapes",
          frame));
    }
    return std::move(v->data);
  };
  const std::vector<double> exact_box = exact("log/carom/box", 3, 1);
  const std::vector<double> position = exact("log/carom/position", n, 3);
  const std::vector<double> velocity = exact("log/carom/velocity", n, 3);
  const std::vector<double> diameter = exact("log/carom/diameter", n, 1);
  const std::vector<double> mass = exact("log/carom/mass", n, 1);
  const auto matches = [](double single, double exact) {
    return single == static_cast<double>(static_cast<float>(exact));
  };
  bool same = true;
  for (std::size_t k = 0; k < D; ++k) same = same && matches(box[k], exact_box[k]);
  for (std::uint64_t i = 0; i < n && same; ++i) {
    for (std::size_t k = 0; k < D; ++k) {
      same = same && matches(chunks.position[3 * i + k], position[3 * i + k] - 0.5 * exact_box[k]);
      same = same && matches(chunks.velocity[3 * i + k], velocity[3 * i + k]);
    }
    same = same && matches(chunks.diameter[i], diameter[i]) && matches(chunks.mass[i], mass[i]);
  }
  if (!same) {
    gsd.fail(fmt::format(
        "frame {}: its double-precision chunks (log/carom/*) are not the values of its particles "
        "and box: the file was changed by another program, which kept carom's copies of the "
        "old ones. Remove the log/carom/box, position, velocity, diameter and mass chunks to "
        "start from the single-precision values",
        frame));
  }
  for (std::size_t k = 0; k < 3; ++k) box[k] = k < D ? exact_box[k] : box[k];
  // In carom's box [0, L) already: centred again as particles/position is, and un-centred by
  // start_from, they would not be these bits.
  for (std::uint64_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < D; ++k) chunks.position[3 * i + k] = position[3 * i + k];
  }
  chunks.velocity = velocity;
  chunks.diameter = diameter;
  chunks.mass = mass;
  chunks.exact = true;
}

template <std::size_t D>
ClassicInput<D> start_from(GsdReader& gsd, std::uint64_t frame, FrameBox frame_box) {
  FrameChunks chunks = read_frame_chunks(gsd, frame, true);
  take_exact_values<D>(gsd, frame, chunks, frame_box.size);
  const std::array<double, 3>& box = frame_box.size;
  ClassicInput<D> input;
  System<D>& system = input.system;
  system.box.boundary = frame_box.periodic ? Boundary::periodic : Boundary::walls;
  for (std::size_t k = 0; k < D; ++k) system.box.size[k] = box[k];
  for (std::uint64_t i = 0; i < chunks.n; ++i) {
    Particle<D> p;
    for (std::size_t k = 0; k < D; ++k) {
      // HOOMD's box is centred on the origin (carom's exact copies are not)
      p.position[k] = chunks.position[3 * i + k] + (chunks.exact ? 0.0 : 0.5 * box[k]);
      p.velocity[k] = chunks.velocity[3 * i + k];
    }
    p.radius = 0.5 * chunks.diameter[i];
    ParticleRecord record{chunks.mass[i]};
    record.image = chunks.image[i];
    record.type = chunks.type[i];
    for (std::size_t k = D; k < 3; ++k) record.image[k] = 0;
    wrap(p.position, system.box, record.image);
    system.particles.push_back(p);
    system.records.push_back(record);
  }
  system.type_names = chunks.type_names;
  if (has_types(system)) input.record.types = system.type_names;
  input.radius = system.particles.front().radius;
  // A GSD frame is a physical system, HOOMD's or carom's: never the classic assignment's.
  input.record.boundary = system.box.boundary;
  input.record.rule = Rule::elastic;
  try {
    check_start(system);
  } catch (const std::invalid_argument& e) {
    gsd.fail(fmt::format("frame {}: {}", frame, e.what()));
  }
  return input;
}

}  // namespace

AnyClassicInput read_gsd_start(const std::string& path, std::optional<std::uint64_t> frame) {
  GsdReader gsd(path, "not a usable GSD start");
  const std::uint64_t k = frame.value_or(gsd.frames() - 1);
  if (k >= gsd.frames()) {
    gsd.fail(fmt::format("it has frames 0 to {}, not {}", gsd.frames() - 1, k));
  }
  const FrameBox box = read_frame_box(gsd, k);
  if (box.shear_shift != 0.0) {
    gsd.fail(fmt::format(
        "frame {} is a sheared box (tilt xy = {:g}): a run starts from a rectangular box; a "
        "sheared run goes on from its checkpoint (carom run --resume)",
        k, box.shear_shift / box.size[1]));
  }
  if (box.dimension == 2) return start_from<2>(gsd, k, box);
  return start_from<3>(gsd, k, box);
}

std::vector<Frame> read_gsd_frames(const std::string& path, const FrameSelection& selection) {
  GsdReader gsd(path, "not a readable GSD trajectory");
  const std::uint64_t last =
      std::min<std::uint64_t>(selection.last.value_or(gsd.frames()), gsd.frames());
  const std::uint64_t stride = std::max<std::size_t>(selection.stride, 1);
  const std::uint64_t selected =
      selection.first < last ? (last - selection.first + stride - 1) / stride : 0;
  // What the frames will take once expanded (each holds every particle, even one that leans on
  // frame 0 for them), against the memory there is, before any is read.
  if (selected > 0) {
    const auto n = gsd.values("particles/N", selection.first);
    const double count = n && n->data.size() == 1 ? n->data[0] : 0.0;
    constexpr double kBytesPerParticle = sizeof(Vec<3>) * 2 + sizeof(double) +
                                         sizeof(std::uint32_t) +
                                         sizeof(std::array<std::int32_t, 3>);
    const double bytes = static_cast<double>(selected) * count * kBytesPerParticle;
    const double memory = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                          static_cast<double>(::sysconf(_SC_PAGE_SIZE));
    if (memory > 0.0 && bytes > memory / 2.0) {
      gsd.fail(fmt::format(
          "its {} frames of {:.0f} particles would take {:.3g} GB in memory, more than half of "
          "this machine's {:.3g} GB: read a part of them (carom view --frames A:B --stride K)",
          selected, count, bytes / 1e9, memory / 1e9));
    }
  }
  std::vector<Frame> frames;
  for (std::uint64_t k = selection.first; k < last; k += stride) {
    Frame f;
    const FrameBox frame_box = read_frame_box(gsd, k);
    const std::array<double, 3>& box = frame_box.size;
    f.dimension = frame_box.dimension;
    const FrameChunks chunks = read_frame_chunks(gsd, k, false);
    if (!frames.empty() &&
        (chunks.n != frames.front().radius.size() || f.dimension != frames.front().dimension)) {
      gsd.fail(fmt::format("frame {} has {} particles in {}D, frame 0 {} in {}D", k, chunks.n,
                           f.dimension, frames.front().radius.size(), frames.front().dimension));
    }
    const auto d = static_cast<std::size_t>(f.dimension);
    const auto time = gsd.values("log/time", k);
    const auto step = gsd.values("configuration/step", k);
    f.time = time && time->data.size() == 1   ? time->data[0]
             : step && step->data.size() == 1 ? step->data[0]
                                              : static_cast<double>(k);
    if (!std::isfinite(f.time)) gsd.fail(fmt::format("frame {} has time {}", k, f.time));
    f.periodic = frame_box.periodic;
    f.shear_shift = frame_box.shear_shift;
    for (std::size_t c = 0; c < d; ++c) f.box[c] = box[c];
    for (std::uint64_t i = 0; i < chunks.n; ++i) {
      Vec<3> x{}, v{};
      for (std::size_t c = 0; c < d; ++c) {
        x[c] = chunks.position[3 * i + c] + 0.5 * box[c];  // HOOMD's box is centred
        v[c] = chunks.velocity[3 * i + c];
      }
      if (!(chunks.diameter[i] > 0.0)) {
        gsd.fail(fmt::format("frame {}: particle {} has diameter {}", k, i, chunks.diameter[i]));
      }
      f.position.push_back(x);
      f.velocity.push_back(v);
      f.radius.push_back(0.5 * chunks.diameter[i]);
      if (chunks.has_image) {
        std::array<std::int32_t, 3> flags = chunks.image[i];
        for (std::size_t c = d; c < 3; ++c) flags[c] = 0;
        f.image.push_back(flags);
      }
    }
    f.collisions.assign(chunks.n, 0);
    f.type = chunks.type;
    f.type_names = chunks.type_names;
    frames.push_back(std::move(f));
  }
  return frames;
}

}  // namespace carom
