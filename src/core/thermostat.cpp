#include "carom/core/thermostat.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "carom/core/observables.hpp"
#include "carom/core/random.hpp"

namespace carom {

void check_thermostat(const Thermostat& t) {
  if (t.kind == ThermostatKind::none) return;
  const auto positive = [](double x, const char* what) {
    if (!(x > 0.0) || !std::isfinite(x)) {
      throw std::invalid_argument(
          fmt::format("{} must be a number greater than 0, got {}", what, x));
    }
  };
  positive(t.kT, "the thermostat's kT");
  if (!resets_as_events(t)) positive(t.every, "the thermostat's interval (--thermostat-every)");
  if (t.kind == ThermostatKind::andersen) positive(t.rate, "Andersen's rate (--thermostat-rate)");
}

template <std::size_t D>
void rescale_velocities(System<D>& system, double kT) {
  const double now = kinetic_temperature(system);
  if (!(now > 0.0)) return;
  double mass = 0.0;
  for (const ParticleRecord& r : system.records) mass += r.mass;
  // Only a periodic box keeps its centre of mass's motion out of the temperature.
  const Vec<D> drift = system.box.periodic() ? (1.0 / mass) * peculiar_momentum(system) : Vec<D>{};
  const double scale = std::sqrt(kT / now);
  // In a sheared box, the motion relative to the streaming profile is rescaled.
  for (Particle<D>& p : system.particles) {
    const Vec<D> c = peculiar_velocity(p, system.box);
    p.velocity = streaming_velocity(drift + scale * (c - drift), p, system.box);
  }
}

template <std::size_t D>
std::size_t andersen_resets(System<D>& system, const Thermostat& thermostat, pcg32& rng) {
  const double probability = -std::expm1(-thermostat.rate * thermostat.every);
  std::size_t resets = 0;
  for (std::size_t i = 0; i < system.size(); ++i) {
    if (uniform_deviate(rng) >= probability) continue;
    // In a sheared box, drawn relative to the streaming profile where the particle is.
    Particle<D>& p = system.particles[i];
    p.velocity = streaming_velocity(maxwell_velocity<D>(thermostat.kT, system.records[i].mass, rng),
                                    p, system.box);
    ++resets;
  }
  return resets;
}

double next_reset_delay(const Thermostat& thermostat, std::size_t n, pcg32& rng) {
  return -std::log1p(-uniform_deviate(rng)) / (static_cast<double>(n) * thermostat.rate);
}

template <std::size_t D>
Vec<D> maxwell_velocity(double kT, double mass, pcg32& rng) {
  const double scale = std::sqrt(kT / mass);
  Vec<D> v;
  for (std::size_t k = 0; k < D; ++k) v[k] = scale * normal_deviate(rng);
  return v;
}

template Vec<2> maxwell_velocity<2>(double, double, pcg32&);
template Vec<3> maxwell_velocity<3>(double, double, pcg32&);
template void rescale_velocities(System<2>&, double);
template void rescale_velocities(System<3>&, double);
template std::size_t andersen_resets(System<2>&, const Thermostat&, pcg32&);
template std::size_t andersen_resets(System<3>&, const Thermostat&, pcg32&);

}  // namespace carom
