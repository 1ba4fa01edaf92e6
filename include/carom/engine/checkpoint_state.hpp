// What a checkpoint holds: everything a Simulation continues from exactly as if never
// interrupted (Simulation::checkpoint makes one, Simulation's constructor takes one back). The
// file format is the io layer's (checkpoint.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <pcg_random.hpp>
#include <string>
#include <variant>

#include "carom/engine/simulation.hpp"

namespace carom {

template <std::size_t D>
struct Checkpoint {
  std::string source;  // the input the run began from (provenance only)
  System<D> system;    // stored states, not brought to a common time
  Settings settings;
  double time = 0.0;     // Simulation::time()
  bool settled = false;  // every event up to `time` processed
  Counts counts;         // since the run began
  Measurement measurement;
  std::optional<double> measure_from;     // a measurement window still to open
  WindowRecords records;                  // of the run that saved it
  std::uint64_t thermostat_instants = 0;  // the thermostat's instants done
  pcg32 thermostat_rng;                   // Andersen's draws to come
  double thermostat_next = kNever;        // Andersen's resets as events: the next one's time
  std::optional<std::uint64_t> seed;      // of the velocities the run began with (its summary's)
  std::optional<ChainState> chain;        // an event-chain run's chain in flight
};

using AnyCheckpoint = std::variant<Checkpoint<2>, Checkpoint<3>>;

}  // namespace carom
