#include "fast_engine.hpp"

#include <algorithm>

namespace carom {

template <std::size_t D>
FastEngine<D>::FastEngine(System<D> system, const CollisionRule& rule, const Growth& growth)
    : Engine<D>(std::move(system), rule, growth),
      grid_(this->system_.box, 2.0 * this->largest_reach(), this->system_.particles.size()),
      queue_(static_cast<std::uint32_t>(this->system_.particles.size() + 1)),
      pending_(this->system_.particles.size() + 1),
      clock_(this->now_),
      horizon_slot_(static_cast<std::uint32_t>(this->system_.particles.size())) {
  const auto& particles = this->system_.particles;
  const auto n = static_cast<std::uint32_t>(particles.size());
  if (this->system_.box.periodic()) {
    for (std::size_t k = 0; k < D; ++k) {
      if (grid_.cells_along(k) < 5) horizon_ = this->image_horizon();
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    grid_.insert(i, grid_.locate(position_at(particles[i], clock_)));
  }
  predict_all();
}

template <std::size_t D>
void FastEngine<D>::rebased(double) {
  // Back to the last event (crossings since then are found again), every particle in the cell it
  // is in then, every prediction made afresh from the shifted states, as the reference engine
  // makes them.
  const auto& particles = this->system_.particles;
  const auto n = static_cast<std::uint32_t>(particles.size());
  clock_ = this->now_;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t cell = grid_.locate(position_at(particles[i], clock_));
    if (cell != grid_.cell_of(i)) grid_.move(i, cell);
  }
  queue_ = EventCalendar(n + 1);
  predict_all();
}

template <std::size_t D>
void FastEngine<D>::predict_all() {
  const auto n = static_cast<std::uint32_t>(this->system_.particles.size());
  for (std::uint32_t i = 0; i < n; ++i) predict(i);
  schedule_horizon();
}

template <std::size_t D>
void FastEngine<D>::schedule_horizon() {
  if (horizon_ == kNever) return;
  if (clock_ + horizon_ == clock_) this->throw_too_fast(clock_);
  pending_[horizon_slot_] = {Kind::horizon, 0, 0, 0};
  renewal_ = clock_ + horizon_;
  queue_.update(horizon_slot_, {renewal_, kNoEvent.order});  // after every event then
}

template <std::size_t D>
void FastEngine<D>::shorten_horizon() {
  if (horizon_ == kNever) return;
  horizon_ = this->image_horizon();
  if (clock_ + horizon_ == clock_) this->throw_too_fast(clock_);
  if (clock_ + horizon_ < renewal_) {
    renewal_ = clock_ + horizon_;
    queue_.update(horizon_slot_, {renewal_, kNoEvent.order});
  }
}

template <std::size_t D>
void FastEngine<D>::predict(std::uint32_t i) {
  if (this->growing()) [[unlikely]] {
    predict_as<true>(i);
  } else {
    predict_as<false>(i);
  }
}

template <std::size_t D>
template <bool kGrowing>
[[gnu::flatten]] void FastEngine<D>::predict_as(std::uint32_t i) {
  const auto& particles = this->system_.particles;
  const Particle<D>& p = particles[i];
  const bool periodic = this->system_.box.periodic();
  const Vec<D> here = position_at(p, clock_);
  Pending best;
  EventKey best_key = kNoEvent;
  const auto consider = [&](const Event& candidate, const Pending& meaning) {
    const EventKey key = key_of<D>(candidate);
    if (key < best_key) {
      best_key = key;
      best = meaning;
    }
  };

  const double rate = this->growth_.rate;
  const WallHit hit =
      kGrowing ? growing_wall_hit(p, this->system_.box, rate) : next_wall_hit(p, this->system_.box);
  if (hit.time != kNever) {
    consider({std::max(hit.time, clock_), i, hit.label}, {Kind::wall, hit.label, 0, 0});
  }
  const auto prefetch = [&](std::uint32_t j) { __builtin_prefetch(&particles[j]); };
  grid_.for_each_near(grid_.cell_of(i), prefetch, [&](std::uint32_t j) {
    if (j == i) return;
    // The image seen now (as Engine::image), with this particle's position computed once.
    const Vec<D> offset =
        periodic ? image_offset(here - position_at(particles[j], clock_), this->system_.box)
                 : Vec<D>{};
    const double t = kGrowing ? growing_contact_time(p, particles[j], offset, rate)
                              : contact_time(p, particles[j], offset, best_key.time);
    if (t == kNever) return;
    consider(pair_event(std::max(t, clock_), i, j),
             {Kind::pair, static_cast<std::int32_t>(j), 0, 0});
  });
  // The winner's version only: the counters are cold data, apart from the state.
  if (best.kind == Kind::pair) best.partner_version = this->system_.records[best.partner].version();
  const auto crossing = grid_.next_crossing(grid_.cell_of(i), here, p.velocity);
  if (crossing.delay != kNever) {
    // Ordered after every collision of particle i at the same time: crossing changes no physics.
    const EventKey key{clock_ + crossing.delay, (std::uint64_t{i} << 32) | 0xFFFFFFFFu};
    if (key < best_key) {
      best_key = key;
      best = {Kind::crossing, 0, crossing.cell, 0};
    }
  }
  pending_[i] = best;
  queue_.update(i, best_key);
}

template <std::size_t D>
void FastEngine<D>::fetch_ahead(std::uint32_t i) const {
  const auto* state = reinterpret_cast<const char*>(&this->system_.particles[i]);
  __builtin_prefetch(state);
  __builtin_prefetch(state + sizeof(Particle<D>) - 1);  // a disk's 48 bytes may straddle lines
  __builtin_prefetch(&this->system_.records[i]);        // the counters, whose sum is the version
  grid_.prefetch_cell_of(i);
}

template <std::size_t D>
std::optional<Event> FastEngine<D>::step(double end_time) {
  const auto& records = this->system_.records;
  while (true) {
    // Events a few steps away are known: what they will read is fetched while these are handled,
    // in two stages (what the second reads, the first has fetched).
    const std::uint32_t i = queue_.top([&](std::uint32_t s, int distance) {
      if (s >= horizon_slot_) return;
      if (distance == 2) {
        __builtin_prefetch(&pending_[s]);
        fetch_ahead(s);
        return;
      }
      grid_.prefetch_near(grid_.cell_of(s));
      if (pending_[s].kind == Kind::pair)
        fetch_ahead(static_cast<std::uint32_t>(pending_[s].partner));
    });
    const double t = queue_.top_key().time;
    if (!this->due_by(t, end_time)) return std::nullopt;
    const Pending pending = pending_[i];
    switch (pending.kind) {
      case Kind::none:
        return std::nullopt;
      case Kind::horizon:
        clock_ = t;
        predict_all();
        break;
      case Kind::crossing:
        clock_ = t;
        grid_.move(i, pending.cell);
        predict(i);
        break;
      case Kind::wall: {
        clock_ = t;
        const Event event = this->apply({t, i, pending.partner});
        predict(i);
        if (this->growing()) shorten_horizon();
        return event;
      }
      case Kind::pair: {
        const auto j = static_cast<std::uint32_t>(pending.partner);
        if (records[j].version() != pending.partner_version) {
          predict(i);  // the partner has collided since: this event will not happen
          break;
        }
        clock_ = t;
        const Event event = this->apply(pair_event(t, i, j));
        predict(i);
        predict(j);
        if (this->growing()) shorten_horizon();
        return event;
      }
    }
  }
}

template class FastEngine<2>;
template class FastEngine<3>;

}  // namespace carom
