// `carom view`: a trajectory turned into one self-contained HTML page that animates it.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "carom/io/trajectory_reader.hpp"

namespace carom {

// The page: no network, data embedded (base64 float32), play/pause, time slider, speed,
// colour by speed or collision count, and the speed histogram against Maxwell-Boltzmann (2D or
// 3D). Spheres are drawn shaded and depth-sorted in a box the mouse rotates.
void write_viewer_html(std::ostream& out, const std::vector<Frame>& frames);

}  // namespace carom
