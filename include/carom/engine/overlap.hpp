// Geometric checks of a configuration: do particles overlap each other or the walls?
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>

#include "carom/core/system.hpp"

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

}  // namespace carom
