// The state a run ends in as a start file that `carom run` reads back to the last bit: carom run
// --final FILE, sim.run(final=...), a sweep plan's `final`. The classic table a run prints (-o)
// is the classic assignment's, six decimals; this is the file to go on from.
#pragma once

#include <ostream>
#include <string_view>

#include "carom/core/physics.hpp"
#include "carom/core/system.hpp"

namespace carom {

enum class FinalFormat {
  classic,  // carom init's start format, every number in its shortest exact form
  gsd,      // one GSD frame (HOOMD, OVITO, freud) with carom's double-precision copies
};

// The format a file name asks for (its ending in any case, as trajectory_kind_of reads it): `.gsd`
// GSD, any other name the classic start format. Throws std::invalid_argument for the trajectory
// formats `.xyz` and `.lammpstrj`, whose frames carom does not start from.
FinalFormat final_format(std::string_view path);

// `system` brought to the absolute time t (its particles wrapped into the box, image flags kept)
// as a start in `format`, recording `rule` (the classic format's first line) and the boundary.
// `at_rest`: every velocity written as 0 (event chains, whose one moving particle's speed is the
// sampler's, not a temperature; `carom run --kT` gives such a start velocities).
template <std::size_t D>
void write_final_state(std::ostream& out, FinalFormat format, const System<D>& system, double t,
                       Rule rule, bool at_rest);

}  // namespace carom
