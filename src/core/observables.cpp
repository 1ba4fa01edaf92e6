#include "carom/core/observables.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "carom/core/physics.hpp"

namespace carom {

template <std::size_t D>
double kinetic_energy(const System<D>& system) {
  double energy = 0.0;
  for (std::size_t i = 0; i < system.size(); ++i) {
    energy += 0.5 * system.records[i].mass * norm2(system.particles[i].velocity);
  }
  return energy;
}

template <std::size_t D>
Vec<D> momentum(const System<D>& system) {
  Vec<D> total;
  for (std::size_t i = 0; i < system.size(); ++i) {
    total += system.records[i].mass * system.particles[i].velocity;
  }
  return total;
}

template <std::size_t D>
double packing_fraction(const System<D>& system) {
  // Area of a disk, volume of a sphere.
  const double unit_ball = D == 2 ? std::numbers::pi : 4.0 / 3.0 * std::numbers::pi;
  double covered = 0.0;
  for (const Particle<D>& p : system.particles) covered += unit_ball * std::pow(p.radius, D);
  return covered / box_volume(system.box);
}

template <std::size_t D>
double degrees_of_freedom(const System<D>& system) {
  const auto n = static_cast<double>(system.size());
  return static_cast<double>(D) * (system.box.periodic() ? n - 1.0 : n);
}

template <std::size_t D>
Vec<D> peculiar_momentum(const System<D>& system) {
  Vec<D> total;
  for (std::size_t i = 0; i < system.size(); ++i) {
    total += system.records[i].mass * peculiar_velocity(system.particles[i], system.box);
  }
  return total;
}

template <std::size_t D>
double kinetic_temperature(const System<D>& system) {
  const double dof = degrees_of_freedom(system);
  if (!(dof > 0.0)) return 0.0;
  double energy = 0.0;
  for (std::size_t i = 0; i < system.size(); ++i) {
    energy +=
        0.5 * system.records[i].mass * norm2(peculiar_velocity(system.particles[i], system.box));
  }
  if (system.box.periodic()) {
    double mass = 0.0;
    for (const ParticleRecord& r : system.records) mass += r.mass;
    energy -= 0.5 * norm2(peculiar_momentum(system)) / mass;  // the centre of mass's share
  }
  return 2.0 * energy / dof;
}

template <std::size_t D>
Observables<D> measure(const System<D>& system, const Measurement& measurement, double now) {
  const Counts& counts = measurement.counts;
  const auto n = static_cast<double>(system.size());
  const double volume = box_volume(system.box);
  double wall_measure = 0.0;
  // The total area (length in 2D) of the walls: two faces normal to each axis.
  for (std::size_t k = 0; k < D; ++k) wall_measure += 2.0 * volume / system.box.size[k];

  Observables<D> o;
  o.elapsed = now - measurement.start_time;
  o.kinetic_energy_initial = measurement.kinetic_energy_initial;
  o.kinetic_energy_final = kinetic_energy(system);
  o.momentum_final = peculiar_momentum(system);
  o.degrees_of_freedom = degrees_of_freedom(system);
  o.temperature = kinetic_temperature(system);
  o.packing_fraction = packing_fraction(system);
  if (o.elapsed > 0.0) {
    const double kinetic = n * o.temperature;
    o.pressure = pressure_over<D>(counts.virial, o.elapsed, kinetic, volume);
    o.compressibility_factor = compressibility_factor_of(o.pressure, kinetic, volume);
    o.wall_pressure =
        system.box.periodic() ? 0.0 : counts.wall_momentum / (o.elapsed * wall_measure);
    o.collision_rate = 2.0 * static_cast<double>(counts.pair_collisions) / (n * o.elapsed);
    o.mean_free_time = o.collision_rate > 0.0 ? 1.0 / o.collision_rate : kNever;
  }
  if (counts.fluxes) {
    const Fluxes& fluxes = *counts.fluxes;  // brought to `now`
    const double elapsed = now - fluxes.since;
    if (elapsed > 0.0) {
      SymmetricTensor p = fluxes.stress_moment();
      for (double& component : p) component /= elapsed * volume;
      o.pressure_tensor = p;
    }
  }
  return o;
}

template <std::size_t D>
Observables<D> at_unit_temperature(Observables<D> o, const Measurement& measurement,
                                   double number_density) {
  const double kT = o.temperature;
  if (kT > 0.0) {
    o.pressure /= kT;
    if (o.pressure_tensor) {
      for (double& component : *o.pressure_tensor) component /= kT;
    }
  } else if (o.elapsed > 0.0 && measurement.counts.pair_collisions == 0) {
    o.compressibility_factor = 1.0;  // a lone particle: no lift, and no temperature to divide by
    o.pressure = number_density;
  }
  o.temperature = 1.0;
  if (measurement.counts.fluxes) {
    const Fluxes& fluxes = *measurement.counts.fluxes;
    std::array<double, D> z{};
    for (std::size_t k = 0; k < D; ++k) {
      // Diagonal components first: xx, yy, zz at 0, 1, 2.
      const double moved = fluxes.kinetic_stress[k];  // m v x (the displacement along k)
      z[k] = moved > 0.0 ? 1.0 + fluxes.collisional_stress[k] / moved
                         : std::numeric_limits<double>::quiet_NaN();
    }
    o.directional_z = z;
    if (o.pressure_tensor) {
      SymmetricTensor& p = *o.pressure_tensor;
      for (std::size_t k = 0; k < D; ++k) p[k] = number_density * z[k];
      // Off the diagonal, the lifts' sym(r dp) over the moves along both axes: the lifts of
      // moves along a give r_b dp_a, those along b r_a dp_b, each over its own displacement.
      for (const std::size_t c : tensor_components<D>()) {
        if (c < 3) continue;
        const auto [a, b] = kTensorAxes[c];
        const double moved = fluxes.kinetic_stress[a] + fluxes.kinetic_stress[b];
        p[c] = moved > 0.0 ? number_density * 2.0 * fluxes.collisional_stress[c] / moved
                           : std::numeric_limits<double>::quiet_NaN();
      }
    }
  }
  return o;
}

template Observables<2> at_unit_temperature(Observables<2>, const Measurement&, double);
template Observables<3> at_unit_temperature(Observables<3>, const Measurement&, double);
template double kinetic_energy(const System<2>&);
template double kinetic_energy(const System<3>&);
template Vec<2> momentum(const System<2>&);
template Vec<3> momentum(const System<3>&);
template double packing_fraction(const System<2>&);
template double packing_fraction(const System<3>&);
template double degrees_of_freedom(const System<2>&);
template double degrees_of_freedom(const System<3>&);
template Vec<2> peculiar_momentum(const System<2>&);
template Vec<3> peculiar_momentum(const System<3>&);
template double kinetic_temperature(const System<2>&);
template double kinetic_temperature(const System<3>&);
template Observables<2> measure(const System<2>&, const Measurement&, double);
template Observables<3> measure(const System<3>&, const Measurement&, double);

}  // namespace carom
