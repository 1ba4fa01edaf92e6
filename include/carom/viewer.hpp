// `carom view`: a trajectory turned into one self-contained HTML page that animates it.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "carom/vec.hpp"

namespace carom {

// One frame of disks or spheres. Positions and velocities always hold x, y and z: disks lie in the
// plane z = 0 (and box[2] is the lattice's nominal thickness).
struct Frame {
  double time = 0.0;
  int dimension = 2;  // 2 (disks) or 3 (spheres): the same in every frame of a file
  Vec<3> box;
  bool periodic = false;
  std::vector<Vec<3>> position, velocity;
  std::vector<double> radius;
  std::vector<std::uint32_t> collisions;
};

// Reads every frame of an extended XYZ file (as `carom run --dump` writes: pos, and optionally
// velo, radius and collisions properties; Lattice, pbc and Time in the comment line). Throws
// InputError with the line for anything else, or for frames whose disk count changes.
// The file holds spheres (dimension 3) if any particle of any frame has a nonzero z position or
// z velocity: disks (carom writes them with z = 0, and a nominal Lz of 1) never do, and spheres
// between walls cannot all sit at z = 0, nor can periodic spheres all stand still in z.
std::vector<Frame> read_xyz_frames(std::istream& in, const std::string& name);

// The page: no network, data embedded (base64 float32), play/pause, time slider, speed,
// colour by speed or collision count, and the speed histogram against Maxwell-Boltzmann (2D or
// 3D). Spheres are drawn shaded and depth-sorted in a box the mouse rotates.
void write_viewer_html(std::ostream& out, const std::vector<Frame>& frames);

}  // namespace carom
