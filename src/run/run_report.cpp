#include "carom/run/run_report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>

#include "carom/core/observables.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/version.hpp"
#include "carom/io/shown_velocities.hpp"
#include "io/json_text.hpp"

namespace carom {

namespace {

// A run's thermostat as its summary shows it: null without one.
nlohmann::ordered_json thermostat_json(const Thermostat& t) {
  if (t.kind == ThermostatKind::none) return nullptr;
  // Andersen's resets as events have no interval: null.
  nlohmann::ordered_json j = {{"kind", name_of(t.kind)},
                              {"kT", t.kT},
                              {"every", resets_as_events(t) ? nlohmann::ordered_json(nullptr)
                                                            : nlohmann::ordered_json(t.every)}};
  if (t.kind == ThermostatKind::andersen) {
    j["rate"] = t.rate;
    j["seed"] = t.seed;
  }
  return j;
}

}  // namespace

template <std::size_t D>
void write_json(std::ostream& out, const Simulation<D>& simulation, const RunReport& report,
                bool particles) {
  const System<D>& system = simulation.state();
  const Counts& counts = simulation.counts();
  const Counts& window = simulation.measurement().counts;
  const Observables<D> o = simulation.observables();
  const CollisionRule& rule = simulation.settings().rule;
  const Sampler& sampler = simulation.settings().sampler;
  const bool chain = sampler.kind == SamplerKind::ecmc;
  // Infinity (no collision yet) is not a json number: null says "undefined".
  const auto number = [](double x) {
    return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
  };
  // What is measured over the window, undefined (null) when it has lasted no time: a run to its
  // start, or one whose --equilibrate is its end.
  const bool measured = o.elapsed > 0.0;
  const auto over_window = [&](double x) {
    return measured ? number(x) : nlohmann::ordered_json(nullptr);
  };
  const auto vector = [](const Vec<D>& v) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < D; ++k) list.push_back(v[k]);
    return list;
  };
  // A tensor as {"xx": ..., "yy": ..., "xy": ...} (and the z components in 3D).
  const auto tensor = [](const std::optional<SymmetricTensor>& t) {
    if (!t) return nlohmann::ordered_json(nullptr);
    nlohmann::ordered_json object;
    for (const std::size_t c : tensor_components<D>()) object[kTensorComponents[c]] = (*t)[c];
    return object;
  };
  const auto optional = [](const std::optional<double>& x) {
    return x ? nlohmann::ordered_json(*x) : nlohmann::ordered_json(nullptr);
  };
  nlohmann::ordered_json transport = nullptr;
  if (const auto& t = report.transport) {
    transport = {{"blocks", t->blocks},
                 {"self_diffusion", t->self_diffusion},
                 {"self_diffusion_error", t->self_diffusion_error},
                 {"self_diffusion_yeh_hummer", optional(t->self_diffusion_corrected)},
                 {"shear_viscosity", t->shear_viscosity},
                 {"shear_viscosity_error", t->shear_viscosity_error},
                 {"thermal_conductivity", t->thermal_conductivity},
                 {"thermal_conductivity_error", t->thermal_conductivity_error},
                 {"enskog_self_diffusion", optional(t->enskog_self_diffusion)},
                 {"enskog_shear_viscosity", optional(t->enskog_shear_viscosity)},
                 {"enskog_thermal_conductivity", optional(t->enskog_thermal_conductivity)}};
  }
  nlohmann::ordered_json shear = nullptr;
  if (const double rate = system.box.shear_rate; rate != 0.0) {
    const auto& p = o.pressure_tensor;
    const auto& error = report.pressure_tensor_error;
    const auto value = [](const std::optional<SymmetricTensor>& t, double scale) {
      return t ? nlohmann::ordered_json(-(*t)[3] * scale) : nlohmann::ordered_json(nullptr);
    };
    const auto spread = [](const std::optional<SymmetricTensor>& t, double scale) {
      return t ? nlohmann::ordered_json((*t)[3] * std::abs(scale))
               : nlohmann::ordered_json(nullptr);
    };
    shear = {{"rate", rate},
             // The images' shift now, at the end of what was run (the stored offset is the
             // one at the epoch, which can lie far back), from the absolute time: a run resumed
             // at its end has the same, where its stored time may differ in the last bit.
             {"offset", shown_shift(system.box, system.stored(simulation.time()))},
             {"shear_stress", value(p, 1.0)},
             {"shear_stress_error", spread(error, 1.0)},
             {"shear_viscosity", value(p, 1.0 / rate)},
             {"shear_viscosity_error", spread(error, 1.0 / rate)}};
  }
  // What only dynamics has (the collision rule, the engine, the kinetic energy and momentum of
  // velocities): null for event chains, whose one moving particle's speed is a unit of the
  // sampler's clock.
  const auto of_dynamics = [&](nlohmann::ordered_json value) {
    return chain ? nlohmann::ordered_json(nullptr) : value;
  };
  const nlohmann::ordered_json head = {
      {"carom_version", kVersion},
      {"input", report.input},
      {"dimension", D},
      {"n", system.size()},
      {"box", vector(system.box.size)},
      {"boundary", name_of(system.box.boundary)},
      {"rule", of_dynamics(name_of(rule.rule))},
      {"restitution", of_dynamics(rule.restitution)},
      {"tc", of_dynamics(rule.elastic_within)},
      {"engine", of_dynamics(name_of(simulation.settings().engine))},
      {"sampler", name_of(sampler.kind)},
      // Event chains: the chain length in mean diameters (the default resolved) and the seed of
      // the chains' particles.
      {"chain_length", chain ? nlohmann::ordered_json(sampler.chain_length) : nlohmann::ordered_json(nullptr)},
      {"chain_seed", chain ? nlohmann::ordered_json(sampler.seed) : nlohmann::ordered_json(nullptr)},
      {"thermostat", thermostat_json(simulation.settings().thermostat)},
      // A run draws random numbers only for --kT; the start file's seed is carom init's.
      {"seed",
       report.seed ? nlohmann::ordered_json(*report.seed) : nlohmann::ordered_json(nullptr)},
      {"end_time", simulation.time()},
      {"equilibrate", simulation.measurement().start_time},
      {"events", counts.events},
      {"pair_collisions", counts.pair_collisions},
      // Event chains: the lifts (each a pair event), the moves handed on.
      {"lifts", chain ? nlohmann::ordered_json(counts.pair_collisions) : nlohmann::ordered_json(nullptr)},
      {"wall_collisions", counts.wall_collisions},
      {"elastic_by_tc", counts.elastic_by_tc},
      {"window_events", window.events},
      {"window_pair_collisions", window.pair_collisions},
      {"window_wall_collisions", window.wall_collisions},
      {"window_elastic_by_tc", window.elastic_by_tc},
      {"packing_fraction", o.packing_fraction},
      {"kinetic_energy_initial", of_dynamics(o.kinetic_energy_initial)},
      {"kinetic_energy_final", of_dynamics(o.kinetic_energy_final)},
      {"momentum_final", of_dynamics(vector(o.momentum_final))},
      {"degrees_of_freedom", of_dynamics(o.degrees_of_freedom)},
      {"temperature", o.temperature},
      {"pressure", over_window(o.pressure)},
      {"wall_pressure", system.box.periodic() ? nlohmann::ordered_json(nullptr)
                                              : over_window(o.wall_pressure)},
      {"compressibility_factor", over_window(o.compressibility_factor)},
      // Over the drift verdict's intervals of the window, taken as independent.
      {"compressibility_factor_error", optional(report.compressibility_factor_error)},
      // Event chains: Z along x, y (and z), from the lifts and the displacement along each.
      {"directional_compressibility_factor",
       o.directional_z ? nlohmann::ordered_json(std::vector<double>(o.directional_z->begin(),
                                                                     o.directional_z->end()))
                       : nlohmann::ordered_json(nullptr)},
      {"compressibility_factor_drift",
       report.drift ? nlohmann::ordered_json{{"first_half", report.drift->first},
                                             {"second_half", report.drift->second},
                                             {"sigmas", report.drift->sigmas},
                                             {"intervals", report.drift->intervals},
                                             {"block_correlation",
                                              report.drift->block_correlation}}
                    : nlohmann::ordered_json(nullptr)},
      {"collision_rate", over_window(o.collision_rate)},
      {"mean_free_time", over_window(o.mean_free_time)},
      // Present when the run kept its fluxes (fluxes.hpp): the window's pressure tensor and the
      // standard error of each component over the drift verdict's intervals.
      {"pressure_tensor", tensor(o.pressure_tensor)},
      {"pressure_tensor_error", tensor(report.pressure_tensor_error)},
      // In a sheared box: -pxy and -pxy / rate, with the pressure tensor's errors.
      {"shear", shear},
      // With --transport: the coefficients over the window's blocks (transport.hpp).
      {"transport", transport},
      {"wall_seconds", report.wall_seconds},
      {"events_per_second",
       report.wall_seconds > 0.0
           ? nlohmann::ordered_json(static_cast<double>(report.events) / report.wall_seconds)
           : nlohmann::ordered_json(nullptr)},
  };
  if (!particles) {
    out << dump_json(head, 2) << '\n';
    return;
  }
  // The settings pretty-printed, then one compact line a particle: readable, and a million
  // particles are streamed rather than built as one document in memory.
  std::string text = dump_json(head, 2);
  text.resize(text.size() - 2);  // reopen the object: drop the closing "\n}"
  out << text << ",\n  \"particles\": [";
  constexpr const char* kAxes[] = {"x", "y", "z"};
  constexpr const char* kVelocities[] = {"vx", "vy", "vz"};
  const double now_stored = simulation.stored_time();
  const bool at_rest = shows_at_rest(simulation);
  for (std::size_t i = 0; i < system.size(); ++i) {
    // One particle at a time: a million-particle result needs no copy of the state.
    const Particle<D> p = synchronised(system.particles[i], system.box, now_stored);
    const ParticleRecord& r = system.records[i];
    nlohmann::ordered_json particle = {{"id", i}};
    for (std::size_t k = 0; k < D; ++k) particle[kAxes[k]] = p.position[k];
    for (std::size_t k = 0; k < D; ++k) particle[kVelocities[k]] = at_rest ? 0.0 : p.velocity[k];
    particle["radius"] = p.radius;
    particle["mass"] = r.mass;
    particle["last_update"] = simulation.time();
    particle["wall_collisions"] = r.wall_collisions;
    particle["pair_collisions"] = r.pair_collisions;
    out << (i == 0 ? "\n    " : ",\n    ") << particle.dump();
  }
  out << "\n  ]\n}\n";
}

void write_result(std::ostream& out, const AnySimulation& simulation, Format format,
                  const RunReport& report, bool particles) {
  simulation.visit([&](const auto& s) {
    switch (format) {
      case Format::table:
        write_table(out, s);
        break;
      case Format::csv:
        write_csv(out, s);
        break;
      case Format::json:
        write_json(out, s, report, particles);
        break;
    }
  });
}

template void write_json(std::ostream&, const Simulation<2>&, const RunReport&, bool);
template void write_json(std::ostream&, const Simulation<3>&, const RunReport&, bool);

}  // namespace carom
