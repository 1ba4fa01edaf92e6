// Starting a run from a frame of a GSD file (HOOMD-blue's format, schema "hoomd"), as HOOMD,
// OVITO's exporter or carom's own --dump FILE.gsd writes it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "carom/io/classic_input.hpp"

namespace carom {

// Frame `frame` (nullopt: the last) of the GSD file `path` as a start in a periodic box (or with
// walls, when carom wrote the frame for one), recorded for the elastic rule: the
// dimension from configuration/dimensions (default 3), the box from configuration/box (no tilt),
// positions (centred on the origin, as HOOMD's) moved into [0, L), velocities, diameters, masses
// and image flags; a chunk missing from the frame is taken from frame 0, else HOOMD's default
// (velocity 0, diameter 1, mass 1, image 0). Every particle starts at t = 0. Validated as a classic
// file is (check_start): anything that is not a readable GSD file of the HOOMD schema, a frame
// that does not exist, or a start no run can have throws InputError naming `path`.
AnyClassicInput read_gsd_start(const std::string& path, std::optional<std::uint64_t> frame);

}  // namespace carom
