// The seed's algorithm, done right: after every event, every wall hit and every pair contact is
// predicted again from the stored states and the earliest (by EventKey) is processed. O(N^2)
// per event and obviously correct; the tests hold the fast engine to it.
#pragma once

#include "carom/engine.hpp"

namespace carom {

template <std::size_t D>
class ReferenceEngine final : public Engine<D> {
 public:
  ReferenceEngine(System<D> system, Rule rule) : Engine<D>(std::move(system), rule) {}

  std::optional<Event> step(double end_time) override {
    const auto& particles = this->system_.particles;
    const auto n = static_cast<std::uint32_t>(particles.size());
    Event best{kNever, 0, 0};
    EventKey best_key{kNever, ~std::uint64_t{0}};
    const auto consider = [&](const Event& candidate) {
      const EventKey key = key_of<D>(candidate);
      if (key < best_key) {
        best = candidate;
        best_key = key;
      }
    };
    for (std::uint32_t i = 0; i < n; ++i) {
      const WallHit hit = next_wall_hit(particles[i], this->system_.box);
      if (hit.time != kNever) consider({std::max(hit.time, this->now_), i, hit.label});
      for (std::uint32_t j = i + 1; j < n; ++j) {
        const double t = contact_time(particles[i], particles[j]);
        if (t != kNever) consider(pair_event(std::max(t, this->now_), i, j));
      }
    }
    if (!(best.time <= end_time)) return std::nullopt;
    this->apply(best);
    return best;
  }
};

}  // namespace carom
