// Geometric checks of a configuration: do particles overlap each other or the walls?
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "carom/simulation.hpp"
#include "carom/system.hpp"

namespace carom {

// Overlaps smaller than this fraction of the contact distance are round-off, not overlaps:
// particles that touch in decimal (as the classic assignment's cases start) may overlap by an ulp
// in binary.
inline constexpr double kOverlapTolerance = 1e-9;

// The first pair (i < j, lowest i then j) whose centres are closer than their contact distance
// beyond kOverlapTolerance at the stored time `time` (see System::stored), using a cell grid: O(N).
template <std::size_t D>
std::optional<std::pair<std::size_t, std::size_t>> find_pair_overlap(const System<D>& system,
                                                                     double time);

// Whether particle p reaches through the wall `label` beyond kOverlapTolerance.
template <std::size_t D>
bool overlaps_wall(const Particle<D>& p, const Box<D>& box, int label);

// What is wrong with the configuration at the stored time `time` (every particle moved there from
// its stored state): a pair overlapping or a particle through a wall or outside the box, beyond
// kOverlapTolerance; nullopt when nothing is. O(N) with a cell grid.
template <std::size_t D>
std::optional<std::string> find_violation(const System<D>& system, double time);

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
