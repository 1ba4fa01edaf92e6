// A priority queue holding exactly one pending event per slot (particle), after Paul (J. Comput.
// Phys. 221, 615, 2007): future events are dropped into time buckets by one multiplication, and
// only the few in the current bucket are kept in order. Replacing an event is O(1); finding the
// next costs O(log k) for the k events sharing a bucket, a handful.
//
// The order is exactly EventQueue's (time, then tie-break order, then slot): buckets are a
// monotone function of time, so every event in an earlier bucket precedes every event in a later
// one, and within the current bucket a binary heap orders by the full key. Times may be replaced
// by earlier ones at any moment (a round-off overlap found late is due at once): anything due no
// later than the current bucket joins the heap.
//
// A year of `buckets` buckets covers the near future; later events wait in an unordered overflow
// list and are distributed when the year runs out. The bucket width is re-tuned at every new year
// from the rate at which events were taken out, so that a bucket holds about two.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "carom/core/event.hpp"
#include "carom/core/physics.hpp"
#include "large_pages.hpp"

namespace carom {

class EventCalendar {
 public:
  explicit EventCalendar(std::uint32_t slots)
      : slot_(slots),
        bucket_(std::max<std::uint32_t>(2 * slots, 16), kEnd),
        year_buckets_(static_cast<double>(bucket_.size())) {}

  // The slot with the earliest event (any slot when none has one: its key is then kNoEvent). When a
  // bucket is entered, ahead(slot, 1) is called for each of its slots and ahead(slot, 2) for each
  // of the next bucket's: events one or a few steps away, whose data the caller may start
  // fetching.
  template <class Ahead>
  std::uint32_t top(Ahead&& ahead) {
    if (current_.empty()) advance(ahead);
    return current_.empty() ? 0 : current_.front().slot;
  }
  std::uint32_t top() {
    return top([](std::uint32_t, int) {});
  }
  EventKey top_key() {
    if (current_.empty()) advance([](std::uint32_t, int) {});
    return current_.empty() ? kNoEvent : current_.front().key;
  }
  EventKey key(std::uint32_t slot) const { return slot_[slot].key; }

  // Replaces the pending event of `slot` (kNoEvent: no event), with 32 bits of the caller's about
  // it (tag(slot) gives them back).
  void update(std::uint32_t slot, const EventKey& key, std::uint32_t tag = 0) {
    remove(slot);
    slot_[slot].key = key;
    slot_[slot].tag = tag;
    if (key.time != kNever) insert(slot);
  }
  std::uint32_t tag(std::uint32_t slot) const { return slot_[slot].tag; }

 private:
  // Slot::where values: a bucket index below kInHeap, or one of these.
  static constexpr std::uint32_t kIdle = 0xFFFFFFFFu;      // no event
  static constexpr std::uint32_t kOverflow = 0xFFFFFFFEu;  // beyond the current year
  static constexpr std::uint32_t kInHeap = 0x80000000u;    // | position in current_
  static constexpr std::uint32_t kEnd = 0xFFFFFFFFu;       // end of a bucket's list
  static constexpr double kPerBucket = 2.0;                // events a bucket is tuned to hold

  // Everything about one slot in one place: a single cache miss reaches it. The tag fills what
  // would be padding: a caller keeps there what it needs when the event comes (the neighbour-list
  // engine, the partner's version), in the line the calendar reads anyway.
  struct alignas(32) Slot {
    EventKey key = kNoEvent;
    std::uint32_t next = kEnd, prev = kEnd;  // neighbours in a bucket's list or the overflow
    std::uint32_t where = kIdle;
    std::uint32_t tag = 0;
  };
  static_assert(sizeof(Slot) == 32);
  struct Entry {
    EventKey key;
    std::uint32_t slot;
  };

  static bool before(const Entry& a, const Entry& b) {
    if (a.key.time != b.key.time) return a.key.time < b.key.time;
    return a.key.order != b.key.order ? a.key.order < b.key.order : a.slot < b.slot;
  }

  // The bucket of `time` in the current year as a double (negative: already due; at least
  // buckets: next year or later). Monotone in time, which is all the order needs.
  double bucket_of(double time) const { return (time - year_start_) * inverse_width_; }

  void insert(std::uint32_t slot) {
    const double at = bucket_of(slot_[slot].key.time);
    if (at < current_end_) {
      heap_push({slot_[slot].key, slot});
    } else if (at < year_buckets_) {
      list_push(bucket_[static_cast<std::uint32_t>(at)], slot, static_cast<std::uint32_t>(at));
    } else {
      list_push(overflow_, slot, kOverflow);
    }
  }

  void remove(std::uint32_t slot) {
    const std::uint32_t at = slot_[slot].where;
    if (at == kIdle) return;
    if (at & kInHeap && at != kOverflow) {
      heap_erase(at & ~kInHeap);
    } else {
      std::uint32_t& head = at == kOverflow ? overflow_ : bucket_[at];
      const Slot& self = slot_[slot];
      if (self.prev != kEnd) {
        slot_[self.prev].next = self.next;
      } else {
        head = self.next;
      }
      if (self.next != kEnd) slot_[self.next].prev = self.prev;
      slot_[slot].where = kIdle;
    }
  }

