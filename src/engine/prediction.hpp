// What the calendar engines (cells: fast_engine.hpp, neighbour lists: list_engine.hpp) share
// about predicting one particle's next collision: what they keep of it, how they find wall hits
// and contacts (one policy per contact kernel), and how a batch of contact times picks the
// earliest event.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>

#include "carom/core/event.hpp"
#include "carom/core/physics.hpp"
#include "carom/core/system.hpp"
#include "contact_batch.hpp"

namespace carom {

enum class PendingKind : std::uint8_t { none, wall, pair };

// A particle's earliest collision, as predicted, and (for the cell engine) the way out of its
// cell. The calendar holds the collision or the engine's own event for the particle (a cell
// crossing, a neighbour list's renewal), whichever comes first, told apart by the event's order
// (after_collisions, keyed_entry). The cell engine keeps it, with its time, beside the calendar,
// which may hold the crossing instead; the list engine keeps only the partner's version, in the
// calendar entry's tag.
struct Pending {
  std::uint64_t partner_version = 0;  // for a pair: the partner's version when predicted
  std::int32_t partner = 0;           // wall label or particle index
  PendingKind kind = PendingKind::none;
  std::uint8_t crossing_axis = 0;  // cell engine: the crossing is into adjacent(cell, axis, upward)
  bool crossing_upward = false;
};

// The order of an engine's own event for particle i (a cell crossing, a neighbour list renewal):
// after every collision of particle i at the same time, since it changes no physics.
constexpr std::uint64_t after_collisions(std::uint32_t i) {
  return (std::uint64_t{i} << 32) | 0xFFFFFFFFu;
}

// What an entry of a calendar engine's queue stands for: each engine decodes it in one place
// (entry_kind) and handles each kind in one branch of its step.
enum class EntryKind : std::uint8_t {
  renewal,   // the cell engine's horizon entry: every particle predicted afresh
  crossing,  // a particle's own event: into the next cell, or out of its neighbour-list shell
  wall,      // its predicted wall collision
  pair,      // its predicted pair collision (void if the partner has collided since)
};

// Particle i's entry with key `key`, read from the key alone: its own event (ordered
// after_collisions), or the collision key_of ordered (the first particle in the high half, the
// other's partner_rank in the low), whose partner is the wall or the particle other than i.
struct KeyedEntry {
  EntryKind kind;
  std::int32_t partner;  // wall label or particle index; 0 for the particle's own event
};
template <std::size_t D>
constexpr KeyedEntry keyed_entry(std::uint32_t i, const EventKey& key) {
  const auto first = static_cast<std::uint32_t>(key.order >> 32);
  const auto rank = static_cast<std::uint32_t>(key.order);
  if (rank == 0xFFFFFFFFu) return {EntryKind::crossing, 0};
  if (rank < 2 * D) return {EntryKind::wall, -static_cast<std::int32_t>(rank) - 1};
  const std::uint32_t second = rank - 2 * D;
  return {EntryKind::pair, static_cast<std::int32_t>(first == i ? second : first)};
}

// The calendar key of particle i's pending collision at `time` (kNoEvent for none).
template <std::size_t D>
EventKey collision_key(const Pending& pending, double time, std::uint32_t i) {
  switch (pending.kind) {
    case PendingKind::wall:
      return key_of<D>({time, i, pending.partner});
    case PendingKind::pair:
      return key_of<D>(pair_event(time, i, static_cast<std::uint32_t>(pending.partner)));
    default:
      return kNoEvent;
  }
}

// The scalar contact kernel and plain wall hits. kLanes: batches of candidates are padded to a
// multiple of it.
struct NarrowContacts {
  static constexpr std::size_t kLanes = 4;
  template <std::size_t D>
  static WallHit wall_hit(const Particle<D>& p, const Box<D>& box) {
    return next_wall_hit(p, box);
  }
  template <std::size_t D, class Names>
  std::uint64_t operator()(const Particle<D>& a, const Vec<D>& here, double clock,
                           const Box<D>& box, const Particle<D>* particles,
                           const std::uint32_t* candidates, std::size_t count, double limit,
                           double* times, Names names) const {
    return contact_times_scalar(a, here, clock, box, particles, candidates, count, limit, times,
                                names);
  }
  template <std::size_t D>
  std::uint64_t near_points(const Vec<D>& centre, const Vec<D>* points,
                            const std::uint32_t* candidates, std::size_t count, const Box<D>& box,
                            double reach) const {
    return near_points_scalar(centre, points, candidates, count, box, reach);
  }
};

#ifdef CAROM_HAVE_AVX2_KERNEL
// The four-wide kernel, for predictions compiled for AVX2 (which inline it).
struct WideContacts : NarrowContacts {
  template <std::size_t D, class Names>
  [[gnu::target("avx2")]] std::uint64_t operator()(const Particle<D>& a, const Vec<D>& here,
                                                   double clock, const Box<D>& box,
                                                   const Particle<D>* particles,
                                                   const std::uint32_t* candidates,
                                                   std::size_t count, double limit, double* times,
                                                   Names names) const {
    return contact_avx2::contact_times(a, here, clock, box, particles, candidates, count, limit,
                                       times, names);
  }
  template <std::size_t D>
  [[gnu::target("avx2")]] std::uint64_t near_points(const Vec<D>& centre, const Vec<D>* points,
                                                    const std::uint32_t* candidates,
                                                    std::size_t count, const Box<D>& box,
                                                    double reach) const {
    return contact_avx2::near_points(centre, points, candidates, count, box, reach);
  }
};

// The eight-wide kernel, for predictions compiled for AVX-512F.
struct WiderContacts : NarrowContacts {
  static constexpr std::size_t kLanes = 8;
  template <std::size_t D, class Names>
  [[gnu::target("avx512f")]] std::uint64_t operator()(const Particle<D>& a, const Vec<D>& here,
                                                      double clock, const Box<D>& box,
                                                      const Particle<D>* particles,
                                                      const std::uint32_t* candidates,
                                                      std::size_t count, double limit,
                                                      double* times, Names names) const {
    return contact_avx512::contact_times(a, here, clock, box, particles, candidates, count, limit,
                                         times, names);
  }
  template <std::size_t D>
  [[gnu::target("avx512f")]] std::uint64_t near_points(const Vec<D>& centre, const Vec<D>* points,
                                                       const std::uint32_t* candidates,
                                                       std::size_t count, const Box<D>& box,
                                                       double reach) const {
    return contact_avx512::near_points(centre, points, candidates, count, box, reach);
  }
};
#endif

// The contact kernels' contract for policies that take one candidate at a time: time_of(b) for
// each candidate but the particle itself (kNever), and the mask of those no later than `limit`.
template <std::size_t D, class Names, class TimeOf>
std::uint64_t one_at_a_time(const Particle<D>& a, const Particle<D>* particles,
                            const std::uint32_t* candidates, std::size_t count, double limit,
                            double* times, Names, TimeOf&& time_of) {
  std::uint64_t soon = 0;
  for (std::size_t n = 0; n < count; ++n) {
    const Particle<D>& b = particles[Names::template index<D>(candidates[n])];
    times[n] = &b == &a ? kNever : time_of(b);
    if (times[n] <= limit && times[n] != kNever) soon |= std::uint64_t{1} << n;
  }
  return soon;
}

// Growing particles (see Growth): their own wall hits and contacts, one candidate at a time.
struct GrowingContacts {
  static constexpr std::size_t kLanes = 4;
  double rate;
  template <std::size_t D>
  WallHit wall_hit(const Particle<D>& p, const Box<D>& box) const {
    return growing_wall_hit(p, box, rate);
  }
  template <std::size_t D, class Names>
  std::uint64_t operator()(const Particle<D>& a, const Vec<D>& here, double clock,
                           const Box<D>& box, const Particle<D>* particles,
                           const std::uint32_t* candidates, std::size_t count, double limit,
                           double* times, Names names) const {
    // Unlike the fixed-size contact, a growing particle overlaps itself: one_at_a_time skips it.
    return one_at_a_time(
        a, particles, candidates, count, limit, times, names, [&](const Particle<D>& b) {
          const Vec<D> offset =
              box.periodic() ? image_offset(here - position_at(b, clock), box) : Vec<D>{};
          return growing_contact_time(a, b, offset, rate);
        });
  }
};

// Particles in a sheared box (Box::sheared): each candidate through the image nearest at the
// time of the prediction, one at a time. No walls.
struct ShearedContacts {
  static constexpr std::size_t kLanes = 4;
  template <std::size_t D>
  static WallHit wall_hit(const Particle<D>&, const Box<D>&) {
    return {};
  }
  template <std::size_t D, class Names>
  std::uint64_t operator()(const Particle<D>& a, const Vec<D>& here, double clock,
                           const Box<D>& box, const Particle<D>* particles,
                           const std::uint32_t* candidates, std::size_t count, double limit,
                           double* times, Names names) const {
    return one_at_a_time(
        a, particles, candidates, count, limit, times, names, [&](const Particle<D>& b) {
          const Vec<D> cells = sheared_cells(here - position_at(b, clock), box, clock);
          return sheared_contact_time(a, b, cells, box, limit);
        });
  }
};

#ifdef CAROM_HAVE_AVX2_KERNEL
// The same with the four-wide kernel where it gives the same times: in a batch none of whose
// candidates lies across the sheared boundary (each within half a box along y at the clock),
// every nearest image is one of a box at rest, and the wide kernel computes what
// sheared_contact_time would, bit for bit; any other batch goes one candidate at a time.
struct ShearedWideContacts : ShearedContacts {
  template <std::size_t D, class Names>
  [[gnu::target("avx2")]] std::uint64_t operator()(const Particle<D>& a, const Vec<D>& here,
                                                   double clock, const Box<D>& box,
                                                   const Particle<D>* particles,
                                                   const std::uint32_t* candidates,
                                                   std::size_t count, double limit, double* times,
                                                   Names names) const {
    const double half = 0.5 * box.size[1];
    for (std::size_t n = 0; n < count; ++n) {
      const Particle<D>& b = particles[Names::template index<D>(candidates[n])];
      if (!(std::abs(here[1] - position_at(b, clock)[1]) <= half)) {
        return ShearedContacts::operator()(a, here, clock, box, particles, candidates, count, limit,
                                           times, names);
      }
    }
    return contact_avx2::contact_times(a, here, clock, box, particles, candidates, count, limit,
                                       times, names);
  }
};
#endif

// The earliest event of particle i so far (its key and what it is) while batches of candidates
// are tried against it.
template <std::size_t D>
struct EarliestEvent {
  EventKey key = kNoEvent;
  Pending pending;
  bool new_partner = false;  // a pair found here: its partner's version is still to be read

