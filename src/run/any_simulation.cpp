#include "carom/run/any_simulation.hpp"

#include <cmath>

#include "carom/io/checkpoint.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/shown_velocities.hpp"

namespace carom {

namespace {

// Writes pick(particle at `now`) for every particle, D values each.
template <std::size_t D, class Pick>
void per_particle_vector(const Simulation<D>& s, double* out, Pick pick) {
  const System<D>& system = s.state();
  const double now = s.stored_time();
  for (std::size_t i = 0; i < system.size(); ++i) {
    // Each particle brought to the simulation's time on its own: no copy of the state.
    const Vec<D>& v = pick(synchronised(system.particles[i], system.box, now));
    for (std::size_t k = 0; k < D; ++k) out[i * D + k] = v[k];
  }
}

// Writes pick(particle, record) for every particle.
template <class T, class Pick>
void per_particle(const AnySimulation& any, T* out, Pick pick) {
  any.visit([&](const auto& s) {
    const auto& system = s.state();
    for (std::size_t i = 0; i < system.size(); ++i) {
      out[i] = pick(system.particles[i], system.records[i]);
    }
  });
}

}  // namespace

AnySimulation::AnySimulation(AnySystem system, const Settings& settings)
    : simulation_(std::visit(
          [&](auto& s) -> std::variant<Simulation<2>, Simulation<3>> {
            using S = std::remove_reference_t<decltype(s)>;
            return Simulation<S::dimension>(std::move(s), settings);
          },
          system)) {}

std::size_t AnySimulation::size() const {
  return visit([](const auto& s) { return s.state().size(); });
}
double AnySimulation::time() const {
  return visit([](const auto& s) { return s.time(); });
}
bool AnySimulation::settled() const {
  return visit([](const auto& s) { return s.settled(); });
}
const Counts& AnySimulation::counts() const {
  return visit([](const auto& s) -> const Counts& { return s.counts(); });
}
const Settings& AnySimulation::settings() const {
  return visit([](const auto& s) -> const Settings& { return s.settings(); });
}
Boundary AnySimulation::boundary() const {
  return visit([](const auto& s) { return s.state().box.boundary; });
}
std::vector<double> AnySimulation::box() const {
  return visit([](const auto& s) {
    const auto& size = s.state().box.size.c;
    return std::vector<double>(size.begin(), size.end());
  });
}

double AnySimulation::shear_shift() const {
  // From the absolute time, as the summary and frames take it (a resumed run's stored time may
  // differ from the uninterrupted run's in the last bit).
  return visit(
      [](const auto& s) { return shown_shift(s.state().box, s.state().stored(s.time())); });
}

void AnySimulation::check_target(double t) const {
  visit([&](const auto& s) { s.check_target(t); });
}
RunStatus AnySimulation::run_until(double t, std::uint64_t max_events) {
  return visit([&](auto& s) { return s.run_until(t, max_events); });
}
void AnySimulation::set_stop_flag(const std::atomic<int>* flag) {
  visit([&](auto& s) { s.set_stop_flag(flag); });
}

void AnySimulation::reset_measurement() {
  visit([](auto& s) { s.reset_measurement(); });
}
void AnySimulation::measure_from(double t) {
  visit([&](auto& s) { s.measure_from(t); });
}
std::optional<double> AnySimulation::pending_measurement() const {
  return visit([](const auto& s) { return s.pending_measurement(); });
}
Measurement AnySimulation::measurement() const {
  return visit([](const auto& s) { return s.measurement(); });
}
std::optional<double> AnySimulation::compressibility_factor() const {
  return visit([](const auto& s) -> std::optional<double> {
    const auto o = s.observables();
    if (o.elapsed > 0.0 && std::isfinite(o.compressibility_factor)) {
      return o.compressibility_factor;
    }
    return std::nullopt;
  });
}

void AnySimulation::positions(double* out) const {
  visit([&](const auto& s) {
    per_particle_vector(s, out, [](const auto& p) { return p.position; });
  });
}
void AnySimulation::velocities(double* out) const {
  visit([&](const auto& s) {
    using V = std::remove_cvref_t<decltype(s.state().particles[0].velocity)>;
    const bool at_rest = shows_at_rest(s);
    per_particle_vector(s, out, [at_rest](const auto& p) { return at_rest ? V{} : p.velocity; });
  });
}
void AnySimulation::images(std::int32_t* out) const {
  visit([&](const auto& s) {
    const auto& system = s.state();
    constexpr std::size_t D = std::remove_cvref_t<decltype(system)>::dimension;
    for (std::size_t i = 0; i < system.size(); ++i) {
      // The flags as the particle's flight to now wraps it, as a trajectory frame has them.
      std::array<std::int32_t, 3> image = system.records[i].image;
      synchronised(system.particles[i], system.box, s.stored_time(), image);
      for (std::size_t k = 0; k < D; ++k) out[i * D + k] = image[k];
    }
  });
}
void AnySimulation::radii(double* out) const {
  per_particle(*this, out, [](const auto& p, const auto&) { return p.radius; });
}
void AnySimulation::masses(double* out) const {
  per_particle(*this, out, [](const auto&, const auto& r) { return r.mass; });
}
void AnySimulation::types(std::uint32_t* out) const {
  per_particle(*this, out, [](const auto&, const auto& r) { return r.type; });
}
std::vector<std::string> AnySimulation::type_names() const {
  return visit([](const auto& s) { return s.state().type_names; });
}
void AnySimulation::wall_collisions(std::uint64_t* out) const {
  per_particle(*this, out, [](const auto&, const auto& r) { return r.wall_collisions; });
}
void AnySimulation::pair_collisions(std::uint64_t* out) const {
  per_particle(*this, out, [](const auto&, const auto& r) { return r.pair_collisions; });
}

AnySystem AnySimulation::snapshot_system() const {
  return visit([](const auto& s) -> AnySystem {
    auto system = s.state();
    system.particles = s.snapshot();
    for (auto& p : system.particles) p.time = 0.0;
    system.epoch = 0.0;
    return system;
  });
}

void write_start(std::ostream& out, const AnySystem& system, Rule rule) {
  std::visit([&](const auto& s) { write_start(out, s, rule); }, system);
}

}  // namespace carom
