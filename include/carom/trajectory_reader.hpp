// Reading trajectories back: every frame of an extended XYZ file or a GSD file, for carom view
// and carom analyze.
#pragma once

#include <array>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include "carom/vec.hpp"

namespace carom {

// One frame of disks or spheres. Positions and velocities always hold x, y and z: disks lie in the
// plane z = 0 (and box[2] is the lattice's nominal thickness). Positions are in [0, L) in a
// periodic box.
struct Frame {
  double time = 0.0;
  int dimension = 2;  // 2 (disks) or 3 (spheres): the same in every frame of a file
  Vec<3> box;
  bool periodic = false;
  std::vector<Vec<3>> position, velocity;
  std::vector<double> radius;
  std::vector<std::uint32_t> collisions;
  // The box sides each particle crossed (unwrapped position = position + image x box); empty
  // when the file has none.
  std::vector<std::array<std::int32_t, 3>> image;
};

// Reads every frame of an extended XYZ file (as `carom run --dump` writes: pos, and optionally
// velo, radius, collisions and image properties; Lattice, pbc and Time in the comment line).
// Throws InputError with the line for anything else, or for frames whose disk count changes.
// The file holds spheres (dimension 3) if any particle of any frame has a nonzero z position or
// z velocity: disks (carom writes them with z = 0, and a nominal Lz of 1) never do, and spheres
// between walls cannot all sit at z = 0, nor can periodic spheres all stand still in z.
std::vector<Frame> read_xyz_frames(std::istream& in, const std::string& name);

// Reads every frame of a GSD file of the HOOMD schema (carom's --dump FILE.gsd, HOOMD's): a
// periodic box (centred positions moved into [0, L)), velocities, diameters, image flags, and
// the time from log/time (else configuration/step). Chunks a frame lacks come from frame 0, as
// the schema says. Throws InputError naming `path` for anything else, or for frames whose
// particle count or dimension changes.
std::vector<Frame> read_gsd_frames(const std::string& path);

// The frames of the trajectory `path`: GSD for a name ending in .gsd, else extended XYZ.
std::vector<Frame> read_trajectory_frames(const std::string& path);

}  // namespace carom