  // Starts from the particle's wall hit, if any.
  template <class Contacts>
  void start_with_wall(const Contacts& contacts, const Particle<D>& p, const Box<D>& box,
                       std::uint32_t i, double clock) {
    const WallHit hit = contacts.wall_hit(p, box);
    if (hit.time != kNever) {
      key = key_of<D>({std::max(hit.time, clock), i, hit.label});
      pending = {0, hit.label, PendingKind::wall};
    }
  }

  // Tries `count` candidates (at most kMostContacts, a multiple of Contacts::kLanes, named as
  // Names says; the particle itself may be among them) against particle i, seen at `here` at
  // `clock`.
  template <class Contacts, class Names = ByIndex>
  void try_batch(const Contacts& contacts, const Particle<D>& p, const Vec<D>& here, double clock,
                 const Box<D>& box, const Particle<D>* particles, std::uint32_t i,
                 const std::uint32_t* candidates, std::size_t count, Names names = {}) {
    std::array<double, kMostContacts> times;
    // Only candidates touching no later than the best so far come back: one test settles the
    // rest, most of them.
    for (std::uint64_t soon = contacts(p, here, clock, box, particles, candidates, count, key.time,
                                       times.data(), names);
         soon != 0; soon &= soon - 1) {
      const auto n = static_cast<std::size_t>(std::countr_zero(soon));
      const double time = std::max(times[n], clock);
      // A later contact cannot come first: only one no later than the best is keyed and compared.
      if (time > key.time) continue;
      const std::uint32_t j = Names::template index<D>(candidates[n]);
      const EventKey candidate = key_of<D>(pair_event(time, i, j));
      if (candidate < key) {
        key = candidate;
        pending = {0, static_cast<std::int32_t>(j), PendingKind::pair};
        new_partner = true;
      }
    }
  }

  // The winner's version only: the counters are cold data, apart from the state.
  void read_partner_version(const std::vector<ParticleRecord>& records) {
    if (new_partner) pending.partner_version = records[pending.partner].version();
  }
};

}  // namespace carom
