// The engine a Simulation runs: the one place that turns Settings (dynamics or event chains)
// into an engine.
#pragma once

#include <memory>
#include <optional>

#include "carom/engine/engine.hpp"
#include "carom/engine/simulation.hpp"

namespace carom {

// Dynamics: make_engine(settings.engine, ...). Event chains: an EcmcEngine with the settings'
// chain length (resolved: above 0), drawing its chains from `chain` when continuing one, else
// from settings.sampler.seed.
template <std::size_t D>
std::unique_ptr<Engine<D>> make_run_engine(const Settings& settings, System<D> system,
                                           const std::optional<ChainState>& chain);

}  // namespace carom
