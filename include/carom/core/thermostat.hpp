// Thermostats: what holds a run at a temperature kT, acting on the velocities at the instants
// t = every, 2 every, ... (counted from t = 0) between collisions. Rescaling multiplies every
// velocity relative to the centre of mass by one factor, so that the kinetic temperature is kT
// exactly (Berendsen's with a coupling time of one step); Andersen's (in its "massive" form:
// Andersen, J. Chem. Phys. 72, 2384 (1980); Tanaka, Yokota and Mochizuki) gives each particle,
// with probability 1 - exp(-rate x every), a new velocity drawn from the Maxwell-Boltzmann
// distribution at kT, from a pcg32 stream of its own seed that a checkpoint carries on. Without
// an interval (every = 0), Andersen's resets are events of their own, as in his paper: each
// particle is reset at the times of a Poisson process of its rate, one particle at a time (the
// whole system's resets come at rate N x rate, each to a particle drawn at random), so that
// collisions and resets interleave as they would in continuous time. Both also drive an
// inelastic gas to a steady state.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <pcg_random.hpp>
#include <string_view>
#include <utility>

#include "carom/core/names.hpp"
#include "carom/core/system.hpp"

namespace carom {

enum class ThermostatKind { none, rescale, andersen };

template <>
struct EnumNames<ThermostatKind> {
  static constexpr std::array<std::pair<std::string_view, ThermostatKind>, 3> table{
      {{"none", ThermostatKind::none},
       {"rescale", ThermostatKind::rescale},
       {"andersen", ThermostatKind::andersen}}};
};

struct Thermostat {
  ThermostatKind kind = ThermostatKind::none;
  double kT = 1.0;
  double every = 0.0;  // between the instants it acts at (Andersen's: 0 for resets as events)
  double rate = 0.0;   // Andersen: resets per particle per unit time
  std::uint64_t seed = 1;
  friend bool operator==(const Thermostat&, const Thermostat&) = default;
};

// Throws std::invalid_argument for a thermostat no run can have: kT or `every` not positive and
// finite (Andersen's `every` may be 0), Andersen without a positive rate.
void check_thermostat(const Thermostat& thermostat);

// Whether Andersen's resets come as events of their own (every = 0), not at instants.
inline bool resets_as_events(const Thermostat& t) {
  return t.kind == ThermostatKind::andersen && t.every == 0.0;
}

// The time to the system's next reset (resets as events): exponential, of mean 1 / (n rate).
double next_reset_delay(const Thermostat& thermostat, std::size_t n, pcg32& rng);

// A Maxwell-Boltzmann velocity at kT for a particle of mass m, drawn from `rng`.
template <std::size_t D>
Vec<D> maxwell_velocity(double kT, double mass, pcg32& rng);

// Sets the kinetic temperature (kinetic_temperature: relative to the centre of mass in a periodic
// box) of particles stored at one time to kT, keeping the centre of mass's velocity. Particles at
// rest stay at rest.
template <std::size_t D>
void rescale_velocities(System<D>& system, double kT);

// Andersen's resets for one instant `every` after the last: each particle, with probability
// 1 - exp(-rate every), gets a Maxwell-Boltzmann velocity at kT. Returns how many did.
template <std::size_t D>
std::size_t andersen_resets(System<D>& system, const Thermostat& thermostat, pcg32& rng);

}  // namespace carom
