// What a run counts and accumulates, event by event: over the whole run, and over the
// measurement window the observables are computed from.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "carom/core/event.hpp"
#include "carom/core/fluxes.hpp"
#include "carom/core/transport.hpp"

namespace carom {

struct Counts {
  std::uint64_t events = 0;  // processed collisions: wall_collisions + pair_collisions
  std::uint64_t wall_collisions = 0;
  std::uint64_t pair_collisions = 0;
  std::uint64_t elastic_by_tc = 0;  // inelastic collisions made elastic by the TC model
  double virial = 0.0;              // sum over pair collisions of r_ij . (momentum given to i)
  double wall_momentum = 0.0;       // total momentum given to the walls
  // The momentum and energy fluxes (fluxes.hpp): a run's are kept event by event; a window's
  // follow from them (Measurement::flux_origin).
  std::optional<Fluxes> fluxes;

  friend bool operator==(const Counts&, const Counts&) = default;

  void add(const Event& event) {
    ++events;
    if (event.is_wall()) {
      ++wall_collisions;
      wall_momentum += event.impulse;
    } else {
      ++pair_collisions;
      virial += event.impulse;
      elastic_by_tc += event.elastic_by_tc ? 1 : 0;
    }
  }
};

// Lifts of event chains as a run counts them: in the run's counts and its window's, and their
// collisional stress in the run's fluxes (the kinetic part follows the chains' turns). Held in
// locals over a batch of lifts (where a compiler keeps them in registers, not read and written
// back at every lift through counts that any store might change) and written back by commit():
// the same sums, added in the same order.
template <std::size_t D>
class LiftTally {
 public:
  LiftTally(const Counts& run, const Counts& window)
      : run_virial_(run.virial),
        window_virial_(window.virial),
        stressed_(run.fluxes.has_value()),
        stress_(stressed_ ? run.fluxes->collisional_stress : SymmetricTensor{}) {}

  void add(const Event& lift) {
    ++lifts_;
    run_virial_ += lift.impulse;
    window_virial_ += lift.impulse;
    if (stressed_) Fluxes::add_lift<D>(stress_, lift);
  }

  void commit(Counts& run, Counts& window) const {
    for (Counts* counts : {&run, &window}) {
      counts->events += lifts_;
      counts->pair_collisions += lifts_;
    }
    run.virial = run_virial_;
    window.virial = window_virial_;
    if (stressed_) run.fluxes->collisional_stress = stress_;
  }

 private:
  std::uint64_t lifts_ = 0;
  double run_virial_;
  double window_virial_;
  bool stressed_;
  SymmetricTensor stress_;
};

// One lift counted (LiftTally).
template <std::size_t D>
inline void count_lift(Counts& run, Counts& window, const Event& lift) {
  LiftTally<D> tally(run, window);
  tally.add(lift);
  tally.commit(run, window);
}

// What was counted between two running totals (of a time-series row, of a drift interval).
inline Counts difference(const Counts& later, const Counts& earlier) {
  return {later.events - earlier.events,
          later.wall_collisions - earlier.wall_collisions,
          later.pair_collisions - earlier.pair_collisions,
          later.elastic_by_tc - earlier.elastic_by_tc,
          later.virial - earlier.virial,
          later.wall_momentum - earlier.wall_momentum,
          later.fluxes && earlier.fluxes
              ? std::optional<Fluxes>(flux_difference(*later.fluxes, *earlier.fluxes))
              : std::nullopt};
}

// The measurement window: observables are measured from `start_time`, when the kinetic energy
// was `kinetic_energy_initial`, with the counts since then. Resetting it (after equilibration,
// say) changes nothing in the dynamics.
struct Measurement {
  double start_time = 0.0;
  double kinetic_energy_initial = 0.0;
  Counts counts;
  // The run's fluxes when the window opened: the window's are the run's since (Simulation keeps
  // one set event by event, and measurement() gives the window's as the difference).
  std::optional<Fluxes> flux_origin;

  friend bool operator==(const Measurement&, const Measurement&) = default;
};

// Where the drift verdict of a run's summary stands (ZDrift): the run's counts at the ends of
// the blocks the measurement window is cut into so far, blocks of `block_length` between
// consecutive multiples of it (counted from t = 0). The blocks double in length as the window
// grows, whatever its end, so that a run continued to a later end (in pieces, or resumed from a
// checkpoint) holds the blocks of a run in one piece. A checkpoint keeps it.
struct DriftRecord {
  double block_length = 0.0;
  std::vector<double> boundaries;  // multiples of block_length, each the next but for gaps
  std::vector<Counts> totals;      // the run's counts at each boundary
  // The kinetic temperature at each: a block's Z is measured at its end's.
  std::vector<double> temperatures;

  friend bool operator==(const DriftRecord&, const DriftRecord&) = default;
};

// What the measurements over a run's window have gathered so far, beyond its counts: every
// checkpoint keeps them (one saved at the run's end too), so that a run continued from one
// reports what a run in one piece would, even a run resumed where its end is already reached.
struct WindowRecords {
  // The measurement they are of: the window's start and the run's end time (absent from older
  // checkpoints, which kept records only of a run stopped on its way to its end).
  std::optional<double> window_start, end_time;
  std::optional<DriftRecord> drift;          // the drift verdict's (ZDrift)
  std::optional<TransportRecord> transport;  // the transport coefficients' (TransportMeter)
  // Whether a run measuring from `start` measures the same window, so that it may go on with
  // these records: the drift's blocks to any end, the transport's where TransportMeter::continued
  // says (not a window opened afresh: mixing them would report on two windows).
  bool same_window(double start) const { return !window_start || *window_start == start; }
  friend bool operator==(const WindowRecords&, const WindowRecords&) = default;
};

}  // namespace carom
