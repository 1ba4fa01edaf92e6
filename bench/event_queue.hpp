// A priority queue holding exactly one pending event per particle: a 4-ary min-heap indexed by
// particle, so that a particle's event can be replaced in O(log N) without leaving stale copies.
// Entries are 16 bytes (time and particle), four siblings to a cache line; the tie-break order of
// equal times lives beside the heap, as it is needed only for exact ties.
//
// The engine uses the calendar (src/engine/event_calendar.hpp), which is faster at every size; the
// heap is no library code: it stays here as the microbenchmarks' baseline and as a second, simpler
// ordering the tests hold the calendar to.
#pragma once

#include <cstdint>
#include <vector>

#include "carom/core/event.hpp"
#include "carom/core/physics.hpp"

namespace carom {

class EventQueue {
 public:
  explicit EventQueue(std::uint32_t particles)
      : heap_(particles), slot_(particles), order_(particles, kNoEvent.order) {
    for (std::uint32_t i = 0; i < particles; ++i) {
      heap_[i] = {kNoEvent.time, i};
      slot_[i] = i;
    }
  }

  std::uint32_t top() const { return heap_.front().particle; }
  EventKey top_key() const { return key(top()); }
  EventKey key(std::uint32_t particle) const {
    return {heap_[slot_[particle]].time, order_[particle]};
  }

  // Replaces the pending event of `particle`.
  void update(std::uint32_t particle, const EventKey& key) {
    const std::uint32_t at = slot_[particle];
    const bool earlier = key < this->key(particle);
    heap_[at].time = key.time;
    order_[particle] = key.order;
    if (earlier) {
      sift_up(at);
    } else {
      sift_down(at);
    }
  }

 private:
  static constexpr std::uint32_t kArity = 4;

  struct Entry {
    double time;
    std::uint32_t particle;
  };

  // By time, then the event's tie-break order, then the particle (both partners of a pair hold
  // the same event): the order never depends on the history of the heap.
  bool before(const Entry& a, const Entry& b) const {
    if (a.time != b.time) return a.time < b.time;
    const std::uint64_t oa = order_[a.particle], ob = order_[b.particle];
    return oa != ob ? oa < ob : a.particle < b.particle;
  }

  void place(std::uint32_t at, const Entry& e) {
    heap_[at] = e;
    slot_[e.particle] = at;
  }

  void sift_up(std::uint32_t at) {
    const Entry e = heap_[at];
    while (at > 0) {
      const std::uint32_t parent = (at - 1) / kArity;
      if (!before(e, heap_[parent])) break;
      place(at, heap_[parent]);
      at = parent;
    }
    place(at, e);
  }

  void sift_down(std::uint32_t at) {
    const Entry e = heap_[at];
    const auto n = static_cast<std::uint32_t>(heap_.size());
    while (true) {
      const std::uint32_t first = kArity * at + 1;
      if (first >= n) break;
      std::uint32_t best = first;
      const std::uint32_t last = first + kArity < n ? first + kArity : n;
      for (std::uint32_t child = first + 1; child < last; ++child) {
        if (before(heap_[child], heap_[best])) best = child;
      }
      if (!before(heap_[best], e)) break;
      place(at, heap_[best]);
      at = best;
    }
    place(at, e);
  }

  std::vector<Entry> heap_;
  std::vector<std::uint32_t> slot_;   // where each particle's entry is in heap_
  std::vector<std::uint64_t> order_;  // each particle's event tie-break order (EventKey::order)
};

}  // namespace carom
