// The production engine: a cell grid limits predictions to nearby particles, each particle holds
// exactly one pending event (its earliest collision, wall hit or cell crossing) in an indexed
// heap, and an event against a partner that has collided since is detected by the partner's
// version and predicted again lazily. An event costs O(log N) plus the particles in 3^D cells.
#pragma once

#include <cstdint>
#include <vector>

#include "carom/engine.hpp"
#include "cell_grid.hpp"
#include "event_queue.hpp"

namespace carom {

template <std::size_t D>
class FastEngine final : public Engine<D> {
 public:
  FastEngine(System<D> system, Rule rule);
  std::optional<Event> step(double end_time) override;

 private:
  enum class Kind : std::uint8_t { none, wall, pair, crossing };
  // What a particle's entry in the queue means; the time and order are in the queue itself.
  struct Pending {
    Kind kind = Kind::none;
    std::int32_t partner = 0;           // wall label or particle index
    std::uint32_t cell = 0;             // for a crossing: the cell entered
    std::uint64_t partner_version = 0;  // for a pair: the partner's version when predicted
  };

  // Finds the earliest event of particle i from the current time and queues it.
  void predict(std::uint32_t i);

  CellGrid<D> grid_;
  EventQueue queue_;
  std::vector<Pending> pending_;
  double clock_ = 0.0;  // the current time: the last processed event or cell crossing
};

}  // namespace carom
