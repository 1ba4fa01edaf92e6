#include "carom/engine/compression.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "carom/core/observables.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/overlap.hpp"
#include "carom/engine/validation.hpp"

namespace carom {

namespace {

// How much the radii may grow in one stretch: the engine's cell grid is sized for the end.
constexpr double kStretchGrowth = 0.02;

bool is_positive(double x) {
  return x > 0.0 && std::isfinite(x);
}

}  // namespace

void check_growth_rate(double rate) {
  if (!is_positive(rate)) {
    throw std::invalid_argument(
        fmt::format("the growth rate must be a positive number, not {}", rate));
  }
}

void check_compression_temperature(double temperature) {
  if (!is_positive(temperature)) {
    throw std::invalid_argument(
        fmt::format("the temperature must be a positive number, not {}", temperature));
  }
}

void check_jammed_pressure(double pressure) {
  if (!is_positive(pressure)) {
    throw std::invalid_argument(
        fmt::format("the jamming pressure must be a positive number, not {}", pressure));
  }
  if (pressure > kMostJammedPressure) {
    throw std::invalid_argument(fmt::format(
        "the jamming pressure must be at most {:g}, got {:g}: beyond it the gaps between particles "
        "are below what doubles resolve, and Z stops rising (near 1e15)",
        kMostJammedPressure, pressure));
  }
}

void check_target_packing(double target, double start_packing, bool equal_particles,
                          std::size_t dimension) {
  if (!(target > start_packing) || !std::isfinite(target)) {
    throw std::invalid_argument(fmt::format(
        "the target packing fraction {} is not above the start's, {}", target, start_packing));
  }
  const double most = equal_particles ? close_packing(dimension) : 1.0;
  if (!(target < most)) {
    throw std::invalid_argument(fmt::format(
        "the target packing fraction {} is beyond {} ({}): no packing of these {} has it", target,
        most, equal_particles ? "close packing" : "a full box",
        dimension == 3 ? kParticlesName<3> : kParticlesName<2>));
  }
}

template <std::size_t D>
Compression<D>::Compression(System<D> start, const CompressionSettings& settings)
    : settings_(settings), system_(std::move(start)) {
  check_growth_rate(settings_.rate);
  check_compression_temperature(settings_.temperature);
  check_jammed_pressure(settings_.jammed_pressure);
  if (system_.particles.empty()) throw std::invalid_argument("there are no particles to compress");
  if (system_.records.empty()) system_.records.resize(system_.particles.size());
  // Every particle at the latest stored time, which becomes t = 0 of the compression.
  double latest = 0.0;
  for (const Particle<D>& p : system_.particles) latest = std::max(latest, p.time);
  for (std::size_t i = 0; i < system_.size(); ++i) {
    Particle<D>& p = system_.particles[i];
    advance(p, latest);
    wrap(p.position, system_.box, system_.records[i].image);
    p.time = 0.0;
    system_.records[i].last_collision = -kNever;
  }
  system_.epoch = 0.0;
  if (const auto wrong = find_violation(system_, 0.0)) {
    throw std::invalid_argument("the start cannot be compressed: " + *wrong);
  }
  bool equal = true;
  for (const Particle<D>& p : system_.particles) {
    initial_radius_.push_back(p.radius);
    equal = equal && p.radius == system_.particles.front().radius;
  }
  initial_packing_ = carom::packing_fraction(system_);
  // Equal particles cannot pass close packing; unequal ones cannot fill the box.
  const double most = equal ? close_packing(D) : 1.0;
  const double final_packing = settings_.target.value_or(most);
  if (settings_.target) {
    const double target = *settings_.target;
    check_target_packing(target, initial_packing_, equal, D);
    const double scale = std::pow(target / initial_packing_, 1.0 / static_cast<double>(D));
    target_time_ = (scale - 1.0) / settings_.rate;
  } else {
    target_time_ = kNever;
  }
  if (system_.box.periodic()) {
    const double grown = largest_radius(system_) *
                         std::pow(final_packing / initial_packing_, 1.0 / static_cast<double>(D));
    if (!(shortest_side(system_.box) > 4.0 * grown * (1.0 + kStretchGrowth))) {
      throw std::invalid_argument(fmt::format(
          "the periodic box is too small to compress {} {} to packing {}: its sides must stay "
          "above two diameters (use more {})",
          system_.size(), kParticlesName<D>, final_packing, kParticlesName<D>));
    }
  }
  if (!(kinetic_temperature(system_) > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "the {} do not move (kT = 0): a compression needs a temperature", kParticlesName<D>));
  }
  // Start at the temperature asked for.
  const double factor = std::sqrt(settings_.temperature / kinetic_temperature(system_));
  for (Particle<D>& p : system_.particles) p.velocity *= factor;
}

