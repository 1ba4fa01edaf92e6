#include "carom/core/random.hpp"

#include <cmath>
#include <cstdint>
#include <numbers>

namespace carom {

double uniform_deviate(pcg32& rng) {
  const std::uint64_t hi = rng() >> 5, lo = rng() >> 6;
  return (static_cast<double>(hi) * 67108864.0 + static_cast<double>(lo)) / 9007199254740992.0;
}

double normal_deviate(pcg32& rng) {
  const double u = 1.0 - uniform_deviate(rng);  // in (0, 1]: the logarithm is finite
  return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * std::numbers::pi * uniform_deviate(rng));
}

}  // namespace carom
