#include "carom/formats.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "carom/observables.hpp"
#include "carom/version.hpp"

namespace carom {

namespace {

constexpr const char* kTableHeader =
    "particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)\n";

// printf's %.6f, exactly as the seed's C program printed (round-half-even on exact ties, `-0`
// kept), which is what users compare against.
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

}  // namespace

std::string particle_line(std::size_t index, const Particle<2>& p) {
  return c_format("particle %zu: (%.6f, %.6f) (%.6f, %.6f): %.6f : (%llu, %llu)", index,
                  p.position[0], p.position[1], p.velocity[0], p.velocity[1], p.time,
                  static_cast<unsigned long long>(p.wall_collisions),
                  static_cast<unsigned long long>(p.pair_collisions));
}

void write_table(std::ostream& out, std::span<const Particle<2>> particles) {
  out << kTableHeader;
  for (std::size_t i = 0; i < particles.size(); ++i) out << particle_line(i, particles[i]) << '\n';
}

void write_csv(std::ostream& out, std::span<const Particle<2>> particles) {
  for (const Particle<2>& p : particles) {
    out << c_format("%.6f, %.6f, %llu, %llu\n", p.position[0], p.position[1],
                    static_cast<unsigned long long>(p.wall_collisions),
                    static_cast<unsigned long long>(p.pair_collisions));
  }
}

void write_json(std::ostream& out, const RunSettings& settings, const Engine<2>& engine,
                bool particles) {
  const System<2>& system = engine.system();
  const RunCounts& counts = engine.counts();
  const double elapsed = settings.end_time - settings.equilibrate;
  const Observables<2> o = measure(engine, elapsed, settings.kinetic_energy_initial);
  // Infinity (no collision yet) is not a json number: null says "undefined".
  const auto number = [](double x) {
    return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
  };
  const nlohmann::ordered_json head = {
      {"carom_version", kVersion},
      {"input", settings.input},
      {"n", system.particles.size()},
      {"box", {system.box.size[0], system.box.size[1]}},
      {"boundary", boundary_name(system.box.boundary)},
      {"rule", rule_name(settings.rule.rule)},
      {"restitution", settings.rule.restitution},
      {"tc", settings.rule.elastic_within},
      {"engine", engine_name(settings.engine)},
      {"seed", nullptr},  // a run draws no random numbers; the start file's seed is carom init's
      {"end_time", settings.end_time},
      {"equilibrate", settings.equilibrate},
      {"events", counts.events},
      {"pair_collisions", counts.pair_collisions},
      {"wall_collisions", counts.wall_collisions},
      {"elastic_by_tc", counts.elastic_by_tc},
      {"packing_fraction", o.packing_fraction},
      {"kinetic_energy_initial", o.kinetic_energy_initial},
      {"kinetic_energy_final", o.kinetic_energy_final},
      {"momentum_final", {o.momentum_final[0], o.momentum_final[1]}},
      {"temperature", o.temperature},
      {"pressure", o.pressure},
      {"wall_pressure", system.box.periodic() ? nlohmann::ordered_json(nullptr)
                                              : nlohmann::ordered_json(o.wall_pressure)},
      {"compressibility_factor", o.compressibility_factor},
      {"collision_rate", o.collision_rate},
      {"mean_free_time", number(o.mean_free_time)},
      {"wall_seconds", settings.wall_seconds},
      {"events_per_second",
       settings.wall_seconds > 0.0
           ? nlohmann::ordered_json(static_cast<double>(counts.events) / settings.wall_seconds)
           : nlohmann::ordered_json(nullptr)},
  };
  if (!particles) {
    out << head.dump(2) << '\n';
    return;
  }
  // The settings pretty-printed, then one compact line a particle: readable, and a million
  // particles are streamed rather than built as one document in memory.
  std::string text = head.dump(2);
  text.resize(text.size() - 2);  // reopen the object: drop the closing "\n}"
  out << text << ",\n  \"particles\": [";
  for (std::size_t i = 0; i < system.particles.size(); ++i) {
    const Particle<2>& p = system.particles[i];
    const nlohmann::ordered_json particle = {{"id", i},
                                             {"x", p.position[0]},
                                             {"y", p.position[1]},
                                             {"vx", p.velocity[0]},
                                             {"vy", p.velocity[1]},
                                             {"radius", p.radius},
                                             {"last_update", p.time},
                                             {"wall_collisions", p.wall_collisions},
                                             {"pair_collisions", p.pair_collisions}};
    out << (i == 0 ? "\n    " : ",\n    ") << particle.dump();
  }
  out << "\n  ]\n}\n";
}

void write_classic(std::ostream& out, const System<2>& system, double radius) {
  // Shortest round-trip representation: reading the file back gives the same doubles.
  out << fmt::format("{}\n{}\n{} {}\n", system.particles.size(), radius, system.box.size[0],
                     system.box.size[1]);
  for (const Particle<2>& p : system.particles) {
    out << fmt::format("{} {} {} {}", p.position[0], p.position[1], p.velocity[0], p.velocity[1]);
    if (p.radius != radius || p.mass != 1.0) out << fmt::format(" {}", p.radius);
    if (p.mass != 1.0) out << fmt::format(" {}", p.mass);
    out << '\n';
  }
}

std::string describe(const Event& event) {
  if (event.is_wall()) {
    return fmt::format("Collision: particle {} with wall {} ({})", event.first, event.partner,
                       wall_name(event.partner));
  }
  return fmt::format("Collision: particle {} with particle {}", event.first, event.partner);
}

void TraceWriter::start(const std::string& input, double end_time,
                        std::span<const Particle<2>> particles) {
  out_ << "Input File: " << input << '\n'
       << c_format("Target Time: %f\n", end_time) << "======== Initial Particles =========\n";
  write_table(out_, particles);
}

void TraceWriter::event(const Event& event, std::span<const Particle<2>> particles) {
  out_ << c_format("                 TIME = %f\n", event.time) << describe(event) << '\n'
       << "======== Particles =========\n";
  write_table(out_, particles);
}

void TraceWriter::finish(std::span<const Particle<2>> particles) {
  out_ << "======== Final Particles =========\n";
  write_table(out_, particles);
}

}  // namespace carom
