#include "fast_engine.hpp"
#include "large_pages.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace carom {

template <std::size_t D>
FastEngine<D>::FastEngine(System<D> system, const CollisionRule& rule, const Growth& growth)
    : Engine<D>(std::move(system), rule, growth),
      wide_(cpu_has_avx2()),
      sheared_(this->system_.box.sheared()),
      grid_(this->system_.box, 2.0 * this->largest_reach(), this->system_.particles.size()),
      queue_(static_cast<std::uint32_t>(this->system_.particles.size() + 1)),
      pending_(this->system_.particles.size()),
      clock_(this->now_),
      horizon_slot_(static_cast<std::uint32_t>(this->system_.particles.size())) {
  if (this->system_.box.periodic()) {
    for (std::size_t k = 0; k < D; ++k) {
      if (grid_.cells_along(k) < 5) horizon_ = this->image_horizon();
    }
  }
  // Across a sheared boundary the nearest image changes as the images slide: renewed always.
  if (sheared_) {
    horizon_ = this->image_horizon();
    layer_.assign(this->system_.size(), 0);
    // With five cells or more along every axis, only the images across the sheared boundary are
    // ambiguous (see the header).
    edge_rows_renewed_ = true;
    for (std::size_t k = 0; k < D; ++k) {
      edge_rows_renewed_ = edge_rows_renewed_ && grid_.cells_along(k) >= 5;
    }
  }
  locate_all();
  // What an event reads and writes, in large pages (large_pages.hpp).
  prefer_large_pages(this->system_);
  grid_.prefer_large_pages();
  queue_.prefer_large_pages();
  prefer_large_pages(pending_);
  predict_all();
}

template <std::size_t D>
std::pair<Vec<D>, Vec<D>> FastEngine<D>::grid_motion(std::uint32_t i, double t) const {
  const Particle<D>& p = this->system_.particles[i];
  std::pair<Vec<D>, Vec<D>> motion{position_at(p, t), p.velocity};
  if (sheared_ && layer_[i] != 0) {
    const Box<D>& box = this->system_.box;
    const double layers = layer_[i];
    motion.first[0] -= layers * box.sheared_shift(t);
    motion.first[1] -= layers * box.size[1];
    motion.second[0] -= layers * box.image_speed();
  }
  return motion;
}

template <std::size_t D>
typename CellGrid<D>::Crossing FastEngine<D>::sheared_crossing(std::uint32_t i) const {
  const auto [position, velocity] = grid_motion(i, clock_);
  return grid_.next_crossing(grid_.cell_of(i), position, velocity);
}

template <std::size_t D>
void FastEngine<D>::locate_all() {
  const auto& particles = this->system_.particles;
  const auto n = static_cast<std::uint32_t>(particles.size());
  const Box<D>& box = this->system_.box;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (sheared_) {
      layer_[i] =
          static_cast<std::int32_t>(std::floor(position_at(particles[i], clock_)[1] / box.size[1]));
    }
    const std::uint32_t cell = grid_.locate(grid_motion(i, clock_).first);
    if (grid_.cell_of(i) == CellGrid<D>::kNone) {
      grid_.insert(i, cell);
    } else if (cell != grid_.cell_of(i)) {
      grid_.move(i, cell);
    }
  }
}

template <std::size_t D>
void FastEngine<D>::cross_shear(std::uint32_t i, bool upward) {
  layer_[i] += upward ? 1 : -1;
  auto [position, velocity] = grid_motion(i, clock_);
  // Into the far edge row, whatever a hair of round-off says of y.
  const Box<D>& box = this->system_.box;
  position[1] = upward ? 0.0 : std::nextafter(box.size[1], 0.0);
  grid_.move(i, grid_.locate(position));
  this->raise_speed_bound(norm2(velocity));
  shorten_horizon();
  predict(i);
}