  void list_push(std::uint32_t& head, std::uint32_t slot, std::uint32_t where) {
    slot_[slot].next = head;
    slot_[slot].prev = kEnd;
    slot_[slot].where = where;
    if (head != kEnd) slot_[head].prev = slot;
    head = slot;
  }

  // Moves on to the next bucket holding events, starting a new year when this one is over.
  template <class Ahead>
  void advance(Ahead&& ahead) {
    const auto buckets = static_cast<std::uint32_t>(bucket_.size());
    while (current_.empty()) {
      if (current_bucket_ + 1 < buckets) {
        ++current_bucket_;
        current_end_ = current_bucket_ + 1.0;
        std::uint32_t& head = bucket_[current_bucket_];
        for (std::uint32_t s = head; s != kEnd; s = slot_[s].next) {
          heap_push({slot_[s].key, s});
          ahead(s, 1);
        }
        head = kEnd;
        if (current_bucket_ + 1 < buckets) {
          for (std::uint32_t s = bucket_[current_bucket_ + 1]; s != kEnd; s = slot_[s].next) {
            ahead(s, 2);
          }
        }
      } else if (!new_year()) {
        return;
      }
    }
  }

  // Starts the year at the earliest overflow event and distributes the overflow over it; false
  // when there is nothing left.
  bool new_year() {
    if (overflow_ == kEnd) return false;
    double earliest = kNever, total_gap = 0.0;
    std::uint64_t waiting = 0;
    for (std::uint32_t s = overflow_; s != kEnd; s = slot_[s].next) {
      earliest = std::min(earliest, slot_[s].key.time);
      ++waiting;
    }
    // The width: from the rate events were taken out of the last year, or, for the first year,
    // from how far ahead the waiting events lie.
    double width = 0.0;
    if (taken_ > 0 && year_end_ > year_start_) {
      width = kPerBucket * (year_end_ - year_start_) / static_cast<double>(taken_);
    } else {
      for (std::uint32_t s = overflow_; s != kEnd; s = slot_[s].next) {
        total_gap += slot_[s].key.time - earliest;
      }
      width = kPerBucket * total_gap / static_cast<double>(waiting) / static_cast<double>(waiting);
    }
    if (!(width > 0.0) || !std::isfinite(1.0 / width)) width = 1.0;
    year_start_ = earliest;
    inverse_width_ = 1.0 / width;
    year_end_ = earliest + width * static_cast<double>(bucket_.size());
    taken_ = 0;
    current_bucket_ = 0;
    current_end_ = 1.0;
    std::uint32_t s = overflow_;
    overflow_ = kEnd;
    while (s != kEnd) {
      const std::uint32_t next = slot_[s].next;
      slot_[s].where = kIdle;
      insert(s);
      s = next;
    }
    return true;
  }

  void heap_push(const Entry& e) {
    current_.push_back(e);
    sift_up(static_cast<std::uint32_t>(current_.size() - 1));
  }

  void heap_erase(std::uint32_t at) {
    slot_[current_[at].slot].where = kIdle;
    if (at == 0) ++taken_;
    const Entry last = current_.back();
    current_.pop_back();
    if (at == current_.size()) return;
    current_[at] = last;
    slot_[last.slot].where = kInHeap | at;
    if (at > 0) sift_up(at);  // the top's replacement can only go down
    sift_down(slot_[last.slot].where & ~kInHeap);
  }

  void heap_place(std::uint32_t at, const Entry& e) {
    current_[at] = e;
    slot_[e.slot].where = kInHeap | at;
  }

  void sift_up(std::uint32_t at) {
    const Entry e = current_[at];
    while (at > 0) {
      const std::uint32_t parent = (at - 1) / 2;
      if (!before(e, current_[parent])) break;
      heap_place(at, current_[parent]);
      at = parent;
    }
    heap_place(at, e);
  }

  void sift_down(std::uint32_t at) {
    const Entry e = current_[at];
    const auto n = static_cast<std::uint32_t>(current_.size());
    while (2 * at + 1 < n) {
      std::uint32_t child = 2 * at + 1;
      if (child + 1 < n && before(current_[child + 1], current_[child])) ++child;
      if (!before(current_[child], e)) break;
      heap_place(at, current_[child]);
      at = child;
    }
    heap_place(at, e);
  }

  std::vector<Slot> slot_;
  std::vector<std::uint32_t> bucket_;  // the head of each bucket's list

 public:
  // Its slots and buckets in large pages (large_pages.hpp).
  void prefer_large_pages() const {
    carom::prefer_large_pages(slot_);
    carom::prefer_large_pages(bucket_);
  }

 private:
  std::vector<Entry> current_;         // the events due by the end of the current bucket, a heap
  std::uint32_t overflow_ = kEnd;      // the head of the list of events after this year
  std::uint32_t current_bucket_ = 0;
  // As doubles, for insert(): the end of the current bucket and of the year, in buckets.
  double current_end_ = 1.0, year_buckets_ = 0.0;
  // Before the first year the width is not yet known: the year lies infinitely far in the past,
  // so that every event waits in the overflow.
  double year_start_ = -kNever, year_end_ = -kNever, inverse_width_ = kNever;
  std::uint64_t taken_ = 0;  // events taken out of the heap's top this year
};

}  // namespace carom
