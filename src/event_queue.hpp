// A priority queue holding exactly one pending event per particle: a binary min-heap indexed by
// particle, so that a particle's event can be replaced in O(log N) without leaving stale copies.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "carom/event.hpp"
#include "carom/physics.hpp"

namespace carom {

class EventQueue {
 public:
  static constexpr EventKey kNone{kNever, std::numeric_limits<std::uint64_t>::max()};

  explicit EventQueue(std::uint32_t particles) : heap_(particles), slot_(particles) {
    for (std::uint32_t i = 0; i < particles; ++i) {
      heap_[i] = {kNone, i};
      slot_[i] = i;
    }
  }

  bool empty() const { return heap_.empty(); }
  std::uint32_t top() const { return heap_.front().particle; }
  const EventKey& top_key() const { return heap_.front().key; }
  const EventKey& key(std::uint32_t particle) const { return heap_[slot_[particle]].key; }

  // Replaces the pending event of `particle`.
  void update(std::uint32_t particle, const EventKey& key) {
    std::uint32_t at = slot_[particle];
    const bool earlier = key < heap_[at].key;
    heap_[at].key = key;
    if (earlier) {
      sift_up(at);
    } else {
      sift_down(at);
    }
  }

 private:
  struct Entry {
    EventKey key;
    std::uint32_t particle;
  };

  // Equal keys (both partners of a pair hold the same event) go to the lower particle index, so
  // the order never depends on the history of the heap.
  static bool before(const Entry& a, const Entry& b) {
    return a.key < b.key || (a.key == b.key && a.particle < b.particle);
  }

  void place(std::uint32_t at, const Entry& e) {
    heap_[at] = e;
    slot_[e.particle] = at;
  }

  void sift_up(std::uint32_t at) {
    const Entry e = heap_[at];
    while (at > 0) {
      const std::uint32_t parent = (at - 1) / 2;
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
      std::uint32_t child = 2 * at + 1;
      if (child >= n) break;
      if (child + 1 < n && before(heap_[child + 1], heap_[child])) ++child;
      if (!before(heap_[child], e)) break;
      place(at, heap_[child]);
      at = child;
    }
    place(at, e);
  }

  std::vector<Entry> heap_;
  std::vector<std::uint32_t> slot_;  // where each particle's entry is in heap_
};

}  // namespace carom
