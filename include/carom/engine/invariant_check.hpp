// Checking a run as it goes (carom run --check): an observer that stops the run when an invariant
// breaks.
#pragma once

#include <cstdint>
#include <limits>
#include <stdexcept>

#include "carom/engine/simulation.hpp"

namespace carom {

// A broken invariant found by InvariantCheck: the engine has a bug, or the input is not what it
// seemed.
class InvariantError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Checks a run as it goes: after every event that event times never decrease, and every
// `every` events (O(N) each, so O(1) per event when `every` is about N) that no pair overlaps and
// no particle is outside the box. Throws InvariantError naming the event.
template <std::size_t D>
class InvariantCheck final : public Observer<D> {
 public:
  explicit InvariantCheck(std::uint64_t every)
      : Observer<D>(Trigger::each_event()), every_(every > 0 ? every : 1) {}
  void observe(const Simulation<D>& simulation) override;

 private:
  std::uint64_t every_;
  std::uint64_t events_ = 0;
  double last_ = -std::numeric_limits<double>::infinity();
};

}  // namespace carom
