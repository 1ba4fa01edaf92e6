// Equations of state of the equal hard-particle fluid, Z = PV / NkT against the packing fraction
// eta: what a measured Z is compared with (the sweep's report, docs/validation.md).
#pragma once

#include <optional>

namespace carom {

// Hard disks: Henderson's (Mol. Phys. 30, 971 (1975)) with the eta^4 correction of Mol. Phys.
// 34, 301 (1977), within about 0.1 % of simulations up to eta = 0.55.
constexpr double henderson_z(double eta) {
  const double free = 1.0 - eta;
  return (1.0 + eta * eta / 8.0) / (free * free) -
         0.043 * eta * eta * eta * eta / (free * free * free);
}

// Hard spheres: Kolafa, Labik and Malijevsky (Phys. Chem. Chem. Phys. 6, 2335 (2004)), within
// about 0.01 % of simulations in the stable fluid (eta up to 0.49).
constexpr double kolafa_labik_malijevsky_z(double eta) {
  const double free = 1.0 - eta;
  return (1.0 + eta + eta * eta - 2.0 / 3.0 * eta * eta * eta * (1.0 + eta)) / (free * free * free);
}

// The one of `dimension` (2 or 3), or nullopt.
constexpr std::optional<double> hard_particle_z(int dimension, double eta) {
  if (dimension == 2) return henderson_z(eta);
  if (dimension == 3) return kolafa_labik_malijevsky_z(eta);
  return std::nullopt;
}

}  // namespace carom
