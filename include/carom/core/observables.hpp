// Thermodynamic observables measured from a run: energies, temperature, pressure, collision
// rate. Reduced units: lengths in the units of the input, masses in units of the particle mass
// (1 in the classic format), kT in units of mass x velocity^2.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>

#include "carom/core/measurement.hpp"
#include "carom/core/physics.hpp"
#include "carom/core/system.hpp"

namespace carom {

template <std::size_t D>
double kinetic_energy(const System<D>& system);

template <std::size_t D>
Vec<D> momentum(const System<D>& system);

// Fraction of the box covered by the particles (area in 2D, volume in 3D).
template <std::size_t D>
double packing_fraction(const System<D>& system);

// Kinetic degrees of freedom: D N with walls; D (N - 1) in a periodic box, where the total
// momentum is conserved and the motion of the centre of mass carries no temperature.
template <std::size_t D>
double degrees_of_freedom(const System<D>& system);

// The total momentum relative to the streaming profile of a sheared box (else momentum()):
// what a sheared run without a thermostat conserves, as long as no momentum flows along y.
template <std::size_t D>
Vec<D> peculiar_momentum(const System<D>& system);

// kT from the kinetic energy in the centre-of-mass frame over the degrees of freedom (0 for a
// single particle in a periodic box, which has none); in a sheared box, from the velocities
// relative to the streaming profile.
template <std::size_t D>
double kinetic_temperature(const System<D>& system);

template <std::size_t D>
struct Observables {
  double elapsed = 0.0;  // the time over which rates and pressures are measured
  double kinetic_energy_initial = 0.0;
  double kinetic_energy_final = 0.0;
  Vec<D> momentum_final;  // relative to the streaming profile in a sheared box
  double degrees_of_freedom = 0.0;
  double temperature = 0.0;  // kinetic_temperature() at the end
  // From the collision virial: P V = N kT + (sum over collisions of r_ij . dp_i) / (D elapsed).
  // With the D (N - 1) temperature in a periodic box this is the exact-N pressure that Monte
  // Carlo gives at the same N (Li et al. 2022), not one biased by 1/N.
  double pressure = 0.0;
  double compressibility_factor = 0.0;  // Z = P V / (N kT); NaN (undefined) when kT = 0
  // Box with walls: the momentum given to the walls per unit time and unit wall length (area).
  double wall_pressure = 0.0;
  double collision_rate = 0.0;     // pair collisions per particle per unit time: 2 C / (N elapsed)
  double mean_free_time = kNever;  // 1 / collision_rate; never (json null) before a collision
  double packing_fraction = 0.0;
  // When the run keeps its fluxes (Simulation::track_fluxes): the pressure tensor averaged over
  // the window (from when the fluxes began, if later), kinetic plus collisional (fluxes.hpp).
  // Its trace over D is the pressure but for the kinetic part, which here is the lab frame's
  // sum m v v averaged in time rather than N kT.
  std::optional<SymmetricTensor> pressure_tensor;
  // Event chains (at_unit_temperature): Z along each axis (x, y[, z]), 1 + (the lifts' virial
  // along it) / (the displacement along it), from the fluxes (Michel, Kapfer and Krauth, J. Chem.
  // Phys. 140, 054116 (2014)); empty for dynamics.
  std::optional<std::array<double, D>> directional_z;
};

// The pressure over a stretch of time `elapsed` whose pair collisions' virial is `virial`, with
// `kinetic` = N kT, in a box of volume `volume`: (N kT + virial / (D elapsed)) / V.
template <std::size_t D>
double pressure_over(double virial, double elapsed, double kinetic, double volume) {
  return (kinetic + virial / (static_cast<double>(D) * elapsed)) / volume;
}

// Z = P V / (N kT) for the pressure `pressure` with `kinetic` = N kT, in a box of volume
// `volume`: NaN without a temperature.
inline double compressibility_factor_of(double pressure, double kinetic, double volume) {
  return kinetic > 0.0 ? pressure * volume / kinetic : std::numeric_limits<double>::quiet_NaN();
}

// The observables of `system` at time `now` over the window `measurement` opened.
template <std::size_t D>
Observables<D> measure(const System<D>& system, const Measurement& measurement, double now);

// Event-chain Monte Carlo samples positions at kT = 1. Measured as dynamics (measure()), its one
// moving particle has the kinetic temperature m v^2 / (D N), a unit of the sampler's clock rather
// than of the system; Z = 1 + (the lifts' virial) / (v^2 elapsed) comes out exact. These are the
// same observables in kT = 1: the pressure and its tensor are beta P, the temperature 1, and the
// window's fluxes give Z along each axis. The tensor's diagonal is beta P along each axis,
// `number_density` times that Z (NaN along an axis no chain moved along): the displacement along
// an axis, not the time, is what its lifts are measured against, and a stretch whose chains did
// not move as far along every axis (part of a turn of chains) weighs them differently; off the
// diagonal, N / V 2 W_ab / (K_aa + K_bb), the lifts' sym(r dp) over the moves along both axes
// (NaN where neither moved). Z, rates and the packing are unchanged, but for a lone particle,
// whose motion is its centre of mass's (no kinetic temperature) and which is never lifted: Z = 1
// and beta P = `number_density`.
template <std::size_t D>
Observables<D> at_unit_temperature(Observables<D> o, const Measurement& measurement,
                                   double number_density);

}  // namespace carom
