// The production engine: a cell grid limits predictions to nearby particles, each particle holds
// exactly one pending event (its earliest collision or wall hit, or its next cell crossing if that
// comes first) in an event calendar, and an event against a partner that has collided since is
// detected by the partner's version and predicted again lazily. An event costs O(1) on average:
// the particles in 3^D cells (after a crossing, the 3^(D-1) cells it brings within reach) and a
// bucket of the calendar.
//
// Why no collision is missed: two particles about to touch are in the same or adjacent cells, and
// the later of them to change cell or velocity predicted their contact then (a crossing needs only
// the new layer of cells: the rest were around the old cell, their pairs predicted already). In a
// periodic box with at least five cells along each axis, adjacent particles are at most two cells,
// 2/5 of the box, apart, so the nearest image at prediction time is the one they touch through.
// (With four, two particles on the far edges of adjacent cells are exactly half a box apart and the
// nearest image is ambiguous: the fuzzer found that.)
//
// In a sheared box (Lees-Edwards) the images above and below slide along x, so a particle in an
// edge row of cells may touch the image of one anywhere in the far edge row: it searches that
// whole row, and the nearest image across the boundary changes as the images slide, so the edge
// rows are predicted again every image horizon. A particle's stored state keeps the image it was
// stored as until it collides; the grid holds where it is in the box (layer_).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "carom/engine/engine.hpp"
#include "cell_grid.hpp"
#include "event_calendar.hpp"
#include "prediction.hpp"

namespace carom {

template <std::size_t D>
class FastEngine final : public Engine<D> {
 public:
  FastEngine(System<D> system, const CollisionRule& rule, const Growth& growth = {});
  std::optional<Event> step(double end_time) override;

 private:
  void rebased(double shift) override;
  // The image horizon follows the fastest speed the energy allows, which a thermostat changes.
  void velocities_changed() override {
    if (horizon_ != kNever) horizon_ = this->image_horizon();
  }
  void velocity_reset(std::uint32_t i) override;
  // Finds the earliest event of particle i from the current time and queues it: against every
  // particle in the cells around it, or after a crossing only against those in the layer of cells
  // the crossing brought within reach, the earlier prediction standing for the rest.
  void predict(std::uint32_t i) { predict(i, D, false); }
  void predict(std::uint32_t i, std::size_t layer_axis, bool layer_upward);
  // The same with one of the contact kernels (contact_batch.hpp), or for growing particles: the
  // choice is made once per prediction, and each compiles to one flat loop.
  void predict_narrow(std::uint32_t i, std::size_t layer_axis, bool layer_upward);
  void predict_wide(std::uint32_t i, std::size_t layer_axis, bool layer_upward);
  void predict_growing(std::uint32_t i, std::size_t layer_axis, bool layer_upward);
  void predict_sheared(std::uint32_t i, std::size_t layer_axis, bool layer_upward);
  void predict_sheared_wide(std::uint32_t i, std::size_t layer_axis, bool layer_upward);
  template <class Contacts>
  void predict_with(std::uint32_t i, std::size_t layer_axis, bool layer_upward,
                    const Contacts& contacts);
  // Starts fetching what processing an event of particle i will read first.
  void fetch_ahead(std::uint32_t i) const;
  // For the queue entry `slot`, `distance` entries from the top: at 2, its pending collision and
  // particle; at 1 (what those say), the cells its prediction reads and its partner.
  void prefetch_entry(std::uint32_t slot, int distance) const;
  EntryKind entry_kind(std::uint32_t slot, const EventKey& key) const {
    return slot == horizon_slot_ ? EntryKind::renewal
                                 : keyed_entry<D>(slot, key).kind;
  }
  // Predicts every particle afresh (at the start and after rebases and interventions).
  void predict_all();
  // At the renewal horizon: every particle predicted afresh, or in a sheared box of five cells
  // or more along every axis those of the edge rows only.
  void renew();
  // Every particle in the cell it is in at clock_ (in a sheared box, with the layers between its
  // stored state and the box made afresh).
  void locate_all();
  // Particle i's position and velocity at time t as the grid sees it: inside the box along y (in a
  // sheared box its stored state may be an image, layer_[i] boxes up).
  std::pair<Vec<D>, Vec<D>> grid_motion(std::uint32_t i, double t) const;
  // Particle i's next cell crossing at clock_ in a sheared box (from its grid_motion).
  typename CellGrid<D>::Crossing sheared_crossing(std::uint32_t i) const;
  // Particle i leaves its edge row of cells across the sheared boundary at clock_ (up or down):
  // into the cell of the far edge row its image enters, predicted afresh.
  void cross_shear(std::uint32_t i, bool upward);
  // Queues the next time every particle is predicted again, or none.
  void schedule_horizon();
  // Where the particles may have sped up (growth, shear, a thermostat's reset): brings that
  // renewal forward as much.
  void shorten_horizon();

  bool wide_;     // the CPU has AVX2: predictions use the four-wide contact kernel
  bool sheared_;  // the box is sheared (Box::sheared)
  // In a sheared box: how many boxes up along y particle i's stored state lies from where the
  // grid has it (its stored state is that image of it until it collides). Empty otherwise.
  std::vector<std::int32_t> layer_;
  bool edge_rows_renewed_ = false;  // see renew()
  CellGrid<D> grid_;
  EventCalendar queue_;
  // Each particle's earliest collision and the time of it (the calendar's key is the crossing's
  // when that comes first).
  struct TimedPending {
    Pending pending;
    double time = kNever;
  };
  std::vector<TimedPending> pending_;
  double clock_ = 0.0;  // the current time: the last processed event or cell crossing
  // In a periodic box too small for five cells along some axis, a neighbour may be reached
  // through more than one image, and predictions are renewed at least this often (see
  // Engine::image_horizon); otherwise infinite.
  double horizon_ = kNever;
  std::uint32_t horizon_slot_ = 0;  // the queue entry (after the particles') of the renewal
  double renewal_ = kNever;         // when it is due
};

}  // namespace carom
