// The Simulation: runs cut into pieces equal whole runs bit for bit, the measurement window,
// observers on their own timeline, the stop flag, run-length guards and checkpoints.
#include "carom/simulation.hpp"

#include <gtest/gtest.h>

namespace carom {
namespace {

}  // namespace
}  // namespace carom
