// A source of the engine layer that includes its own layer's headers (public and private) and
// core's: the build takes it. The control of engine_includes_run.cpp, compiled the same way.
#include "carom/core/system.hpp"
#include "carom/engine/engine.hpp"
#include "engine/cell_grid.hpp"
