// The GSD writer: GsdFormat (gsd_format.hpp) appends frames to a file of the HOOMD schema.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "carom/engine/engine.hpp"
#include "carom/version.hpp"
#include "gsd_format.hpp"
#include "whole_lines.hpp"

namespace carom {

namespace {

using gsd::kHeaderSize;
using gsd::kMagic;
using gsd::kNameBlock;
using gsd::kTypeSize;

constexpr std::uint32_t version(std::uint32_t major, std::uint32_t minor) {
  return major << 16 | minor;
}
constexpr std::uint64_t kFirstIndexCapacity = 256;

// Moves a position of the rectangular box [0, L) along x by whole sides into HOOMD's tilted box
// of tilt shift / Ly (the parallelogram of x - shift (y / Ly - 1/2) in [0, Lx)), where HOOMD
// expects its particles, keeping `image` the flags that unwrap it.
template <std::size_t D>
void into_tilted_box(Vec<D>& position, const Vec<D>& side, double shift,
                     std::array<std::int32_t, 3>& image) {
  const double sides = std::floor((position[0] - shift * (position[1] / side[1] - 0.5)) / side[0]);
  position[0] -= sides * side[0];
  add_sides(image[0], sides);
}

// GSD's element types.
enum Type : std::uint8_t {
  kUint8 = 1,
  kUint32 = 3,
  kUint64 = 4,
  kInt8 = 5,
  kInt32 = 7,
  kFloat = 9,
  kDouble = 10
};

// Every chunk a frame may have, in the order of their names (GSD's name list is sorted): a
// file's ids are the places of its chunks' names among those it writes.
enum Chunk : std::uint16_t {
  kBox,
  kDimensions,
  kStep,
  kExactBox,
  kExactDiameter,
  kExactMass,
  kPeriodic,
  kExactPosition,
  kExactVelocity,
  kTime,
  kN,
  kDiameter,
  kImage,
  kMass,
  kPosition,
  kTypeid,
  kTypes,
  kVelocity,
  kChunks
};
constexpr std::array<std::string_view, kChunks> kNames = {
    "configuration/box",  "configuration/dimensions", "configuration/step",
    "log/carom/box",      "log/carom/diameter",       "log/carom/mass",
    "log/carom/periodic", "log/carom/position",       "log/carom/velocity",
    "log/time",           "particles/N",              "particles/diameter",
    "particles/image",    "particles/mass",           "particles/position",
    "particles/typeid",   "particles/types",          "particles/velocity"};

// The double-precision copies a full-precision file adds (GsdFormat::full_precision).
constexpr bool is_exact(Chunk chunk) {
  return chunk == kExactBox || chunk == kExactDiameter || chunk == kExactMass ||
         chunk == kExactPosition || chunk == kExactVelocity;
}

// A chunk's id in a file with or without the copies: its name's place among the file's names
// (kChunks: how many chunks a frame of the file has).
constexpr std::uint16_t chunk_id(Chunk chunk, bool full_precision) {
  std::uint16_t id = 0;
  for (std::uint16_t c = 0; c < chunk; ++c) id += full_precision || !is_exact(Chunk(c)) ? 1 : 0;
  return id;
}

template <class T>
void put(std::ostream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <class T>
void put(std::ostream& out, const std::vector<T>& values) {
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(T)));
}

// Room for index entries still to come.
void put_zeros(std::ostream& out, std::uint64_t bytes) {
  const std::vector<char> zeros(bytes, '\0');
  out.write(zeros.data(), static_cast<std::streamsize>(zeros.size()));
}

// The name list: the chunks' names, null-terminated, padded to whole blocks.
std::string name_list(bool full_precision) {
  std::string names;
  for (std::uint16_t c = 0; c < kChunks; ++c) {
    if (full_precision || !is_exact(Chunk(c))) (names += kNames[c]) += '\0';
  }
  names.resize((names.size() + kNameBlock - 1) / kNameBlock * kNameBlock, '\0');
  return names;
}

// The capacity of the block the index moves to (at the end of the file, after frame `frame`'s
// chunks) when the frame brings it to `needed` entries and a block of `capacity` cannot take
// them; nullopt when it can. A resumed run finds where the index was after its frames by the
// same rule.
std::optional<std::uint64_t> moved_index_capacity(std::uint64_t frame, std::uint64_t needed,
                                                  std::uint64_t capacity) {
  if (needed <= capacity && frame + 1 < capacity) return std::nullopt;
  return 2 * std::max(needed, capacity);
}

// `value` as the single-precision number a GSD file stores. Throws std::range_error naming
// `what` when it would not read back: not a number, beyond float's range (stored as inf), or a
// size (a box side, a diameter, a mass: positive) that rounds to 0.
template <class What>
float single(double value, bool size, const What& what) {
  const auto stored = static_cast<float>(value);
  if (std::isfinite(stored) && (!size || stored > 0.0f)) return stored;
  if (std::isnan(value)) {
    throw std::range_error(fmt::format("{} is not a number, which no .gsd reader takes", what()));
  }
  throw std::range_error(fmt::format(
      "{} is {:g}, which a .gsd file's single precision stores as {} (magnitudes up to {:.3g}{}), "
      "and no reader takes that back: dump to .xyz or .lammpstrj, which hold every double, or "
      "rescale the units",
      what(), value, stored, static_cast<double>(std::numeric_limits<float>::max()),
      size ? fmt::format(", sizes from {:.3g}",
                         static_cast<double>(std::numeric_limits<float>::denorm_min()))
           : ""));
}

}  // namespace

