// The production engine for dense systems: neighbour lists with a shell (after Smallenburg, Eur.
// Phys. J. E 45, 22, 2022; the design, not the code). Each particle keeps the list of particles
// near the point where its list was made (its shell's centre) and predicts only against them; it
// holds one pending event, its earliest collision or the moment it leaves its shell, whichever
// comes first, in the event calendar, and leaving its shell makes its list again.
//
// Why no collision is missed: every particle stays within a shell of thickness s around its
// shell's centre until it makes its list again, so two particles that touch while both are in
// their shells have centres at most 2 (R + s) apart (R the largest radius), and every such pair
// is in both lists
// (the lists are symmetric: whoever makes its list adds itself to its neighbours'). The later of
// the two to change velocity or make its list predicted their contact then.
//
// Where a cell engine looks at the 3^D cells around a particle (about 26 spheres at packing
// 0.45), a list holds about 12; cells are visited only to make a list.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

#include "carom/engine/engine.hpp"
#include "cell_grid.hpp"
#include "event_calendar.hpp"
#include "prediction.hpp"

namespace carom {

// How long until a particle `offset` from its shell's centre, moving at `velocity`, is `radius`
// from it: the later root of |offset + velocity t| = radius, in the form without cancellation; 0
// for a particle already there (by round-off), kNever for one at rest.
template <std::size_t D>
double shell_exit_delay(const Vec<D>& offset, const Vec<D>& velocity, double radius) {
  const double speed2 = norm2(velocity);
  if (speed2 == 0.0) return kNever;
  const double c = norm2(offset) - radius * radius;
  if (!(c < 0.0)) return 0.0;
  const double b = dot(offset, velocity);
  const double root = std::sqrt(b * b - speed2 * c);
  return b <= 0.0 ? (root - b) / speed2 : -c / (b + root);
}

template <std::size_t D>
class ListEngine final : public Engine<D> {
 public:
  // How many largest radii thick shells are at packing fraction `packing`: the measured optima
  // (instructions a collision, N = 10^4, skins from 0.4 to 1.5). Spheres at packing 0.3 cost
  // least at 0.8 (0.7: 0.3 % more, 0.9: 1.2 %, 0.6: 3.2 %), at 0.45 at 0.7 (0.6: 0.2 % more,
  // 0.8: 4 %, 0.9: 8 %).
  // Disks at 0.5 cost least at 1.2 (0.9: 4 % more, 1.5: 5 %), at 0.6 and 0.7 at 0.9 (1.2: 7 and
  // 10 % more): thicker shells the less dense, as a particle goes further between collisions.
  static constexpr double skin(double packing) {
    if constexpr (D == 3) return std::clamp(0.7 + (0.45 - packing) * 2.0 / 3.0, 0.7, 0.8);
    return std::clamp(0.9 + 3.0 * (0.6 - packing), 0.9, 1.2);
  }
  // Lists serve systems at least this densely packed (see suits()): below, a particle leaves its
  // shell every few collisions and the cells' candidates are few. Measured crossovers: spheres
  // near 0.3 (cells 5,860 and lists 5,980 instructions a collision; 5,870 and 9,100 at 0.2),
  // disks near 0.4 (cells 3,600 and lists 4,500 at 0.3; 3,180 and 2,730 at 0.5).
  static constexpr double kLeastPacking = D == 2 ? 0.4 : 0.25;

  // Whether lists serve this system: particles that do not grow in a box not sheared, none of zero
  // size nor much smaller than the largest (a list would hold too many), and in a periodic box one
  // image of each neighbour within reach.
  static bool suits(const System<D>& system, const Growth& growth);

  // Predictions use `kernel` (tests choose each; the widest the CPU runs by default).
  ListEngine(System<D> system, const CollisionRule& rule,
             ContactKernel kernel = widest_contact_kernel());
  std::optional<Event> step(double end_time) override;

  // The neighbours of particle i (their indices), for tests.
  std::vector<std::uint32_t> neighbours(std::uint32_t i) const;
  const Vec<D>& shell_centre(std::uint32_t i) const { return centre_[i]; }
  // How far a particle moves from its shell's centre before it makes its list again.
  double shell() const { return shell_; }

 private:
  void rebased(double shift) override;
  void velocity_reset(std::uint32_t i) override;
  // Every list made afresh around the positions at the clock, every prediction made again.
  void make_all_lists();
  // The event loop with each contact kernel (step() picks one), and with any.
  std::optional<Event> step_scalar(double end_time);
  std::optional<Event> step_avx2(double end_time);
  std::optional<Event> step_avx512(double end_time);
  template <class Contacts>
  std::optional<Event> step_with(double end_time, const Contacts& contacts);
  // For the queue entry of particle i a few entries from the top: the particle and its list.
  void prefetch_entry(std::uint32_t i) const {
    __builtin_prefetch(&this->system_.particles[i]);
    __builtin_prefetch(&slots_[slot(i)]);
  }
  // Particle i's list made again around where it is now (its next event is then predicted).
  template <class Contacts>
  void make_list_with(std::uint32_t i, const Contacts& contacts);
  void add(std::uint32_t i, std::uint32_t j);
  template <class Contacts>
  void remove(std::uint32_t i, std::uint32_t j, const Contacts& contacts);
  // Makes room for a longer list: every list moves to slots eight wider.
  void widen();
  std::size_t slot(std::uint32_t i) const { return std::size_t{i} * capacity_; }

  // Finds the earliest event of particle i from the clock among its neighbours and walls, or its
  // leaving its shell, and queues it.
  template <class Contacts>
  void predict_with(std::uint32_t i, const Contacts& contacts);

  double shell_;  // how far a particle moves from its shell's centre before it makes its list again
  double reach_;  // the farthest apart two centres of neighbours are
  CellGrid<D> grid_;  // the shells' centres, to find neighbours when a list is made
  // Each particle's next event: its key says what it is (keyed_entry) and, for a pair, the tag
  // holds the partner's version when it was predicted (a stale prediction is dropped).
  EventCalendar queue_;
  std::vector<Vec<D>> centre_;
  // Particle i's list in slots_[slot(i) ..], size_[i] long, its neighbours named by offset (see
  // ByOffset: what the contact kernel reads, without a multiplication); the rest of its slots
  // hold i itself, so that a list read in fours or eights is padded by a particle that never
  // touches itself.
  // From malloc, so that widen() grows them in place (realloc moves the pages of a large block
  // without copying them): a std::vector would hold the old slots and the new ones at once,
  // twice the lists' memory at the peak.
  struct FreeSlots {
    void operator()(std::uint32_t* slots) const { std::free(slots); }
  };
  std::unique_ptr<std::uint32_t[], FreeSlots> slots_;
  // Gives slots_ room for `count` slots, keeping what it holds.
  void reserve_slots(std::size_t count);
  std::vector<std::uint32_t> size_;
  // A list being made again keeps its old neighbours here (make_list_with).
  std::vector<std::uint32_t> former_;
  // Slots a particle, a multiple of eight. Not a std::uint32_t, which a store to a slot might
  // alias: the compiler would read it again after every store.
  std::size_t capacity_ = 0;
  double clock_ = 0.0;  // the current time: the last processed event or list renewal
  ContactKernel kernel_;
};

}  // namespace carom
