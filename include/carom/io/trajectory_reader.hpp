// Reading trajectories back: every frame of an extended XYZ file or a GSD file, for carom view
// and carom analyze.
#pragma once

#include <array>
#include <cstdint>
#include <istream>
#include <optional>
#include <string>
#include <vector>

#include "carom/core/vec.hpp"

namespace carom {

// One frame of disks or spheres. Positions and velocities always hold x, y and z: disks lie in the
// plane z = 0 (and box[2] is the lattice's nominal thickness). Positions are in [0, L) in a
// periodic box.
struct Frame {
  double time = 0.0;
  int dimension = 2;  // 2 (disks) or 3 (spheres): the same in every frame of a file
  Vec<3> box;
  bool periodic = false;
  // The x shift of the box's images one box up, as a sheared run's frame has it (Lees-Edwards;
  // a tilted box of tilt shear_shift / Ly): the lattice of images is (Lx, 0, 0), (shear_shift,
  // Ly, 0), (0, 0, Lz). 0 in a rectangular box.
  double shear_shift = 0.0;
  std::vector<Vec<3>> position, velocity;
  std::vector<double> radius;
  std::vector<std::uint32_t> collisions;
  // The box sides each particle crossed (unwrapped position = position + image x box, plus
  // image_y x shear_shift along x); empty when the file has none.
  std::vector<std::array<std::int32_t, 3>> image;
  // The species: each particle's index into type_names (empty: every particle type 0), and the
  // names (empty: one, "A"), as GSD's particles/typeid and types, an XYZ file's species column,
  // a LAMMPS dump's type.
  std::vector<std::uint32_t> type;
  std::vector<std::string> type_names;
};

// Reads every frame of an extended XYZ file (as `carom run --dump` writes: pos, and optionally
// velo, radius, collisions and image properties; Lattice, pbc and Time in the comment line).
// Throws InputError with the line for anything else, or for frames whose disk count changes.
// The file holds spheres (dimension 3) if any particle of any frame has a nonzero z position or
// z velocity: disks (carom writes them with z = 0, and a nominal Lz of 1) never do, and spheres
// between walls cannot all sit at z = 0, nor can periodic spheres all stand still in z.
std::vector<Frame> read_xyz_frames(std::istream& in, const std::string& name);

// Which frames of a trajectory to read: first, first + stride, ... before `last` (nullopt: to
// the end).
struct FrameSelection {
  std::size_t first = 0;
  std::optional<std::size_t> last;
  std::size_t stride = 1;
};

// Reads the selected frames of a GSD file of the HOOMD schema (carom's --dump FILE.gsd, HOOMD's):
// a periodic box (centred positions moved into [0, L)), velocities, diameters, image flags, and
// the time from log/time (else configuration/step). Chunks a frame lacks come from frame 0, else
// they take the schema's defaults (position and velocity 0, diameter and mass 1, image 0), as
// HOOMD's readers do. Throws InputError naming `path` for anything else, for frames whose
// particle count or dimension changes, or for frames that would take more than half of this
// machine's memory once expanded (a file of 2.5 MB whose frames lean on a large frame 0 can ask
// for tens of GB).
std::vector<Frame> read_gsd_frames(const std::string& path, const FrameSelection& selection = {});

// The selected frames of the trajectory `path`: GSD for a name ending in .gsd, else extended XYZ
// (whose frames take about what the file does).
std::vector<Frame> read_trajectory_frames(const std::string& path,
                                          const FrameSelection& selection = {});

}  // namespace carom