template <std::size_t D>
struct GsdFormat<D>::Values {
  std::array<float, 6> box{};
  std::vector<float> position, velocity, diameter, mass;
  std::vector<std::int32_t> image;
  // full_precision's: the box sides, and the positions in carom's own box [0, L), as doubles.
  std::array<double, 3> exact_box{};
  std::vector<double> exact_position, exact_velocity, exact_diameter, exact_mass;
};

template <std::size_t D>
typename GsdFormat<D>::Values GsdFormat<D>::values(double t, const System<D>& system,
                                                   Velocities velocities) const {
  const std::size_t n = system.size();
  const Vec<D>& side = system.box.size;
  constexpr const char* kAxes = "xyz";
  Values v;
  // HOOMD's box is centred on the origin; a disk's box has Lz = 0, as HOOMD writes 2D boxes.
  for (std::size_t k = 0; k < D; ++k) {
    v.box[k] = single(side[k], true, [&] { return fmt::format("the box side L{}", kAxes[k]); });
  }
  v.position.resize(3 * n);
  v.velocity.resize(3 * n);
  v.diameter.resize(n);
  v.mass.resize(n);
  v.image.resize(3 * n);
  const double at = system.stored(t);
  // A sheared box as HOOMD's tilted one: the images one box up lie at (xy Ly, Ly).
  const double shift = shown_shift(system.box, at);
  v.box[3] = single(shift / side[1], false, [] { return std::string("the box's tilt xy"); });
  for (std::size_t i = 0; i < n; ++i) {
    std::array<std::int32_t, 3> flags = system.records[i].image;
    Particle<D> p = synchronised(system.particles[i], system.box, at, flags);
    if (velocities == Velocities::at_rest) p.velocity = Vec<D>{};
    if (shift != 0.0) into_tilted_box(p.position, side, shift, flags);
    for (std::size_t k = 0; k < D; ++k) {
      v.position[3 * i + k] = single(p.position[k] - 0.5 * side[k], false, [&] {
        return fmt::format("{} of particle {} (from the box's centre) at t = {}", kAxes[k], i, t);
      });
      v.velocity[3 * i + k] = single(p.velocity[k], false, [&] {
        return fmt::format("v{} of particle {} at t = {}", kAxes[k], i, t);
      });
      v.image[3 * i + k] = flags[k];
    }
    v.diameter[i] =
        single(2.0 * p.radius, true, [&] { return fmt::format("the diameter of particle {}", i); });
    v.mass[i] = single(system.records[i].mass, true,
                       [&] { return fmt::format("the mass of particle {}", i); });
    if (full_precision_) {
      for (std::size_t k = 0; k < 3; ++k) {
        v.exact_position.push_back(k < D ? p.position[k] : 0.0);
        v.exact_velocity.push_back(k < D ? p.velocity[k] : 0.0);
      }
      v.exact_diameter.push_back(2.0 * p.radius);
      v.exact_mass.push_back(system.records[i].mass);
    }
  }
  for (std::size_t k = 0; k < D; ++k) v.exact_box[k] = side[k];
  return v;
}

