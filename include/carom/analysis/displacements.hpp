// The particles' displacements over lags of whole frames, which the mean-square displacement, the
// non-Gaussian parameter and the self-intermediate scattering function all average: the frames'
// unwrapped positions, the lags they are taken over, and the moments of the displacements.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "carom/io/trajectory_reader.hpp"

namespace carom {

// The unwrapped positions (position + image x box in a periodic box; in a sheared one, plus
// image_y x shear_shift along x) of frames evenly spaced in time.
struct UnwrappedTrajectory {
  std::size_t frames = 0, particles = 0, dimension = 2;
  double spacing = 0.0;           // the time between frames; 0 for a single frame
  std::vector<double> positions;  // coordinate k of particle i in frame f at (f N + i) D + k

  const double* frame(std::size_t f) const { return &positions[f * particles * dimension]; }
};

// Throws std::invalid_argument, naming `what` needs it ("the MSD"), when there is no frame, when
// the frames are not evenly spaced in time, or when a periodic trajectory has no image flags.
UnwrappedTrajectory unwrap(const std::vector<Frame>& frames, std::string_view what);

// Moves every frame by its centre of mass's displacement since the first (every particle
// weighed alike): displacements from the centre of mass.
void remove_centre_of_mass_motion(UnwrappedTrajectory& trajectory);

// The square of how far the centre of mass (every particle weighed alike) moved from the first
// frame of `trajectory` to its last: dynamics in a periodic box keeps it still (to rounding with
// equal masses), event chains move it along +x, +y (+z) by about a mean diameter a unit of time.
double centre_of_mass_shift_squared(const UnwrappedTrajectory& trajectory);

// The lags (in frames) displacements are averaged over for `frames` frames: every lag up to 200
// frames, beyond that about 100 lags evenly spaced in log up to the longest. Starts at lag 0.
std::vector<std::size_t> displacement_lags(std::size_t frames);

// At each lag of displacement_lags: the lag's time and the mean of |dr|^2 and of |dr|^4 over every
// particle and every time origin.
struct DisplacementMoments {
  std::vector<std::size_t> lags;
  std::vector<double> t, r2, r4;
};
DisplacementMoments displacement_moments(const UnwrappedTrajectory& trajectory);

}  // namespace carom
