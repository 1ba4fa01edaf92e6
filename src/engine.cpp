#include "carom/engine.hpp"

#include <stdexcept>

#include "fast_engine.hpp"
#include "reference_engine.hpp"

namespace carom {

template <std::size_t D>
Engine<D>::Engine(System<D> system, Rule rule) : system_(std::move(system)), rule_(rule) {
  for (const Particle<D>& p : system_.particles) now_ = std::max(now_, p.time);
}

template <std::size_t D>
void Engine<D>::apply(const Event& event) {
  now_ = event.time;
  Particle<D>& a = system_.particles[event.first];
  advance(a, event.time);
  if (event.is_wall()) {
    bounce(a, event.partner, system_.box);
    ++counts_.wall_collisions;
  } else {
    Particle<D>& b = system_.particles[static_cast<std::size_t>(event.partner)];
    advance(b, event.time);
    collide(a, b, rule_);
    ++counts_.pair_collisions;
  }
  ++counts_.events;
}

template <std::size_t D>
void Engine<D>::finish(double end_time) {
  if (end_time < now_) throw std::logic_error("Engine::finish: end time precedes the last event");
  for (Particle<D>& p : system_.particles) advance(p, end_time);
  now_ = end_time;
}

template <std::size_t D>
std::unique_ptr<Engine<D>> make_engine(EngineKind kind, System<D> system, Rule rule) {
  if (kind == EngineKind::reference) {
    return std::make_unique<ReferenceEngine<D>>(std::move(system), rule);
  }
  return std::make_unique<FastEngine<D>>(std::move(system), rule);
}

std::string_view rule_name(Rule rule) {
  return rule == Rule::swap ? "swap" : "elastic";
}

std::string_view engine_name(EngineKind kind) {
  return kind == EngineKind::fast ? "fast" : "reference";
}

template class Engine<2>;
template class Engine<3>;
template std::unique_ptr<Engine<2>> make_engine(EngineKind, System<2>, Rule);
template std::unique_ptr<Engine<3>> make_engine(EngineKind, System<3>, Rule);

}  // namespace carom