template <std::size_t D>
void GsdFormat<D>::check_frame(const System<D>& system, double t) const {
  values(t, system, Velocities::as_stored);
}

template <std::size_t D>
void GsdFormat<D>::write_header(std::ostream& out) const {
  std::array<char, kHeaderSize> header{};
  const auto at = [&](std::size_t offset, const auto& value) {
    std::memcpy(header.data() + offset, &value, sizeof(value));
  };
  at(0, kMagic);
  at(8, index_location_);
  at(16, index_capacity_);
  at(24, namelist_location_);
  at(32, namelist_blocks_);
  at(40, version(1, 4));  // the HOOMD schema's version
  at(44, version(2, 0));  // the file layer's
  const std::string application = std::string("carom ") + kVersion;
  std::memcpy(header.data() + 48, application.data(),
              std::min<std::size_t>(63, application.size()));
  std::memcpy(header.data() + 112, "hoomd", 5);
  out.seekp(0);
  out.write(header.data(), header.size());
}

template <std::size_t D>
void GsdFormat<D>::start(std::ostream& out) {
  const std::string names = name_list(full_precision_);
  namelist_location_ = kHeaderSize;
  namelist_blocks_ = names.size() / kNameBlock;
  index_location_ = kHeaderSize + names.size();
  index_capacity_ = kFirstIndexCapacity;
  write_header(out);
  out.write(names.data(), static_cast<std::streamsize>(names.size()));
  put_zeros(out, index_capacity_ * sizeof(Entry));
}