template <std::size_t D>
void FastEngine<D>::rebased(double) {
  // Back to the last event (crossings since then are found again), every particle in the cell it
  // is in then, every prediction made afresh from the shifted states, as the reference engine
  // makes them.
  const auto n = static_cast<std::uint32_t>(this->system_.particles.size());
  clock_ = this->now_;
  locate_all();
  if (sheared_) horizon_ = this->image_horizon();  // with the speeds made afresh
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
void FastEngine<D>::renew() {
  if (!edge_rows_renewed_) {
    predict_all();
    return;
  }
  // Only pairs across the sheared boundary see their nearest image change: those of the edge
  // rows (a particle elsewhere cannot touch across it before it enters one, and is then
  // predicted afresh).
  grid_.for_each_in_edge_rows([this](std::uint32_t i) { predict(i); });
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
void FastEngine<D>::velocity_reset(std::uint32_t i) {
  clock_ = this->now_;
  if (sheared_) layer_[i] = 0;  // stored inside the box again (Engine::reset_velocity)
  shorten_horizon();
  predict(i);
}

template <std::size_t D>
void FastEngine<D>::shorten_horizon() {
  if (horizon_ == kNever) return;
  if (!this->growing()) {
    // What is left of the room the predictions had is used up faster by as much as the particles
    // sped up.
    const double before = horizon_;
    horizon_ = this->image_horizon();
    if (horizon_ < before) {
      renewal_ = clock_ + (renewal_ - clock_) * (horizon_ / before);
      if (renewal_ == clock_ && horizon_ + clock_ == clock_) this->throw_too_fast(clock_);
      queue_.update(horizon_slot_, {renewal_, kNoEvent.order});
    }
    return;
  }
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
    predict_growing(i, layer_axis, layer_upward);
  } else if (sheared_) [[unlikely]] {
    if (wide_) {
      predict_sheared_wide(i, layer_axis, layer_upward);
    } else {
      predict_sheared(i, layer_axis, layer_upward);
    }
  } else if (wide_) {
    predict_wide(i, layer_axis, layer_upward);
  } else {
    predict_narrow(i, layer_axis, layer_upward);
  }
}

template <std::size_t D>
[[gnu::flatten]] void FastEngine<D>::predict_narrow(std::uint32_t i, std::size_t layer_axis,
                                                    bool layer_upward) {
  predict_with(i, layer_axis, layer_upward, NarrowContacts{});
}

template <std::size_t D>
#ifdef CAROM_HAVE_AVX2_KERNEL
[[gnu::flatten, gnu::target("avx2")]] void FastEngine<D>::predict_wide(std::uint32_t i,
                                                                       std::size_t layer_axis,
                                                                       bool layer_upward) {
  predict_with(i, layer_axis, layer_upward, WideContacts{});
}
#else
void FastEngine<D>::predict_wide(std::uint32_t i, std::size_t layer_axis, bool layer_upward) {
  predict_narrow(i, layer_axis, layer_upward);
}
#endif

template <std::size_t D>
[[gnu::flatten]] void FastEngine<D>::predict_growing(std::uint32_t i, std::size_t layer_axis,
                                                     bool layer_upward) {
  predict_with(i, layer_axis, layer_upward, GrowingContacts{this->growth_.rate});
}

template <std::size_t D>
[[gnu::flatten]] void FastEngine<D>::predict_sheared(std::uint32_t i, std::size_t layer_axis,
                                                     bool layer_upward) {
  predict_with(i, layer_axis, layer_upward, ShearedContacts{});
}

template <std::size_t D>
#ifdef CAROM_HAVE_AVX2_KERNEL
[[gnu::flatten, gnu::target("avx2")]] void FastEngine<D>::predict_sheared_wide(
    std::uint32_t i, std::size_t layer_axis, bool layer_upward) {
  predict_with(i, layer_axis, layer_upward, ShearedWideContacts{});
}
#else
void FastEngine<D>::predict_sheared_wide(std::uint32_t i, std::size_t layer_axis,
                                         bool layer_upward) {
  predict_sheared(i, layer_axis, layer_upward);
}
#endif

template <std::size_t D>
template <class Contacts>
void FastEngine<D>::predict_with(std::uint32_t i, std::size_t layer_axis, bool layer_upward,
                                 const Contacts& contacts) {
  const auto& particles = this->system_.particles;
  const Particle<D>& p = particles[i];
  const Box<D> box = this->system_.box;  // a copy, which the loop below can keep in registers
  const Vec<D> here = position_at(p, clock_);
  EarliestEvent<D> earliest;
  if (layer_axis < D) {
    earliest.pending = pending_[i].pending;
    earliest.key = collision_key<D>(pending_[i].pending, pending_[i].time, i);
  } else {
    earliest.start_with_wall(contacts, p, box, i, clock_);
  }
  // The candidates go to the contact kernel in batches. The particle itself, among them or
  // padding a batch to a multiple of the kernel's lanes, is never a contact of its own.
  std::array<std::uint32_t, kMostContacts> batch;
  std::size_t size = 0;
  const auto flush = [&] {
    while (size % Contacts::kLanes != 0) batch[size++] = i;
    earliest.try_batch(contacts, p, here, clock_, box, particles.data(), i, batch.data(), size);
    size = 0;
  };
  const auto gather = [&](std::uint32_t j) {
    batch[size++] = j;
    if (size == kMostContacts) flush();
  };
  const auto prefetch = [&](std::uint32_t j) { __builtin_prefetch(&particles[j]); };
  if (layer_axis < D) {
    grid_.for_each_in_layer(grid_.cell_of(i), layer_axis, layer_upward, prefetch, gather);
  } else {
    grid_.for_each_near(grid_.cell_of(i), prefetch, gather);
    if (sheared_) grid_.for_each_across_shear(grid_.cell_of(i), gather);
  }
  if (size > 0) flush();
  earliest.read_partner_version(this->system_.records);
  Pending best = earliest.pending;
  EventKey best_key = earliest.key;
  const auto crossing =
      sheared_ ? sheared_crossing(i) : grid_.next_crossing(grid_.cell_of(i), here, p.velocity);
  if (crossing.delay != kNever) {
    best.crossing_axis = crossing.axis;
    best.crossing_upward = crossing.upward;
    const EventKey key{clock_ + crossing.delay, after_collisions(i)};
    if (key < best_key) best_key = key;
  }
  pending_[i] = {best, earliest.key.time};
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
void FastEngine<D>::prefetch_entry(std::uint32_t slot, int distance) const {
  if (slot >= horizon_slot_) return;
  if (distance == 2) {
    __builtin_prefetch(&pending_[slot]);
    fetch_ahead(slot);
    return;
  }
  grid_.prefetch_near(grid_.cell_of(slot));
  if (pending_[slot].pending.kind == PendingKind::pair) {
    fetch_ahead(static_cast<std::uint32_t>(pending_[slot].pending.partner));
  }
}

template <std::size_t D>
std::optional<Event> FastEngine<D>::step(double end_time) {
  const auto& records = this->system_.records;
  while (true) {
    // Events a few steps away are known: what they will read is fetched while these are handled,
    // in two stages (what the second reads, the first has fetched).
    const std::uint32_t i =
        queue_.top([&](std::uint32_t slot, int distance) { prefetch_entry(slot, distance); });
    const EventKey key = queue_.top_key();
    const double t = key.time;
    if (t == kNever || !this->due_by(t, end_time)) return std::nullopt;  // kNever: none queued
    switch (entry_kind(i, key)) {
      case EntryKind::renewal:
        clock_ = t;
        renew();
        continue;
      case EntryKind::crossing: {
        clock_ = t;
        const Pending pending = pending_[i].pending;
        const std::size_t axis = pending.crossing_axis;
        const bool upward = pending.crossing_upward;
        if (sheared_ && axis == 1 && grid_.leaves_along_y(grid_.cell_of(i), upward)) [[unlikely]] {
          cross_shear(i, upward);
          continue;
        }
        grid_.move(i, grid_.adjacent(grid_.cell_of(i), axis, upward));
        // Into a sheared box's edge row, the far row's cells around it are new too (all of them,
        // as the images slide): predicted afresh.
        if (sheared_ && grid_.in_edge_row(grid_.cell_of(i))) [[unlikely]] {
          predict(i);
        } else {
          predict(i, axis, upward);
        }
        continue;
      }
      case EntryKind::wall: {
        clock_ = t;
        const Event event = this->apply({t, i, pending_[i].pending.partner});
        predict(i);
        if (this->growing()) shorten_horizon();
        return event;
      }
      case EntryKind::pair: {
        const Pending pending = pending_[i].pending;
        const auto j = static_cast<std::uint32_t>(pending.partner);
        if (records[j].version() != pending.partner_version) {
          predict(i);  // the partner has collided since: this event will not happen
          continue;
        }
        clock_ = t;
        const Event event = this->apply(pair_event(t, i, j));
        if (sheared_) [[unlikely]] {
          layer_[i] = layer_[j] = 0;  // both stored inside the box again (Engine::apply)
          shorten_horizon();
        }
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
