// Whether a checkpoint read from a file holds a state a run can have reached: private to the
// checkpoint reader (read_checkpoint), apart from the format it reads.
#pragma once

#include <optional>
#include <string>

#include "carom/io/checkpoint.hpp"

namespace carom {

// The first thing wrong with `checkpoint` (stored in format `format`), if anything: settings
// check_settings refuses, times no run reaches or out of order, counts that do not add up, a
// particle as the start reader would refuse it (at its stored time, and moved to the
// checkpoint's), overlaps, or a collision due before the checkpoint's time that was never
// processed (the fast engine is replayed from the stored states to find one).
template <std::size_t D>
std::optional<std::string> checkpoint_problem(const Checkpoint<D>& checkpoint, int format);

}  // namespace carom
