#include "fast_engine.hpp"

#include <algorithm>

namespace carom {

template <std::size_t D>
FastEngine<D>::FastEngine(System<D> system, const CollisionRule& rule, const Growth& growth)
    : Engine<D>(std::move(system), rule, growth),
      grid_(this->system_.box, 2.0 * this->largest_reach(), this->system_.particles.size()),
      queue_(static_cast<std::uint32_t>(this->system_.particles.size() + 1)),
      pending_(this->system_.particles.size()),
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
void FastEngine<D>::predict(std::uint32_t i, std::size_t layer_axis, bool layer_upward) {
  if (this->growing()) [[unlikely]] {
    predict_as<true>(i, layer_axis, layer_upward);
  } else {
    predict_as<false>(i, layer_axis, layer_upward);
  }
}

template <std::size_t D>
EventKey FastEngine<D>::collision_key(std::uint32_t i) const {
  const Pending& pending = pending_[i];
  switch (pending.kind) {
    case Kind::wall:
      return key_of<D>({pending.time, i, pending.partner});
    case Kind::pair:
      return key_of<D>(pair_event(pending.time, i, static_cast<std::uint32_t>(pending.partner)));
    default:
      return kNoEvent;
  }
}

template <std::size_t D>
template <bool kGrowing>
[[gnu::flatten]] void FastEngine<D>::predict_as(std::uint32_t i, std::size_t layer_axis,
                                                bool layer_upward) {
  const auto& particles = this->system_.particles;
  const Particle<D>& p = particles[i];
  const Box<D> box = this->system_.box;  // a copy, which the loop below can keep in registers
  const bool periodic = box.periodic();
  const double rate = this->growth_.rate;
  const Vec<D> here = position_at(p, clock_);
  Pending best;
  EventKey best_key = kNoEvent;
  if (layer_axis < D) {
    best = pending_[i];
    best_key = collision_key(i);
  } else {
    const WallHit hit = kGrowing ? growing_wall_hit(p, box, rate) : next_wall_hit(p, box);
    if (hit.time != kNever) {
      best_key = key_of<D>({std::max(hit.time, clock_), i, hit.label});
      best = {best_key.time, 0, hit.label, Kind::wall};
    }
  }
  bool new_partner = false;
  const auto consider = [&](std::uint32_t j) {
    if (j == i) return;
    // The image seen now (as Engine::image), with this particle's position computed once.
    const Vec<D> offset =
        periodic ? image_offset(here - position_at(particles[j], clock_), box) : Vec<D>{};
    const double t = kGrowing ? growing_contact_time(p, particles[j], offset, rate)
                              : contact_time(p, particles[j], offset, best_key.time);
    if (t == kNever) return;
    const EventKey key = key_of<D>(pair_event(std::max(t, clock_), i, j));
    if (key < best_key) {
      best_key = key;
      best = {key.time, 0, static_cast<std::int32_t>(j), Kind::pair};
      new_partner = true;
    }
  };
  const auto prefetch = [&](std::uint32_t j) { __builtin_prefetch(&particles[j]); };
  if (layer_axis < D) {
    grid_.for_each_in_layer(grid_.cell_of(i), layer_axis, layer_upward, prefetch, consider);
  } else {
    grid_.for_each_near(grid_.cell_of(i), prefetch, consider);
  }
  // The winner's version only: the counters are cold data, apart from the state.
  if (new_partner) best.partner_version = this->system_.records[best.partner].version();
  const auto crossing = grid_.next_crossing(grid_.cell_of(i), here, p.velocity);
  if (crossing.delay != kNever) {
    best.crossing_axis = crossing.axis;
    best.crossing_upward = crossing.upward;
    const EventKey key{clock_ + crossing.delay, crossing_order(i)};
    if (key < best_key) best_key = key;
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
    const EventKey key = queue_.top_key();
    const double t = key.time;
    if (t == kNever || !this->due_by(t, end_time)) return std::nullopt;  // kNever: none queued
    if (i == horizon_slot_) {
      clock_ = t;
      predict_all();
      continue;
    }
    const Pending pending = pending_[i];
    if (key.order == crossing_order(i)) {
      clock_ = t;
      const std::size_t axis = pending.crossing_axis;
      grid_.move(i, grid_.adjacent(grid_.cell_of(i), axis, pending.crossing_upward));
      predict(i, axis, pending.crossing_upward);
      continue;
    }
    if (pending.kind == Kind::wall) {
      clock_ = t;
      const Event event = this->apply({t, i, pending.partner});
      predict(i);
      if (this->growing()) shorten_horizon();
      return event;
    }
    const auto j = static_cast<std::uint32_t>(pending.partner);
    if (records[j].version() != pending.partner_version) {
      predict(i);  // the partner has collided since: this event will not happen
      continue;
    }
    clock_ = t;
    const Event event = this->apply(pair_event(t, i, j));
    predict(i);
    predict(j);
    if (this->growing()) shorten_horizon();
    return event;
  }
}

template class FastEngine<2>;
template class FastEngine<3>;

}  // namespace carom
