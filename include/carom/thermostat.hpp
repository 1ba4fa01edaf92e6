// Thermostats: what holds a run at a temperature kT, acting on the velocities at the instants
// t = every, 2 every, ... (counted from t = 0) between collisions. Rescaling multiplies every
// velocity relative to the centre of mass by one factor, so that the kinetic temperature is kT
// exactly (Berendsen's with a coupling time of one step); Andersen's (in its "massive" form:
// Andersen, J. Chem. Phys. 72, 2384 (1980); Tanaka, Yokota and Mochizuki) gives each particle,
// with probability 1 - exp(-rate x every), a new velocity drawn from the Maxwell-Boltzmann
// distribution at kT, from a pcg32 stream of its own seed that a checkpoint carries on. Both also
// drive an inelastic gas to a steady state.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <pcg_random.hpp>
#include <string_view>
#include <utility>

#include "carom/names.hpp"
#include "carom/system.hpp"

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
  double every = 0.0;  // between the instants it acts at
  double rate = 0.0;   // Andersen: resets per particle per unit time
  std::uint64_t seed = 1;
  friend bool operator==(const Thermostat&, const Thermostat&) = default;
};

// Throws std::invalid_argument for a thermostat no run can have: kT or `every` not positive and
// finite, Andersen without a positive rate.
void check_thermostat(const Thermostat& thermostat);

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
