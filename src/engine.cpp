#include "carom/engine.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "fast_engine.hpp"
#include "reference_engine.hpp"

namespace carom {

template <std::size_t D>
Engine<D>::Engine(System<D> system, const CollisionRule& rule)
    : system_(std::move(system)), rule_(rule) {
  for (const Particle<D>& p : system_.particles) now_ = std::max(now_, p.time);
  if (system_.box.periodic()) {
    for (std::size_t k = 0; k < D; ++k) {
      if (!(system_.box.size[k] > 4.0 * largest_radius(system_))) {
        throw std::invalid_argument(
            "a periodic box side must exceed two diameters of the largest particle");
      }
    }
  }
}

template <std::size_t D>
void Engine<D>::apply(const Event& event) {
  // Simultaneous events are common (corners, symmetric starts) but bounded: a few per particle.
  events_at_now_ = event.time == now_ ? events_at_now_ + 1 : 0;
  if (events_at_now_ > 64 * system_.particles.size() + 1000) {
    throw JamError(fmt::format(
        "the disks are jammed: {} collisions at t = {} without time advancing (particle {} "
        "cannot move apart from {}; is a disk wedged exactly between two walls?)",
        events_at_now_, event.time, event.first, event.partner));
  }
  now_ = event.time;
  const double t = event.time;
  Particle<D>& a = system_.particles[event.first];
  if (event.is_wall()) {
    advance(a, t);
    counts_.wall_momentum += bounce(a, event.partner, system_.box);
    ++counts_.wall_collisions;
  } else {
    Particle<D>& b = system_.particles[static_cast<std::size_t>(event.partner)];
    const bool recent = t - a.time < rule_.elastic_within || t - b.time < rule_.elastic_within;
    const bool elastic_by_tc = recent && rule_.restitution < 1.0;
    advance(a, t);
    advance(b, t);
    counts_.virial += collide(a, b, separation(a, b, system_.box), rule_.rule,
                              elastic_by_tc ? 1.0 : rule_.restitution);
    wrap(a.position, system_.box);
    wrap(b.position, system_.box);
    ++counts_.pair_collisions;
    if (elastic_by_tc) ++counts_.elastic_by_tc;
  }
  ++counts_.events;
}

template <std::size_t D>
Vec<D> Engine<D>::image(std::uint32_t i, std::uint32_t j, double t) const {
  if (!system_.box.periodic()) return Vec<D>{};
  const auto& particles = system_.particles;
  return image_offset(position_at(particles[i], t) - position_at(particles[j], t), system_.box);
}

template <std::size_t D>
double Engine<D>::image_horizon() const {
  if (!system_.box.periodic()) return kNever;
  const double speed = speed_bound(system_);
  const double largest = largest_radius(system_);
  const double room = shortest_side(system_.box) / 2.0 - 2.0 * largest;
  return speed > 0.0 ? room / (2.0 * speed) : kNever;
}

template <std::size_t D>
void Engine<D>::throw_too_fast(double t) const {
  throw JamError(fmt::format(
      "the disks move too fast for the box: at t = {} a double cannot resolve the time it takes "
      "them to cross it ({} at most); rescale the velocities or the time unit",
      t, image_horizon()));
}

template <std::size_t D>
void Engine<D>::finish(double end_time) {
  if (end_time < now_) throw std::logic_error("Engine::finish: end time precedes the last event");
  for (Particle<D>& p : system_.particles) {
    advance(p, end_time);
    wrap(p.position, system_.box);
  }
  now_ = end_time;
  resync();
}

template <std::size_t D>
std::unique_ptr<Engine<D>> make_engine(EngineKind kind, System<D> system,
                                       const CollisionRule& rule) {
  if (kind == EngineKind::reference) {
    return std::make_unique<ReferenceEngine<D>>(std::move(system), rule);
  }
  return std::make_unique<FastEngine<D>>(std::move(system), rule);
}

std::string_view rule_name(Rule rule) {
  return rule == Rule::swap ? "swap" : "elastic";
}

std::string_view boundary_name(Boundary boundary) {
  return boundary == Boundary::walls ? "walls" : "periodic";
}

std::string_view engine_name(EngineKind kind) {
  return kind == EngineKind::fast ? "fast" : "reference";
}

template class Engine<2>;
template class Engine<3>;
template std::unique_ptr<Engine<2>> make_engine(EngineKind, System<2>, const CollisionRule&);
template std::unique_ptr<Engine<3>> make_engine(EngineKind, System<3>, const CollisionRule&);

}  // namespace carom
