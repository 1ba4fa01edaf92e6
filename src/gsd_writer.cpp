// The GSD writer: GsdFormat (gsd_format.hpp) appends frames to a file of the HOOMD schema.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

#include "carom/engine.hpp"
#include "carom/version.hpp"
#include "gsd_format.hpp"

namespace carom {

namespace {

using gsd::kHeaderSize;
using gsd::kMagic;
using gsd::kNameBlock;

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

// The chunks of a frame in the order of their ids (the namelist's order).
enum Chunk : std::uint16_t {
  kBox,
  kDimensions,
  kStep,
  kPeriodic,
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
    "configuration/box",  "configuration/dimensions",
    "configuration/step", "log/carom/periodic",
    "log/time",           "particles/N",
    "particles/diameter", "particles/image",
    "particles/mass",     "particles/position",
    "particles/typeid",   "particles/types",
    "particles/velocity"};

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

}  // namespace

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
  std::string names;
  for (const std::string_view name : kNames) (names += name) += '\0';
  names.resize((names.size() + kNameBlock - 1) / kNameBlock * kNameBlock, '\0');
  namelist_location_ = kHeaderSize;
  namelist_blocks_ = names.size() / kNameBlock;
  index_location_ = kHeaderSize + names.size();
  index_capacity_ = kFirstIndexCapacity;
  write_header(out);
  out.write(names.data(), static_cast<std::streamsize>(names.size()));
  put_zeros(out, index_capacity_ * sizeof(Entry));
}

template <std::size_t D>
void GsdFormat<D>::frame(std::ostream& out, std::uint64_t index, double t,
                         const System<D>& system) {
  if (frames_ == 0) start(out);
  const auto n = static_cast<std::uint32_t>(system.size());
  const Vec<D>& side = system.box.size;
  // HOOMD's box is centred on the origin; a disk's box has Lz = 0, as HOOMD writes 2D boxes.
  std::array<float, 6> box{};
  for (std::size_t k = 0; k < D; ++k) box[k] = static_cast<float>(side[k]);
  // A sheared box as HOOMD's tilted one: the images one box up lie at (xy Ly, Ly).
  const double at = system.stored(t);
  const double shift = shown_shift(system.box, at);
  box[3] = static_cast<float>(shift / side[1]);
  std::vector<float> position(3 * std::size_t{n}), velocity(3 * std::size_t{n}), diameter(n),
      mass(n);
  std::vector<std::int32_t> image(3 * std::size_t{n});
  for (std::uint32_t i = 0; i < n; ++i) {
    std::array<std::int32_t, 3> flags = system.records[i].image;
    Particle<D> p = synchronised(system.particles[i], system.box, at, flags);
    if (shift != 0.0) into_tilted_box(p.position, side, shift, flags);
    for (std::size_t k = 0; k < D; ++k) {
      position[3 * i + k] = static_cast<float>(p.position[k] - 0.5 * side[k]);
      velocity[3 * i + k] = static_cast<float>(p.velocity[k]);
      image[3 * i + k] = flags[k];
    }
    diameter[i] = static_cast<float>(2.0 * p.radius);
    mass[i] = static_cast<float>(system.records[i].mass);
  }
  const std::vector<std::uint32_t> typeid_(n, 0);

  out.seekp(0, std::ios::end);
  std::vector<Entry> added;
  const auto chunk = [&](Chunk id, Type type, std::uint64_t rows, std::uint32_t columns,
                         const auto& write) {
    added.push_back({frames_, rows, static_cast<std::int64_t>(out.tellp()), columns, id, type, 0});
    write();
  };
  chunk(kBox, kFloat, 6, 1, [&] { put(out, box); });
  chunk(kDimensions, kUint8, 1, 1, [&] { put(out, static_cast<std::uint8_t>(D)); });
  chunk(kStep, kUint64, 1, 1, [&] { put(out, index); });
  // HOOMD's boxes are periodic; carom's may have walls, which its readers take from here.
  chunk(kPeriodic, kUint8, 1, 1,
        [&] { put(out, static_cast<std::uint8_t>(system.box.periodic() ? 1 : 0)); });
  chunk(kTime, kDouble, 1, 1, [&] { put(out, t); });
  chunk(kN, kUint32, 1, 1, [&] { put(out, n); });
  chunk(kDiameter, kFloat, n, 1, [&] { put(out, diameter); });
  chunk(kImage, kInt32, n, 3, [&] { put(out, image); });
  chunk(kMass, kFloat, n, 1, [&] { put(out, mass); });
  chunk(kPosition, kFloat, n, 3, [&] { put(out, position); });
  chunk(kTypeid, kUint32, n, 1, [&] { put(out, typeid_); });
  chunk(kTypes, kInt8, 1, 2, [&] { out.write("A", 2); });  // one type, "A", null-terminated
  chunk(kVelocity, kFloat, n, 3, [&] { put(out, velocity); });
  // Chunks with no rows (N = 0) are not indexed: GSD has no empty chunks.
  std::erase_if(added, [](const Entry& e) { return e.n == 0; });

  // The index grows by doubling into a new block at the end; the header points at it last, so
  // that an interruption leaves the previous frames readable.
  const std::uint64_t needed = entries_.size() + added.size();
  if (needed > index_capacity_ || frames_ + 1 >= index_capacity_) {
    index_capacity_ = 2 * std::max(needed, index_capacity_);
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
std::uint64_t GsdFormat<D>::whole_frames_before(std::istream&, double, bool, double) const {
  throw std::invalid_argument(
      "a resumed run cannot continue a .gsd trajectory yet: give --dump a new file (or an .xyz "
      "or .lammpstrj one, which it continues)");
}

template class GsdFormat<2>;
template class GsdFormat<3>;

}  // namespace carom
