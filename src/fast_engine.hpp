// The production engine: a cell grid limits predictions to nearby particles, each particle holds
// exactly one pending event (its earliest collision, wall hit or cell crossing) in an event
// calendar, and an event against a partner that has collided since is detected by the partner's
// version and predicted again lazily. An event costs O(1) on average: the particles in 3^D cells
// and a bucket of the calendar.
//
// Why no collision is missed: two particles about to touch are in the same or adjacent cells, and
// the later of them to change cell or velocity predicted their contact then. In a periodic box
// with at least five cells along each axis, adjacent particles are at most two cells, 2/5 of the
// box, apart, so the nearest image at prediction time is the one they touch through. (With four,
// two particles on the far edges of adjacent cells are exactly half a box apart and the nearest
// image is ambiguous: the fuzzer found that.)
#pragma once

#include <cstdint>
#include <vector>

#include "carom/engine.hpp"
#include "cell_grid.hpp"
#include "event_calendar.hpp"

namespace carom {

template <std::size_t D>
class FastEngine final : public Engine<D> {
 public:
  FastEngine(System<D> system, const CollisionRule& rule, const Growth& growth = {});
  std::optional<Event> step(double end_time) override;

 private:
  void rebased(double shift) override;
  enum class Kind : std::uint8_t { none, wall, pair, crossing, horizon };
  // What a particle's entry in the queue means; the time and order are in the queue itself.
  struct Pending {
    Kind kind = Kind::none;
    std::int32_t partner = 0;           // wall label or particle index
    std::uint32_t cell = 0;             // for a crossing: the cell entered
    std::uint64_t partner_version = 0;  // for a pair: the partner's version when predicted
  };

  // Finds the earliest event of particle i from the current time and queues it.
  void predict(std::uint32_t i);
  // The same for growing particles or not, chosen once per prediction rather than per partner.
  template <bool kGrowing>
  void predict_as(std::uint32_t i);
  // Starts fetching what processing an event of particle i will read first.
  void fetch_ahead(std::uint32_t i) const;
  // Predicts every particle afresh (at the start and at every renewal horizon).
  void predict_all();
  // Queues the next time every particle is predicted again, or none.
  void schedule_horizon();
  // With growth, after an event: brings that renewal forward if the particles sped up.
  void shorten_horizon();

  CellGrid<D> grid_;
  EventCalendar queue_;
  std::vector<Pending> pending_;
  double clock_ = 0.0;  // the current time: the last processed event or cell crossing
  // In a periodic box too small for five cells along some axis, a neighbour may be reached
  // through more than one image, and predictions are renewed at least this often (see
  // Engine::image_horizon); otherwise infinite.
  double horizon_ = kNever;
  std::uint32_t horizon_slot_ = 0;  // the queue entry (after the particles') of the renewal
  double renewal_ = kNever;         // when it is due
};

}  // namespace carom
