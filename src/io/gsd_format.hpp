// HOOMD-blue's GSD trajectories (read by HOOMD, OVITO, freud, mdtraj), written by carom's own
// implementation of the documented file layer (GSD 2.0) and HOOMD schema (1.4): a 256-byte
// header, the names of the data chunks (null-separated), a block of 32-byte index entries sorted
// by frame, and the chunks themselves, appended frame after frame.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "carom/io/trajectory.hpp"

namespace carom {

// The file layer's constants, which the writer (gsd_writer.cpp) and the reader (gsd_reader.cpp)
// share.
namespace gsd {
static_assert(std::endian::native == std::endian::little, "GSD files are little-endian");
inline constexpr std::uint64_t kMagic = 0x65DF65DF65DF65DFull;
inline constexpr std::uint64_t kNameBlock = 64;  // the namelist's size is a multiple of this
inline constexpr std::uint64_t kHeaderSize = 256;
// Bytes per element of each GSD type (0: not a type).
inline constexpr std::array<std::uint64_t, 11> kTypeSize = {0, 1, 2, 4, 8, 1, 2, 4, 8, 4, 8};
}  // namespace gsd

template <std::size_t D>
class GsdFormat final : public TrajectoryFormat<D> {
 public:
  // `full_precision`: every frame also holds carom's own double-precision copy of the box sides,
  // positions (in carom's box [0, L)), velocities, diameters and masses (log/carom/box, ...,
  // which HOOMD keeps as logged quantities and other readers pass over), so that a start read
  // from it is the state written, to the last bit (read_gsd_start). A run's --final file has
  // them; its --dump frames, many and read by other programs, do not.
  explicit GsdFormat(bool full_precision = false) : full_precision_(full_precision) {}
  // Appends frame `index` (HOOMD's configuration/step) at time t (log/time) and updates the
  // index and header in place, so that the file is a valid GSD file after every frame: `out`
  // must be seekable (a file or a string stream opened in binary mode). Throws std::range_error
  // (check_frame's), before writing anything, for a frame whose numbers single precision cannot
  // hold. (frame and frame_at_rest write through write_frame.)
  // Every number of the frame in single precision, as the schema stores them: beyond float's
  // range it would be written as inf, and a positive size (a box side, a diameter, a mass) that
  // rounds to 0 as 0, which no reader takes.
  void check_frame(const System<D>& system, double t) const override;
  // Takes up a file carom wrote (its chunks and name list): its frames up to `t` are kept, and
  // the index they use is the one the next frames extend, as if the writer had written them.
  // Throws std::invalid_argument for a GSD file of another program's.
  std::uint64_t whole_frames_before(std::istream& in, double t, bool inclusive,
                                    double every) override;
  // Zeroes the index entries of the frames cut off and points the header at the index of the
  // frames kept: the file is then, byte for byte, the one a run never interrupted had written
  // up to there.
  void continue_after_cut(std::ostream& out) override;

  struct Entry {  // the on-disk index entry
    std::uint64_t frame, n;
    std::int64_t location;
    std::uint32_t m;
    std::uint16_t id;
    std::uint8_t type, flags;
    friend bool operator==(const Entry&, const Entry&) = default;
  };
  static_assert(sizeof(Entry) == 32);

 private:
  using Velocities = typename TrajectoryFormat<D>::Velocities;
  void write_frame(std::ostream& out, std::uint64_t index, double t, const System<D>& system,
                   Velocities velocities) override;
  // A frame's chunks as stored (single precision where the schema has it).
  struct Values;
  Values values(double t, const System<D>& system, Velocities velocities) const;
  void start(std::ostream& out);
  void write_header(std::ostream& out) const;

  bool full_precision_ = false;
  std::uint64_t frames_ = 0;
  std::uint64_t index_location_ = 0, index_capacity_ = 0;
  std::uint64_t namelist_location_ = 0, namelist_blocks_ = 0;
  std::vector<Entry> entries_;
};

}  // namespace carom
