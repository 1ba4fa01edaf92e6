#include "ecmc_engine.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "carom/engine/initial.hpp"

namespace carom {

namespace {

// A system as chains start in it: a periodic box, unit masses, every particle at rest at the
// latest stored time.
template <std::size_t D>
System<D> at_rest(System<D> system) {
  if (!system.box.periodic() || system.box.sheared()) {
    throw std::invalid_argument("event-chain Monte Carlo needs a periodic box that is not sheared");
  }
  for (const ParticleRecord& r : system.records) {
    if (r.mass != 1.0) {
      throw std::invalid_argument(
          "event-chain Monte Carlo samples positions only: every mass must be 1");
    }
  }
  double latest = 0.0;
  for (const Particle<D>& p : system.particles) latest = std::max(latest, p.time);
  if (system.records.empty()) system.records.resize(system.size());
  for (std::size_t i = 0; i < system.size(); ++i) {
    Particle<D>& p = system.particles[i];
    p.position = position_at(p, latest);
    p.time = latest;
    p.velocity = Vec<D>{};
    wrap(p, system.box, system.records[i].image);
  }
  return system;
}

template <std::size_t D>
Vec<D> along(std::size_t axis, double speed) {
  Vec<D> v{};
  v[axis] = speed;
  return v;
}

}  // namespace

template <std::size_t D>
EcmcEngine<D>::EcmcEngine(System<D> system, double chain_length, const ChainState& chain)
    : Engine<D>(std::move(system), {Rule::swap, 1.0, 0.0}, {}),
      chain_(chain),
      grid_(this->system_.box, 2.0 * largest_radius(this->system_), this->system_.size()) {
  if (!(chain_length > 0.0)) {
    throw std::invalid_argument(
        fmt::format("a chain length must be above 0, not {}", chain_length));
  }
  const double n = static_cast<double>(this->system_.size());
  const double diameter = mean_diameter(this->system_);
  speed_ = n * diameter;
  chain_duration_ = chain_length * diameter / speed_;
  for (std::uint32_t i = 0; i < this->system_.size(); ++i) {
    grid_.insert(i, grid_.locate(this->system_.particles[i].position));
  }
}

template <std::size_t D>
EcmcEngine<D>::EcmcEngine(System<D> system, double chain_length, pcg32 rng)
    : EcmcEngine(at_rest(std::move(system)), chain_length, ChainState{0, 0, 0.0, rng}) {
  start_moving_at(this->now_);
}

template <std::size_t D>
std::pair<std::uint32_t, double> EcmcEngine<D>::nearest_lift(const Particle<D>& a) const {
  const std::uint32_t active = chain_.active;
  std::uint32_t target = active;
  double nearest = kNever;
  grid_.for_each_ahead(grid_.cell_of(active), chain_.axis, [&](std::uint32_t j) {
    if (j == active) return;
    const Particle<D>& b = this->system_.particles[j];
    const double s = lift_distance(image_separation(a, b, this->system_.box), chain_.axis,
                                   a.radius + b.radius, nearest);
    // Ties go to the lower index, so that the order of the cells' lists does not matter.
    if (s < nearest || (s == nearest && s != kNever && j < target)) {
      nearest = s;
      target = j;
    }
  });
  return {target, nearest};
}

template <std::size_t D>
std::optional<Event> EcmcEngine<D>::step(double end_time) {
  while (true) {
    const std::uint32_t active = chain_.active;
    const Particle<D>& a = this->system_.particles[active];
    const auto [target, distance] = nearest_lift(a);
    const double lift_time = distance == kNever ? kNever : a.time + distance / speed_;
    const auto crossing = grid_.next_crossing(grid_.cell_of(active), a.position, a.velocity);
    const double crossing_time = a.time + crossing.delay;
    if (chain_.chain_end <= lift_time && chain_.chain_end <= crossing_time) {
      if (!this->due_by(chain_.chain_end, end_time)) return std::nullopt;
      start_next_chain();
    } else if (lift_time <= crossing_time) {
      if (!this->due_by(lift_time, end_time)) return std::nullopt;
      const Event event = this->apply(Event{lift_time, std::min(active, target),
                                            static_cast<std::int32_t>(std::max(active, target))});
      // apply() wrapped both into the box: the active one may have left the cell it was in.
      grid_.move(active, grid_.locate(this->system_.particles[active].position));
      chain_.active = target;
      return event;
    } else {
      if (!this->due_by(crossing_time, end_time)) return std::nullopt;
      grid_.move(active, grid_.adjacent(grid_.cell_of(active), crossing.axis, crossing.upward));
    }
  }
}

template <std::size_t D>
void EcmcEngine<D>::start_next_chain() {
  Particle<D>& a = this->system_.particles[chain_.active];
  ParticleRecord& record = this->system_.records[chain_.active];
  const double t = chain_.chain_end;
  advance(a, t);
  this->velocity_changes_.push_back({chain_.active, t, a.velocity, Vec<D>{}});
  a.velocity = Vec<D>{};
  wrap(a, this->system_.box, record.image);
  grid_.move(chain_.active, grid_.locate(a.position));
  chain_.axis = static_cast<std::uint8_t>((chain_.axis + 1) % D);
  start_moving_at(t);
  this->velocity_changes_.push_back({chain_.active, t, Vec<D>{}, along<D>(chain_.axis, speed_)});
}

template <std::size_t D>
void EcmcEngine<D>::start_moving_at(double t) {
  chain_.active =
      static_cast<std::uint32_t>(chain_.rng(static_cast<std::uint32_t>(this->system_.size())));
  Particle<D>& next = this->system_.particles[chain_.active];
  next.time = t;
  next.velocity = along<D>(chain_.axis, speed_);
  chain_.chain_end = t + chain_duration_;
}

template <std::size_t D>
void EcmcEngine<D>::velocity_reset(std::uint32_t) {
  throw std::logic_error("event-chain Monte Carlo has no velocities to reset");
}

template class EcmcEngine<2>;
template class EcmcEngine<3>;

}  // namespace carom
