// The classic assignment's algorithm, done right: after every event, every wall hit and every pair
// contact is predicted again from the stored states and the earliest (by EventKey) is processed.
// O(N^2) per event and obviously correct; the tests hold the fast engine to it.
//
// In a periodic box each pair is predicted through the image nearest at the start of a window
// no longer than image_horizon(), within which no other image can be reached; when nothing
// happens within a window, the next one is examined.
#pragma once

#include "carom/engine/engine.hpp"

namespace carom {

template <std::size_t D>
class ReferenceEngine final : public Engine<D> {
 public:
  ReferenceEngine(System<D> system, const CollisionRule& rule, const Growth& growth = {})
      : Engine<D>(std::move(system), rule, growth),
        horizon_(this->image_horizon()),
        window_start_(this->now_) {}

  std::optional<Event> step(double end_time) override {
    // Growing particles speed up at collisions: the window shrinks with them.
    if (this->growing()) horizon_ = this->image_horizon();
    while (true) {
      // In a sheared box a particle's velocity changes when it crosses the sheared boundary,
      // which this engine does not watch: at most once in a window, as the window is short.
      if (this->system_.box.sheared()) {
        const double drift = std::abs(this->system_.box.image_speed());
        horizon_ = this->image_horizon(this->fastest_in_box(window_start_) + drift);
      }
      Event best = earliest();
      const double window_end = window_start_ + horizon_;
      if (best.time <= window_end || !this->due_by(window_end, end_time)) {
        if (best.time == kNever || !this->due_by(best.time, end_time)) return std::nullopt;
        window_start_ = best.time;
        return this->apply(best);
      }
      if (window_end == window_start_) this->throw_too_fast(window_start_);
      window_start_ = window_end;
    }
  }

 private:
  void rebased(double) override { window_start_ = this->now_; }
  // The window follows the fastest speed the energy allows, which a thermostat changes.
  void velocities_changed() override { horizon_ = this->image_horizon(); }
  // The window restarts where the velocity changed, bounded by the speeds now.
  void velocity_reset(std::uint32_t) override {
    window_start_ = this->now_;
    velocities_changed();
  }

  Event earliest() const {
    const auto& particles = this->system_.particles;
    const auto n = static_cast<std::uint32_t>(particles.size());
    Event best{kNever, 0, 0};
    EventKey best_key = kNoEvent;
    const auto consider = [&](const Event& candidate) {
      const EventKey key = key_of<D>(candidate);
      if (key < best_key) {
        best = candidate;
        best_key = key;
      }
    };
    const double rate = this->growth_.rate;
    const Box<D>& box = this->system_.box;
    for (std::uint32_t i = 0; i < n; ++i) {
      const WallHit hit = this->growing() ? growing_wall_hit(particles[i], this->system_.box, rate)
                                          : next_wall_hit(particles[i], this->system_.box);
      if (hit.time != kNever) consider({std::max(hit.time, window_start_), i, hit.label});
      for (std::uint32_t j = i + 1; j < n; ++j) {
        double t = kNever;
        if (box.sheared()) {
          const Vec<D> apart =
              position_at(particles[i], window_start_) - position_at(particles[j], window_start_);
          t = sheared_contact_time(particles[i], particles[j],
                                   sheared_cells(apart, box, window_start_), box);
        } else {
          const Vec<D> offset = this->image(i, j, window_start_);
          t = this->growing() ? growing_contact_time(particles[i], particles[j], offset, rate)
                              : contact_time(particles[i], particles[j], offset);
        }
        if (t != kNever) consider(pair_event(std::max(t, window_start_), i, j));
      }
    }
    return best;
  }

  double horizon_;
  double window_start_;  // the time the images are taken at
};

}  // namespace carom
