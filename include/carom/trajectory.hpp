// Trajectory files that other tools read: snapshots of every disk at chosen times.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <ostream>
#include <string>

#include "carom/system.hpp"

namespace carom {

// Writes one frame per call, each disk at time `t` (computed from its stored state, which is not
// changed, so writing frames cannot change the dynamics). Positions are wrapped into a periodic
// box; z = 0 for the 2D disks.
class TrajectoryWriter {
 public:
  virtual ~TrajectoryWriter() = default;
  void frame(std::ostream& out, double t, const System<2>& system);

 private:
  // A format is a frame header and one line a particle, `at` its position at the frame's time.
  virtual void header(std::ostream& out, double t, const System<2>& system) = 0;
  virtual void line(std::ostream& out, std::size_t index, const Vec<2>& at,
                    const Particle<2>& p) = 0;
};

// The writer for a file name: `.xyz` is extended XYZ (ASE, OVITO), `.lammpstrj` a LAMMPS text
// dump. Throws std::invalid_argument naming the supported endings for anything else.
std::unique_ptr<TrajectoryWriter> trajectory_writer_for(const std::string& path);

}  // namespace carom