template <std::size_t D>
double Compression<D>::packing_fraction() const {
  return carom::packing_fraction(system_);
}

template <std::size_t D>
CompressionStatus Compression<D>::run(std::uint64_t events) {
  const std::uint64_t until = events_ + events;
  while (status_ == CompressionStatus::running && events_ < until &&
         !(stop_ != nullptr && stop_->load() != 0)) {
    stretch();
  }
  return status_;
}

template <std::size_t D>
void Compression<D>::stretch() {
  const double start = time_, scale = scale_at(start);
  // Radii in the engine grow as radius x (1 + rate' tau) from the current ones.
  const double rate = settings_.rate / scale;
  const double to_target = target_time_ - start;
  const double length = std::min(kStretchGrowth / rate, to_target);
  const auto n = static_cast<std::uint64_t>(system_.size());
  auto engine =
      make_engine(settings_.engine, system_, CollisionRule{Rule::elastic}, Growth{rate, length});
  // A stretch is N events (at least 100), unless it reaches its length first.
  const std::uint64_t budget = std::max<std::uint64_t>(n, 100);
  double virial = 0.0, stop = length;
  std::uint64_t done = 0;
  for (; done < budget; ++done) {
    const std::optional<Event> event = engine->step(length);
    if (!event) break;
    if (!event->is_wall()) virial += event->impulse;
    stop = event->time;
  }
  const bool whole = done < budget;
  if (whole) stop = length;
  // Every particle at the end of the stretch, at its grown radius.
  system_ = engine->system();
  const bool reached = whole && length == to_target;
  const double final_scale =
      reached ? std::pow(*settings_.target / initial_packing_, 1.0 / static_cast<double>(D))
              : scale_at(start + stop);
  for (std::size_t i = 0; i < system_.size(); ++i) {
    Particle<D>& p = system_.particles[i];
    advance(p, stop);
    wrap(p.position, system_.box, system_.records[i].image);
    p.time = 0.0;
    p.radius = initial_radius_[i] * final_scale;
    system_.records[i].last_collision = -kNever;
  }
  time_ = reached ? target_time_ : start + stop;
  events_ += done;
  // Z from the collision virial over the stretch, at its mean temperature; then back to the
  // temperature asked for.
  const double temperature = kinetic_temperature(system_);
  if (stop > 0.0) {
    const double mean_temperature = 0.5 * (settings_.temperature + temperature);
    compressibility_factor_ =
        1.0 + virial / (static_cast<double>(D) * static_cast<double>(n) * mean_temperature * stop);
  }
  const double factor = std::sqrt(settings_.temperature / temperature);
  for (Particle<D>& p : system_.particles) {
    p.velocity *= factor;
    // Rounding noise closer to 0 than a start file carries (a jammed rattler's velocity can be
    // 1e-115) is 0, so that the packing written out is one carom reads.
    for (std::size_t k = 0; k < D; ++k) {
      if (std::abs(p.velocity[k]) < kSmallestMagnitude) p.velocity[k] = 0.0;
      if (std::abs(p.position[k]) < kSmallestMagnitude) p.position[k] = 0.0;
    }
  }
  // Particles that can grow no more (pinned between walls, or jammed as densely as doubles
  // resolve) make events ever closer in time while their radii stop changing: that is a jam too,
  // whatever Z says (wall collisions are not in it).
  unchanged_stretches_ = final_scale == last_scale_ ? unchanged_stretches_ + 1 : 0;
  last_scale_ = final_scale;
  if (reached) {
    status_ = CompressionStatus::reached_target;
  } else if (compressibility_factor_ > settings_.jammed_pressure ||
             unchanged_stretches_ >= kStalledStretches) {
    status_ = CompressionStatus::jammed;
  }
}

template class Compression<2>;
template class Compression<3>;

}  // namespace carom