template <std::size_t D>
void GsdFormat<D>::write_frame(std::ostream& out, std::uint64_t index, double t,
                               const System<D>& system, Velocities velocities) {
  const Values v = values(t, system, velocities);  // refused before anything is written
  if (frames_ == 0) start(out);
  const auto n = static_cast<std::uint32_t>(system.size());
  std::vector<std::uint32_t> typeid_(n);
  for (std::size_t i = 0; i < n; ++i) typeid_[i] = system.records[i].type;
  // The names as GSD stores them: one row each, null-padded to the longest plus its null.
  std::size_t width = 0;
  for (const std::string& name : system.type_names) width = std::max(width, name.size() + 1);
  std::string types(width * system.type_names.size(), '\0');
  for (std::size_t t = 0; t < system.type_names.size(); ++t) {
    types.replace(t * width, system.type_names[t].size(), system.type_names[t]);
  }

  out.seekp(0, std::ios::end);
  std::vector<Entry> added;
  // Chunks are written in the order of their names: their ids rise within the frame.
  const auto chunk = [&](Chunk chunk, Type type, std::uint64_t rows, std::uint32_t columns,
                         const auto& write) {
    const std::uint16_t id = chunk_id(chunk, full_precision_);
    added.push_back({frames_, rows, static_cast<std::int64_t>(out.tellp()), columns, id, type, 0});
    write();
  };
  chunk(kBox, kFloat, 6, 1, [&] { put(out, v.box); });
  chunk(kDimensions, kUint8, 1, 1, [&] { put(out, static_cast<std::uint8_t>(D)); });
  chunk(kStep, kUint64, 1, 1, [&] { put(out, index); });
  if (full_precision_) {
    chunk(kExactBox, kDouble, 3, 1, [&] { put(out, v.exact_box); });
    chunk(kExactDiameter, kDouble, n, 1, [&] { put(out, v.exact_diameter); });
    chunk(kExactMass, kDouble, n, 1, [&] { put(out, v.exact_mass); });
  }
  // HOOMD's boxes are periodic; carom's may have walls, which its readers take from here.
  chunk(kPeriodic, kUint8, 1, 1,
        [&] { put(out, static_cast<std::uint8_t>(system.box.periodic() ? 1 : 0)); });
  if (full_precision_) {
    chunk(kExactPosition, kDouble, n, 3, [&] { put(out, v.exact_position); });
    chunk(kExactVelocity, kDouble, n, 3, [&] { put(out, v.exact_velocity); });
  }
  chunk(kTime, kDouble, 1, 1, [&] { put(out, t); });
  chunk(kN, kUint32, 1, 1, [&] { put(out, n); });
  chunk(kDiameter, kFloat, n, 1, [&] { put(out, v.diameter); });
  chunk(kImage, kInt32, n, 3, [&] { put(out, v.image); });
  chunk(kMass, kFloat, n, 1, [&] { put(out, v.mass); });
  chunk(kPosition, kFloat, n, 3, [&] { put(out, v.position); });
  chunk(kTypeid, kUint32, n, 1, [&] { put(out, typeid_); });
  chunk(kTypes, kInt8, system.type_names.size(), static_cast<std::uint32_t>(width),
        [&] { out.write(types.data(), static_cast<std::streamsize>(types.size())); });
  chunk(kVelocity, kFloat, n, 3, [&] { put(out, v.velocity); });
  // Chunks with no rows (N = 0) are not indexed: GSD has no empty chunks.
  std::erase_if(added, [](const Entry& e) { return e.n == 0; });

  // The index grows by doubling into a new block at the end; the header points at it last, so
  // that an interruption leaves the previous frames readable.
  if (const auto moved =
          moved_index_capacity(frames_, entries_.size() + added.size(), index_capacity_)) {
    index_capacity_ = *moved;
    index_location_ = static_cast<std::uint64_t>(out.tellp());
    put(out, entries_);
    put_zeros(out, (index_capacity_ - entries_.size()) * sizeof(Entry));
  }
  out.seekp(static_cast<std::streamoff>(index_location_ + entries_.size() * sizeof(Entry)));
  put(out, added);
  entries_.insert(entries_.end(), added.begin(), added.end());
  ++frames_;
  write_header(out);
  out.seekp(0, std::ios::end);
}

