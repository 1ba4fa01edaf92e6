// Random deviates from carom's one generator, pcg32, the same on every platform and standard
// library: what initial velocities, random placements and Andersen's thermostat draw.
#pragma once

#include <pcg_random.hpp>

namespace carom {

// Uniform in [0, 1) with 53 random bits; pcg32 gives 32 a call. (std:: distributions differ
// between standard libraries; these do not.)
double uniform_deviate(pcg32& rng);
// A standard normal deviate (Box-Muller; one of the pair, so each deviate costs two draws).
double normal_deviate(pcg32& rng);

}  // namespace carom
