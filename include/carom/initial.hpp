// Start configurations: non-overlapping disks at a chosen packing fraction with
// Maxwell-Boltzmann velocities, reproducible bit for bit from a seed.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>

#include "carom/system.hpp"

namespace carom {

enum class Placement {
  automatic,  // random where that works (packing fraction <= 0.4), else the lattice
  random,     // random sequential placement
  lattice,    // a triangular lattice, which reaches close packing
};

struct InitialOptions {
  std::uint64_t n = 0;
  double packing_fraction = 0.0;
  std::optional<Vec<2>> box;     // the box; else from the packing fraction and `aspect`
  double aspect = 1.0;           // Lx / Ly when the box is derived
  std::optional<double> radius;  // the mean radius; default 0.5 (diameter 1), or derived
                                 // from the packing fraction when the box is given
  double polydispersity = 0.0;   // standard deviation of the radius / its mean (uniform)
  double temperature = 1.0;      // kT, masses 1
  std::uint64_t seed = 1;
  Boundary boundary = Boundary::walls;
  Placement placement = Placement::automatic;
};

// A request that cannot be met (packing fraction above close packing, a random placement that
// jams, conflicting sizes), with a message saying why.
class InitialError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Close packing of equal disks: the triangular lattice, pi / (2 sqrt 3).
inline constexpr double kClosePacking = 0.9068996821171089;

// Velocities are Maxwell-Boltzmann at `temperature`, shifted to zero total momentum and scaled so
// that sum m v^2 / (2 N) = kT exactly. Radii (polydisperse) are uniform around the mean.
System<2> make_initial(const InitialOptions& options);

}  // namespace carom
