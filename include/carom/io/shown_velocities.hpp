// Which velocities a run's outputs show.
#pragma once

#include <cstddef>

#include "carom/engine/simulation.hpp"

namespace carom {

// Event chains sample positions: their one moving particle's speed is a unit of the sampler's
// clock, not a velocity, so every output of theirs (the table, json, frames, the end state,
// Python's velocities) shows the particles at rest. (The trace, which shows the stored states the
// engine advances, keeps the moving particle's speed.)
template <std::size_t D>
bool shows_at_rest(const Simulation<D>& simulation) {
  return simulation.settings().sampler.kind == SamplerKind::ecmc;
}

}  // namespace carom
