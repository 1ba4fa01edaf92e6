#include "carom/io/classic_output.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <stdexcept>
#include <string>

#include "carom/io/classic_input.hpp"
#include "carom/io/shown_velocities.hpp"

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
    if (shows_at_rest(simulation)) now.velocity = Vec<D>{};
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

template <std::size_t D>
void write_classic(std::ostream& out, const System<D>& system, double radius) {
  // Shortest round-trip representation: reading the file back gives the same doubles.
  out << fmt::format("{}\n{}\n{}\n", system.size(), radius, fmt::join(system.box.size.c, " "));
  for (std::size_t i = 0; i < system.size(); ++i) {
    const Particle<D>& p = system.particles[i];
    const double mass = system.records[i].mass;
    out << fmt::format("{} {}", fmt::join(p.position.c, " "), fmt::join(p.velocity.c, " "));
    // A mixture's lines end with r, m and the type's index (see StartRecord::types).
    const bool typed = has_types(system);
    if (p.radius != radius || mass != 1.0 || typed) out << fmt::format(" {}", p.radius);
    if (mass != 1.0 || typed) out << fmt::format(" {}", mass);
    if (typed) out << fmt::format(" {}", system.records[i].type);
    out << '\n';
  }
}

template <std::size_t D>
void write_start(std::ostream& out, const System<D>& system, Rule rule) {
  out << start_record_line(system.box.boundary, rule,
                           has_types(system) ? system.type_names : std::vector<std::string>{})
      << '\n';
  const double first = system.particles.front().radius;
  double sum = 0.0;
  bool equal = true;
  for (const Particle<D>& p : system.particles) {
    sum += p.radius;
    equal = equal && p.radius == first;
  }
  write_classic(out, system, equal ? first : sum / static_cast<double>(system.size()));
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

#define CAROM_CLASSIC_OUTPUT(D)                                                               \
  template std::string particle_line(std::size_t, const Particle<D>&, const ParticleRecord&); \
  template void write_table(std::ostream&, const System<D>&);                                 \
  template void write_csv(std::ostream&, std::span<const Particle<D>>,                        \
                          std::span<const ParticleRecord>);                                   \
  template void write_table(std::ostream&, const Simulation<D>&);                             \
  template void write_csv(std::ostream&, const Simulation<D>&);                               \
  template class TraceWriter<D>;                                                              \
  template void write_classic(std::ostream&, const System<D>&, double);                       \
  template void write_start(std::ostream&, const System<D>&, Rule);
CAROM_CLASSIC_OUTPUT(2)
CAROM_CLASSIC_OUTPUT(3)
#undef CAROM_CLASSIC_OUTPUT

}  // namespace carom
