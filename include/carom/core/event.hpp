// A collision event and the total order in which events are processed.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>

namespace carom {

// A processed or pending collision: particle `first` with `partner`, a particle index (>= 0)
// or a wall label (< 0). For a pair, first < partner. A processed one also says what it did.
struct Event {
  double time = 0.0;
  std::uint32_t first = 0;
  std::int32_t partner = 0;
  // A pair: the collision virial r . (momentum given to `first`); a wall: the momentum given to it.
  double impulse = 0.0;
  bool elastic_by_tc = false;  // an inelastic collision made elastic by the TC model
  // The momentum the first particle received (the partner received its opposite), and for a pair
  // the contact vector r = first - partner between the touching images (zero for a wall); the
  // third components are 0 in 2D. What the pressure tensor and the transport moments follow from
  // (fluxes.hpp).
  std::array<double, 3> momentum{};
  std::array<double, 3> contact{};

  bool is_wall() const { return partner < 0; }
  // The same collision: who met whom when (what it did follows from that).
  friend bool operator==(const Event& a, const Event& b) {
    return a.time == b.time && a.first == b.first && a.partner == b.partner;
  }
};

// Events are processed by time; ties (a corner, a symmetric start, several contacts at once)
// go to the lower particle index, then to walls before particles (walls by |label|, particles
// by index). Packing the tie-break into one integer makes comparisons cheap and lets both
// engines order events identically.
struct EventKey {
  double time;
  std::uint64_t order;

  friend bool operator<(const EventKey& a, const EventKey& b) {
    return std::tie(a.time, a.order) < std::tie(b.time, b.order);
  }
  friend bool operator==(const EventKey&, const EventKey&) = default;
};

// No event at all: after every real one, also in the tie-break order.
inline constexpr EventKey kNoEvent{std::numeric_limits<double>::infinity(),
                                   std::numeric_limits<std::uint64_t>::max()};

template <std::size_t D>
constexpr std::uint64_t partner_rank(std::int32_t partner) {
  return partner < 0 ? static_cast<std::uint64_t>(-partner - 1)
                     : 2 * D + static_cast<std::uint64_t>(partner);
}

template <std::size_t D>
constexpr EventKey key_of(const Event& e) {
  return {e.time, (static_cast<std::uint64_t>(e.first) << 32) | partner_rank<D>(e.partner)};
}

// Orders a pair so that first < partner, as the Event invariant requires.
constexpr Event pair_event(double time, std::uint32_t i, std::uint32_t j) {
  return i < j ? Event{time, i, static_cast<std::int32_t>(j)}
               : Event{time, j, static_cast<std::int32_t>(i)};
}

// One line naming an event: `Collision: particle 1 with particle 2` or
// `Collision: particle 3 with wall -2 (right)`.
std::string describe(const Event& event);

}  // namespace carom
