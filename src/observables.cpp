#include "carom/observables.hpp"

#include <cmath>
#include <numbers>

namespace carom {

template <std::size_t D>
double kinetic_energy(const System<D>& system) {
  double energy = 0.0;
  for (const Particle<D>& p : system.particles) energy += 0.5 * p.mass * norm2(p.velocity);
  return energy;
}

template <std::size_t D>
Vec<D> momentum(const System<D>& system) {
  Vec<D> total;
  for (const Particle<D>& p : system.particles) total += p.mass * p.velocity;
  return total;
}

template <std::size_t D>
double packing_fraction(const System<D>& system) {
  // Area of a disk, volume of a sphere.
  const double unit_ball = D == 2 ? std::numbers::pi : 4.0 / 3.0 * std::numbers::pi;
  double covered = 0.0, volume = 1.0;
  for (const Particle<D>& p : system.particles) covered += unit_ball * std::pow(p.radius, D);
  for (std::size_t k = 0; k < D; ++k) volume *= system.box.size[k];
  return covered / volume;
}

template <std::size_t D>
Observables<D> measure(const Engine<D>& engine, double elapsed, double kinetic_energy_initial) {
  const System<D>& system = engine.system();
  const RunCounts& counts = engine.counts();
  const auto n = static_cast<double>(system.particles.size());
  double volume = 1.0, wall_measure = 0.0;
  for (std::size_t k = 0; k < D; ++k) volume *= system.box.size[k];
  // The total area (length in 2D) of the walls: two faces normal to each axis.
  for (std::size_t k = 0; k < D; ++k) wall_measure += 2.0 * volume / system.box.size[k];

  Observables<D> o;
  o.elapsed = elapsed;
  o.kinetic_energy_initial = kinetic_energy_initial;
  o.kinetic_energy_final = kinetic_energy(system);
  o.momentum_final = momentum(system);
  o.temperature = 2.0 * o.kinetic_energy_final / (static_cast<double>(D) * n);
  o.packing_fraction = packing_fraction(system);
  if (elapsed > 0.0) {
    const double kinetic = n * o.temperature;
    o.pressure = (kinetic + counts.virial / (static_cast<double>(D) * elapsed)) / volume;
    o.compressibility_factor = kinetic > 0.0 ? o.pressure * volume / kinetic : 0.0;
    o.wall_pressure = system.box.periodic() ? 0.0 : counts.wall_momentum / (elapsed * wall_measure);
    o.collision_rate = 2.0 * static_cast<double>(counts.pair_collisions) / (n * elapsed);
    o.mean_free_time = o.collision_rate > 0.0 ? 1.0 / o.collision_rate : kNever;
  }
  return o;
}

template double kinetic_energy(const System<2>&);
template double kinetic_energy(const System<3>&);
template Vec<2> momentum(const System<2>&);
template Vec<3> momentum(const System<3>&);
template double packing_fraction(const System<2>&);
template double packing_fraction(const System<3>&);
template Observables<2> measure(const Engine<2>&, double, double);
template Observables<3> measure(const Engine<3>&, double, double);

}  // namespace carom
