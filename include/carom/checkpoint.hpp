// Checkpoints: the complete state of a run, from which `carom run --resume` continues exactly
// as if never interrupted. Every particle's stored (lazy) state is kept as it is, double for
// double: predictions are functions of the stored states alone, so the resumed run finds the
// same events at the same times, bit for bit.
#pragma once

#include <istream>
#include <ostream>
#include <string>

#include "carom/engine.hpp"

namespace carom {

inline constexpr int kCheckpointFormat = 1;

struct Checkpoint {
  std::string input;  // the file the run started from
  System<2> system;   // stored states, not brought to a common time
  CollisionRule rule;
  EngineKind engine = EngineKind::fast;
  double time = 0.0;  // the last processed event
  RunCounts counts;
  double equilibrate = 0.0;
  double kinetic_energy_initial = 0.0;  // at the start of the measurement
};

// json, numbers in shortest round-trip form; written through AtomicFile by the caller.
void write_checkpoint(std::ostream& out, const Checkpoint& checkpoint);

// Throws InputError naming `name` for anything that is not a complete checkpoint of this format.
Checkpoint read_checkpoint(std::istream& in, const std::string& name);

}  // namespace carom
