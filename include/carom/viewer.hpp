// `carom view`: a trajectory turned into one self-contained HTML page that animates it.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "carom/vec.hpp"

namespace carom {

struct Frame {
  double time = 0.0;
  Vec<2> box;
  bool periodic = false;
  std::vector<Vec<2>> position, velocity;
  std::vector<double> radius;
  std::vector<std::uint32_t> collisions;
};

// Reads every frame of an extended XYZ file (as `carom run --dump` writes: pos, and optionally
// velo, radius and collisions properties; Lattice, pbc and Time in the comment line). Throws
// InputError with the line for anything else, or for frames whose disk count changes.
std::vector<Frame> read_xyz_frames(std::istream& in, const std::string& name);

// The page: no network, data embedded (base64 float32), play/pause, time slider, speed,
// colour by speed or collision count, and the speed histogram against Maxwell-Boltzmann.
void write_viewer_html(std::ostream& out, const std::vector<Frame>& frames);

}  // namespace carom
