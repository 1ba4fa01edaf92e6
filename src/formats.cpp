#include "carom/formats.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "carom/classic_input.hpp"
#include "carom/observables.hpp"
#include "carom/version.hpp"
#include "json_text.hpp"
#include "whole_lines.hpp"

namespace carom {

namespace {

template <std::size_t D>
constexpr const char* kTableHeader =
    D == 3 ? "particle id: (xpos, ypos, zpos) (xvel, yvel, zvel): last_update : (cwall, cpart)\n"
           : "particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)\n";

// printf's %.6f, exactly as the classic assignment's C program printed (round-half-even on exact
// ties, `-0` kept), which is what users compare against.
template <class... Args>
std::string c_format(const char* format, Args... args) {
  char buffer[512];
  const int length = std::snprintf(buffer, sizeof buffer, format, args...);
  if (length >= 0 && static_cast<std::size_t>(length) < sizeof buffer) {
    return std::string(buffer, static_cast<std::size_t>(length));
  }
  std::string big(static_cast<std::size_t>(length) + 1, '\0');
  std::snprintf(big.data(), big.size(), format, args...);
  big.pop_back();
  return big;
}

// The components of a vector, `%.6f, %.6f[, %.6f]`.
template <std::size_t D>
std::string components(const Vec<D>& v) {
  std::string text = c_format("%.6f", v[0]);
  for (std::size_t k = 1; k < D; ++k) text += c_format(", %.6f", v[k]);
  return text;
}

}  // namespace

template <std::size_t D>
std::string particle_line(std::size_t index, const Particle<D>& p, const ParticleRecord& record) {
  return c_format("particle %zu: (", index) + components(p.position) + ") (" +
         components(p.velocity) +
         c_format("): %.6f : (%llu, %llu)", p.time,
                  static_cast<unsigned long long>(record.wall_collisions),
                  static_cast<unsigned long long>(record.pair_collisions));
}

namespace {

std::string csv_line(const auto& position, const ParticleRecord& record) {
  return components(position) + c_format(", %llu, %llu\n",
                                         static_cast<unsigned long long>(record.wall_collisions),
                                         static_cast<unsigned long long>(record.pair_collisions));
}

}  // namespace

template <std::size_t D>
void write_table(std::ostream& out, const System<D>& system) {
  out << kTableHeader<D>;
  for (std::size_t i = 0; i < system.size(); ++i) {
    Particle<D> stored = system.particles[i];
    stored.time = system.absolute(stored.time);
    out << particle_line(i, stored, system.records[i]) << '\n';
  }
}

template <std::size_t D>
void write_table(std::ostream& out, const Simulation<D>& simulation) {
  const System<D>& system = simulation.state();
  const double now_stored = simulation.stored_time();
  out << kTableHeader<D>;
  for (std::size_t i = 0; i < system.size(); ++i) {
    Particle<D> now = synchronised(system.particles[i], system.box, now_stored);
    now.time = simulation.time();
    out << particle_line(i, now, system.records[i]) << '\n';
  }
}

template <std::size_t D>
void write_csv(std::ostream& out, std::span<const Particle<D>> particles,
               std::span<const ParticleRecord> records) {
  for (std::size_t i = 0; i < particles.size(); ++i) {
    out << csv_line(particles[i].position, records[i]);
  }
}

template <std::size_t D>
void write_csv(std::ostream& out, const Simulation<D>& simulation) {
  const System<D>& system = simulation.state();
  const double now_stored = simulation.stored_time();
  for (std::size_t i = 0; i < system.size(); ++i) {
    const Particle<D> now = synchronised(system.particles[i], system.box, now_stored);
    out << csv_line(now.position, system.records[i]);
  }
}

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
  // Infinity (no collision yet) is not a json number: null says "undefined".
  const auto number = [](double x) {
    return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
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
  const nlohmann::ordered_json head = {
      {"carom_version", kVersion},
      {"input", report.input},
      {"dimension", D},
      {"n", system.size()},
      {"box", vector(system.box.size)},
      {"boundary", name_of(system.box.boundary)},
      {"rule", name_of(rule.rule)},
      {"restitution", rule.restitution},
      {"tc", rule.elastic_within},
      {"engine", name_of(simulation.settings().engine)},
      {"thermostat", thermostat_json(simulation.settings().thermostat)},
      // A run draws random numbers only for --kT; the start file's seed is carom init's.
      {"seed",
       report.seed ? nlohmann::ordered_json(*report.seed) : nlohmann::ordered_json(nullptr)},
      {"end_time", simulation.time()},
      {"equilibrate", simulation.measurement().start_time},
      {"events", counts.events},
      {"pair_collisions", counts.pair_collisions},
      {"wall_collisions", counts.wall_collisions},
      {"elastic_by_tc", counts.elastic_by_tc},
      {"window_events", window.events},
      {"window_pair_collisions", window.pair_collisions},
      {"window_wall_collisions", window.wall_collisions},
      {"window_elastic_by_tc", window.elastic_by_tc},
      {"packing_fraction", o.packing_fraction},
      {"kinetic_energy_initial", o.kinetic_energy_initial},
      {"kinetic_energy_final", o.kinetic_energy_final},
      {"momentum_final", vector(o.momentum_final)},
      {"degrees_of_freedom", o.degrees_of_freedom},
      {"temperature", o.temperature},
      {"pressure", o.pressure},
      {"wall_pressure", system.box.periodic() ? nlohmann::ordered_json(nullptr)
                                              : nlohmann::ordered_json(o.wall_pressure)},
      {"compressibility_factor", number(o.compressibility_factor)},
      {"compressibility_factor_drift",
       report.drift ? nlohmann::ordered_json{{"first_half", report.drift->first},
                                             {"second_half", report.drift->second},
                                             {"sigmas", report.drift->sigmas},
                                             {"intervals", report.drift->intervals}}
                    : nlohmann::ordered_json(nullptr)},
      {"collision_rate", o.collision_rate},
      {"mean_free_time", number(o.mean_free_time)},
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
  for (std::size_t i = 0; i < system.size(); ++i) {
    // One particle at a time: a million-particle result needs no copy of the state.
    const Particle<D> p = synchronised(system.particles[i], system.box, now_stored);
    const ParticleRecord& r = system.records[i];
    nlohmann::ordered_json particle = {{"id", i}};
    for (std::size_t k = 0; k < D; ++k) particle[kAxes[k]] = p.position[k];
    for (std::size_t k = 0; k < D; ++k) particle[kVelocities[k]] = p.velocity[k];
    particle["radius"] = p.radius;
    particle["mass"] = r.mass;
    particle["last_update"] = simulation.time();
    particle["wall_collisions"] = r.wall_collisions;
    particle["pair_collisions"] = r.pair_collisions;
    out << (i == 0 ? "\n    " : ",\n    ") << particle.dump();
  }
  out << "\n  ]\n}\n";
}

template <std::size_t D>
void write_classic(std::ostream& out, const System<D>& system, double radius) {
  // Shortest round-trip representation: reading the file back gives the same doubles.
  out << fmt::format("{}\n{}\n{}\n", system.size(), radius, fmt::join(system.box.size.c, " "));
  for (std::size_t i = 0; i < system.size(); ++i) {
    const Particle<D>& p = system.particles[i];
    const double mass = system.records[i].mass;
    out << fmt::format("{} {}", fmt::join(p.position.c, " "), fmt::join(p.velocity.c, " "));
    if (p.radius != radius || mass != 1.0) out << fmt::format(" {}", p.radius);
    if (mass != 1.0) out << fmt::format(" {}", mass);
    out << '\n';
  }
}

template <std::size_t D>
void write_start(std::ostream& out, const System<D>& system, Rule rule) {
  out << start_record_line(system.box.boundary, rule) << '\n';
  const double first = system.particles.front().radius;
  double sum = 0.0;
  bool equal = true;
  for (const Particle<D>& p : system.particles) {
    sum += p.radius;
    equal = equal && p.radius == first;
  }
  write_classic(out, system, equal ? first : sum / static_cast<double>(system.size()));
}

std::string describe(const Event& event) {
  if (event.is_wall()) {
    return fmt::format("Collision: particle {} with wall {} ({})", event.first, event.partner,
                       wall_name(event.partner));
  }
  return fmt::format("Collision: particle {} with particle {}", event.first, event.partner);
}

template <std::size_t D>
void TraceWriter<D>::start(const std::string& input, double end_time,
                           const Simulation<D>& simulation) {
  out_ << "Input File: " << input << '\n'
       << c_format("Target Time: %f\n", end_time) << "======== Initial Particles =========\n";
  write_table(out_, simulation.state());
}

template <std::size_t D>
void TraceWriter<D>::observe(const Simulation<D>& simulation) {
  out_ << c_format("                 TIME = %f\n", simulation.last_event().time)
       << describe(simulation.last_event()) << '\n'
       << "======== Particles =========\n";
  write_table(out_, simulation.state());
  if (!out_) throw std::runtime_error("cannot write the trace");
}

template <std::size_t D>
void TraceWriter<D>::finish(const Simulation<D>& simulation) {
  out_ << "======== Final Particles =========\n";
  write_table(out_, simulation);
}

template <std::size_t D>
void EventLogWriter<D>::observe(const Simulation<D>& simulation) {
  const Event& event = simulation.last_event();
  out_ << fmt::format("{},{},{},{}\n", event.time, event.is_wall() ? "wall" : "pair", event.first,
                      event.partner);
  if (!out_) throw std::runtime_error("cannot write the event log");
}

template <std::size_t D>
std::uint64_t EventLogWriter<D>::events_before(std::istream& in, double t, bool inclusive) {
  LineReader reader{in, 0, {}};
  if (!reader.next() || reader.line + "\n" != kHeader) return 0;
  std::uint64_t kept = reader.offset;
  while (reader.next()) {
    char* end = nullptr;
    const double time = std::strtod(reader.line.c_str(), &end);
    if (end == reader.line.c_str() || *end != ',' || !written_before(time, t, inclusive)) break;
    kept = reader.offset;
  }
  return kept;
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

void write_start(std::ostream& out, const AnySystem& system, Rule rule) {
  std::visit([&](const auto& s) { write_start(out, s, rule); }, system);
}

#define CAROM_FORMATS(D)                                                                      \
  template std::string particle_line(std::size_t, const Particle<D>&, const ParticleRecord&); \
  template void write_table(std::ostream&, const System<D>&);                                 \
  template void write_csv(std::ostream&, std::span<const Particle<D>>,                        \
                          std::span<const ParticleRecord>);                                   \
  template void write_table(std::ostream&, const Simulation<D>&);                             \
  template void write_csv(std::ostream&, const Simulation<D>&);                               \
  template void write_json(std::ostream&, const Simulation<D>&, const RunReport&, bool);      \
  template class TraceWriter<D>;                                                              \
  template class EventLogWriter<D>;                                                           \
  template void write_classic(std::ostream&, const System<D>&, double);                       \
  template void write_start(std::ostream&, const System<D>&, Rule);
CAROM_FORMATS(2)
CAROM_FORMATS(3)
#undef CAROM_FORMATS

}  // namespace carom
