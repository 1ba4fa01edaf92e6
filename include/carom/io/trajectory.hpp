// Trajectory files that other tools read: snapshots of every particle at chosen times.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <memory>
#include <ostream>
#include <string>

#include "carom/engine/simulation.hpp"

namespace carom {

// A trajectory format. Frames are snapshots at time t, computed from the stored states, which are
// not changed, so writing frames cannot change the dynamics. Positions are wrapped into a periodic
// box, with image flags to unwrap them; disks have z = 0.
template <std::size_t D>
class TrajectoryFormat {
 public:
  virtual ~TrajectoryFormat() = default;
  enum class Velocities { as_stored, at_rest };
  // Frame number `index` of a run writing a frame every `every`: t = index x every.
  void frame(std::ostream& out, std::uint64_t index, double t, const System<D>& system) {
    write_frame(out, index, t, system, Velocities::as_stored);
  }
  // The same with every velocity 0: event chains' frames, whose one moving particle's speed is
  // a unit of the sampler's clock, not a velocity (as their end state has them).
  void frame_at_rest(std::ostream& out, std::uint64_t index, double t, const System<D>& system) {
    write_frame(out, index, t, system, Velocities::at_rest);
  }
  // Throws std::range_error, naming the value, when a frame of `system` at `t` would not read
  // back as written (a number beyond a GSD file's single precision). Text formats write every
  // double as it is.
  virtual void check_frame(const System<D>& /*system*/, double /*t*/) const {}
  // The length of the leading part of a file in this format made of whole frames taken before
  // `t` (or at it, when `inclusive`): what a resumed run keeps before appending its own frames.
  // The format takes up writing after those frames (a GSD file's index). Throws
  // std::invalid_argument for a file it cannot continue.
  virtual std::uint64_t whole_frames_before(std::istream& in, double t, bool inclusive,
                                            double every) = 0;
  // Once the file is cut to that length (and opened for reading and writing, at its end):
  // rewrites what pointed past the cut (a GSD file's header and index). Text formats have
  // nothing to rewrite.
  virtual void continue_after_cut(std::ostream& /*out*/) {}

 private:
  virtual void write_frame(std::ostream& out, std::uint64_t index, double t,
                           const System<D>& system, Velocities velocities) = 0;
};

// The format for a file name: `.xyz` is extended XYZ (ASE, OVITO), `.lammpstrj` a LAMMPS text
// dump, `.gsd` HOOMD-blue's GSD (binary: the stream must be seekable). Throws
// std::invalid_argument naming the supported endings for anything else.
template <std::size_t D>
std::unique_ptr<TrajectoryFormat<D>> trajectory_format_for(const std::string& path);

// Writes a frame every `every` (at t = 0, every, 2 every, ...) and flushes it, so that the frames
// of an interrupted run are on disk. Throws std::runtime_error when the stream fails.
template <std::size_t D>
class FrameWriter final : public Observer<D> {
 public:
  FrameWriter(std::ostream& out, std::unique_ptr<TrajectoryFormat<D>> format, double every)
      : Observer<D>(Trigger::every_time(every)), out_(out), format_(std::move(format)) {}
  void observe(const Simulation<D>& simulation) override;

 private:
  std::ostream& out_;
  std::unique_ptr<TrajectoryFormat<D>> format_;
};

}  // namespace carom
