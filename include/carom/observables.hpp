// Thermodynamic observables measured from a run: energies, temperature, pressure, collision
// rate. Reduced units: lengths in the units of the input, masses in units of the particle mass
// (1 in the classic format), kT in units of mass x velocity^2.
#pragma once

#include <cstddef>

#include "carom/engine.hpp"

namespace carom {

template <std::size_t D>
double kinetic_energy(const System<D>& system);

template <std::size_t D>
Vec<D> momentum(const System<D>& system);

// Fraction of the box covered by the particles (area in 2D, volume in 3D).
template <std::size_t D>
double packing_fraction(const System<D>& system);

template <std::size_t D>
struct Observables {
  double elapsed = 0.0;  // the time over which rates and pressures are measured
  double kinetic_energy_initial = 0.0;
  double kinetic_energy_final = 0.0;
  Vec<D> momentum_final;
  double temperature = 0.0;  // kT = sum m v^2 / (D N), at the end
  // From the collision virial: P V = N kT + (sum over collisions of r_ij . dp_i) / (D elapsed).
  double pressure = 0.0;
  double compressibility_factor = 0.0;  // Z = P V / (N kT)
  // Box with walls: the momentum given to the walls per unit time and unit wall length (area).
  double wall_pressure = 0.0;
  double collision_rate = 0.0;  // pair collisions per particle per unit time: 2 C / (N elapsed)
  double mean_free_time = 0.0;  // 1 / collision_rate
  double packing_fraction = 0.0;
};

// The observables of `engine` since the moment its counts started (see Engine::reset_counts),
// `elapsed` time ago, when the kinetic energy was `kinetic_energy_initial`.
template <std::size_t D>
Observables<D> measure(const Engine<D>& engine, double elapsed, double kinetic_energy_initial);

}  // namespace carom
