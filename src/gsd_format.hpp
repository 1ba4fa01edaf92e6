// HOOMD-blue's GSD trajectories (read by HOOMD, OVITO, freud, mdtraj), written by carom's own
// implementation of the documented file layer (GSD 2.0) and HOOMD schema (1.4): a 256-byte
// header, the names of the data chunks (null-separated), a block of 32-byte index entries sorted
// by frame, and the chunks themselves, appended frame after frame.
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

#include "carom/trajectory.hpp"

namespace carom {

// The file layer's constants, which the writer (gsd_writer.cpp) and the reader (gsd_reader.cpp)
// share.
namespace gsd {
static_assert(std::endian::native == std::endian::little, "GSD files are little-endian");
inline constexpr std::uint64_t kMagic = 0x65DF65DF65DF65DFull;
inline constexpr std::uint64_t kNameBlock = 64;  // the namelist's size is a multiple of this
inline constexpr std::uint64_t kHeaderSize = 256;
}  // namespace gsd

template <std::size_t D>
class GsdFormat final : public TrajectoryFormat<D> {
 public:
  // Appends frame `index` (HOOMD's configuration/step) at time t (log/time) and updates the
  // index and header in place, so that the file is a valid GSD file after every frame: `out`
  // must be seekable (a file or a string stream opened in binary mode).
  void frame(std::ostream& out, std::uint64_t index, double t, const System<D>& system) override;
  // A GSD file is not continued by a resumed run yet: throws std::invalid_argument.
  std::uint64_t whole_frames_before(std::istream& in, double t, bool inclusive,
                                    double every) const override;

  struct Entry {  // the on-disk index entry
    std::uint64_t frame, n;
    std::int64_t location;
    std::uint32_t m;
    std::uint16_t id;
    std::uint8_t type, flags;
  };
  static_assert(sizeof(Entry) == 32);

 private:
  void start(std::ostream& out);
  void write_header(std::ostream& out) const;

  std::uint64_t frames_ = 0;
  std::uint64_t index_location_ = 0, index_capacity_ = 0;
  std::uint64_t namelist_location_ = 0, namelist_blocks_ = 0;
  std::vector<Entry> entries_;
};

}  // namespace carom