template <std::size_t D>
std::uint64_t GsdFormat<D>::whole_frames_before(std::istream& in, double t, bool inclusive,
                                                double) {
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  const auto read = [&](std::uint64_t offset, void* data, std::uint64_t bytes) {
    if (offset > size || bytes > size - offset) return false;
    in.seekg(static_cast<std::streamoff>(offset));
    in.read(static_cast<char*>(data), static_cast<std::streamsize>(bytes));
    return static_cast<bool>(in);
  };
  const auto refuse = [](const std::string& why) {
    throw std::invalid_argument(
        fmt::format("it is not a GSD trajectory carom wrote ({}), and a resumed run continues only "
                    "carom's own: give --dump a new file",
                    why));
  };
  std::uint64_t magic = 0;
  if (read(0, &magic, sizeof magic) && magic != kMagic) refuse("it does not start as GSD does");
  const std::string names = name_list(full_precision_);
  const std::uint64_t first_index = kHeaderSize + names.size();
  // The header and the names are written first, at once: a file without them whole is one a
  // run was killed as it began.
  if (size < first_index) return 0;
  std::array<char, kHeaderSize> header{};
  std::string stored_names(names.size(), '\0');
  read(0, header.data(), header.size());
  const auto field = [&](std::size_t offset) {
    std::uint64_t value = 0;
    std::memcpy(&value, header.data() + offset, sizeof value);
    return value;
  };
  if (field(24) != kHeaderSize || field(32) != names.size() / kNameBlock ||
      !read(kHeaderSize, stored_names.data(), names.size()) || stored_names != names ||
      std::string_view(header.data() + 112, strnlen(header.data() + 112, 64)) != "hoomd") {
    refuse("its chunks are not the ones carom writes");
  }
  if (size <= first_index + kFirstIndexCapacity * sizeof(Entry)) return 0;  // no frame's chunks
  const std::uint64_t index_at = field(8), capacity = field(16);
  if (capacity > size / sizeof(Entry)) refuse("its index runs past the end of the file");
  std::vector<Entry> index(capacity);
  if (!read(index_at, index.data(), capacity * sizeof(Entry))) {
    refuse("its index runs past the end of the file");
  }
  // Where a chunk ends, if it lies in the file.
  const auto end_of = [&](const Entry& e) -> std::optional<std::uint64_t> {
    const std::uint64_t element = e.type < kTypeSize.size() ? kTypeSize[e.type] : 0;
    const auto at = static_cast<std::uint64_t>(e.location);
    if (element == 0 || e.location <= 0 || at > size || e.m == 0 || e.n > size / e.m ||
        e.n * e.m > (size - at) / element) {
      return std::nullopt;
    }
    return at + e.n * e.m * element;
  };
  // The frames in order, each with its chunks as this writer indexes them, while whole and
  // taken before t.
  const std::uint64_t per_frame = chunk_id(kChunks, full_precision_);
  std::vector<Entry> kept;
  for (std::uint64_t frame = 0; (frame + 1) * per_frame <= capacity; ++frame) {
    const std::span<const Entry> chunks(index.data() + frame * per_frame, per_frame);
    bool whole = true;
    for (std::uint16_t c = 0; c < per_frame; ++c) {
      whole = whole && chunks[c].frame == frame && chunks[c].id == c && end_of(chunks[c]);
    }
    double time = 0.0;
    const Entry& time_chunk = chunks[chunk_id(kTime, full_precision_)];
    if (!whole || time_chunk.type != kDouble || time_chunk.n != 1 ||
        !read(static_cast<std::uint64_t>(time_chunk.location), &time, sizeof time) ||
        !written_before(time, t, inclusive)) {
      break;
    }
    kept.insert(kept.end(), chunks.begin(), chunks.end());
  }
  const std::uint64_t frames = kept.size() / per_frame;
  if (frames == 0) return 0;
  // The index as the writer left it after the last frame kept, and the file's length then.
  std::uint64_t location = first_index, block = kFirstIndexCapacity, length = 0;
  for (std::uint64_t frame = 0; frame < frames; ++frame) {
    std::uint64_t frame_end = 0;
    for (std::uint64_t c = 0; c < per_frame; ++c) {
      frame_end = std::max(frame_end, *end_of(kept[frame * per_frame + c]));
    }
    length = frame_end;
    if (const auto moved = moved_index_capacity(frame, (frame + 1) * per_frame, block)) {
      block = *moved;
      location = frame_end;
      length = location + block * sizeof(Entry);
    }
  }
  std::vector<Entry> then(kept.size());
  if (length > size || !read(location, then.data(), then.size() * sizeof(Entry)) || then != kept) {
    refuse("its index is not where carom puts it");
  }
  frames_ = frames;
  entries_ = std::move(kept);
  index_location_ = location;
  index_capacity_ = block;
  namelist_location_ = kHeaderSize;
  namelist_blocks_ = names.size() / kNameBlock;
  return length;
}

template <std::size_t D>
void GsdFormat<D>::continue_after_cut(std::ostream& out) {
  if (frames_ == 0) return;  // the file begins anew
  out.seekp(static_cast<std::streamoff>(index_location_ + entries_.size() * sizeof(Entry)));
  put_zeros(out, (index_capacity_ - entries_.size()) * sizeof(Entry));
  write_header(out);
  out.seekp(0, std::ios::end);
}

template class GsdFormat<2>;
template class GsdFormat<3>;

}  // namespace carom
