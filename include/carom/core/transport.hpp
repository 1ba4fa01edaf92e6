// Transport coefficients from an equilibrium run, by the Einstein-Helfand route: the self-
// diffusion coefficient from the mean-square displacement, the shear viscosity from the moment
// of the pressure tensor and the thermal conductivity from the moment of the heat flux (both
// kept event by event, collisional parts included: fluxes.hpp). For a moment G whose rate is a
// flux J, <(G(t + tau) - G(t))^2> grows as 2 tau times the integral of J's autocorrelation (the
// Green-Kubo integral) once tau is past J's correlation time, so
//   D = d<|dr|^2>/dtau / (2 d),   eta = d<dG_xy^2>/dtau / (2 V kT),   lambda = d<dH_x^2>/dtau /
//   (2 V kT^2),
// each slope taken between the lags tau/2 and tau (the short-time curvature cancels). The
// measurement window is cut into blocks; each block gives an estimate, and the spread of the
// blocks gives the error. The shear components averaged are every off-diagonal one and the
// halved differences of the diagonal ones (an off-diagonal component in axes turned by 45
// degrees); the heat flux's every component. The heat flux is the energy's, which is the heat's
// when the total momentum is zero (as carom init makes it): a periodic box only.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "carom/core/fluxes.hpp"

namespace carom {

// The mean over origins j of (x[j + lag] - x[j])^2, j + lag within x.
double mean_square_increment(std::span<const double> x, std::size_t lag);

// The growth rate of mean_square_increment between lag / 2 and lag samples `spacing` apart.
double einstein_helfand_slope(std::span<const double> x, std::size_t lag, double spacing);

// One block's estimates.
struct TransportBlock {
  double self_diffusion = 0.0;
  double shear_viscosity = 0.0;
  double thermal_conductivity = 0.0;
  friend bool operator==(const TransportBlock&, const TransportBlock&) = default;
};

// One sample of the moments: the stress moment's components (xx, yy, zz, xy, xz, yz) and the
// heat moment's (x, y, z).
using MomentSample = std::array<double, 9>;

// A block's shear viscosity and thermal conductivity from its samples (spacing apart), in a box
// of `volume` at temperature kT; the moments' lag is a quarter of the block.
template <std::size_t D>
std::array<double, 2> block_viscosity_and_conductivity(std::span<const MomentSample> samples,
                                                       double spacing, double volume, double kT);

// Where a run's transport measurement stands: what a checkpoint keeps to continue it exactly.
struct TransportRecord {
  double spacing = 0.0;                // between samples
  // The spacing of a window long enough for TransportMeter's least blocks of its lag (0: not
  // kept: a checkpoint of an older carom): a run continued to another end keeps the record
  // where that end gives `spacing` too.
  double lag_spacing = 0.0;
  std::size_t block_samples = 0;       // samples a block spans (its last is the next one's first)
  std::vector<MomentSample> samples;   // the block under way
  std::vector<double> origin;          // the unwrapped positions at its start, N x D
  double half_msd = 0.0;               // its mean-square displacement at its middle
  std::vector<TransportBlock> blocks;  // those done
  friend bool operator==(const TransportRecord&, const TransportRecord&) = default;
};

// The coefficients over the blocks done: means and standard errors; Yeh and Hummer's
// finite-size correction of D (cubic boxes of spheres), and the ratios to Enskog's values
// (spheres of one diameter and mass: the Chapman-Enskog first approximations times Enskog's
// density factors, with the Carnahan-Starling contact value).
struct TransportEstimate {
  std::size_t blocks = 0;
  double self_diffusion = 0.0, self_diffusion_error = 0.0;
  double shear_viscosity = 0.0, shear_viscosity_error = 0.0;
  double thermal_conductivity = 0.0, thermal_conductivity_error = 0.0;
  // D + 2.837297 kT / (6 pi eta L): D of an infinite system.
  std::optional<double> self_diffusion_corrected;
  std::optional<double> enskog_self_diffusion, enskog_shear_viscosity, enskog_thermal_conductivity;
};

// The Enskog values for hard spheres of diameter sigma and mass m at packing fraction phi and
// temperature kT: {D, eta, lambda}.
std::array<double, 3> enskog_spheres(double phi, double sigma, double mass, double kT);

// Enskog's mean time between a particle's collisions for disks (dimension 2) or spheres (3) of
// diameter sigma and mass m at packing fraction phi and temperature kT: 1 / omega, omega =
// 2 sqrt(pi) n sigma chi sqrt(kT / m) for disks (chi Henderson's contact value) and
// 4 sqrt(pi) n sigma^2 chi sqrt(kT / m) for spheres (Carnahan-Starling's). Infinite at rest.
double enskog_collision_time(std::size_t dimension, double phi, double sigma, double mass,
                             double kT);

// Yeh and Hummer's constant for a cubic periodic box.
inline constexpr double kYehHummerXi = 2.837297;

}  // namespace carom
