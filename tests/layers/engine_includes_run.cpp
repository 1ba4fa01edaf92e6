// A source of the engine layer that reaches up to the run layer. The build must refuse it: the
// engine layer compiles against the include roots of core and engine only (CMakeLists.txt,
// carom_layer), so the run layer's header is not there to be found.
#include "carom/engine/engine.hpp"
#include "carom/run/run.hpp"
