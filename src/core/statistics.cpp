#include "carom/core/statistics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace carom {

std::pair<double, double> mean_and_variance_of_mean(std::span<const double> values) {
  const auto n = static_cast<double>(values.size());
  double mean = 0.0, squares = 0.0;
  for (const double x : values) mean += x / n;
  for (const double x : values) squares += (x - mean) * (x - mean);
  return {mean, squares / (n - 1.0) / n};
}

double lag_one_autocorrelation(std::span<const double> values,
                               std::span<const std::uint8_t> follows) {
  if (values.size() < 3) return std::numeric_limits<double>::quiet_NaN();
  if (!follows.empty() && follows.size() != values.size()) {
    throw std::invalid_argument("lag_one_autocorrelation: one flag a value");
  }
  const auto n = static_cast<double>(values.size());
  double mean = 0.0;
  for (const double x : values) mean += x / n;
  double variance = 0.0, covariance = 0.0;
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double d = values[i] - mean;
    variance += d * d;
    if (i > 0 && (follows.empty() || follows[i] != 0)) {
      covariance += d * (values[i - 1] - mean);
      ++pairs;
    }
  }
  if (pairs == 0) return std::numeric_limits<double>::quiet_NaN();
  // As many pairs' worth as a series without gaps has (a factor of exactly 1 where there are
  // none).
  covariance *= (n - 1.0) / static_cast<double>(pairs);
  // Values that differ only by round-off (a gas that never collides: Z = 1 in every block, to the
  // last bits) have no correlation to speak of.
  const double resolution = 64.0 * std::numeric_limits<double>::epsilon() * std::abs(mean);
  if (!(variance > n * resolution * resolution)) return std::numeric_limits<double>::quiet_NaN();
  return covariance / variance;
}

void BlockAverage::add(double value) {
  for (std::size_t level = 0;; ++level) {
    if (level == levels_.size()) levels_.emplace_back();
    Level& here = levels_[level];
    here.sum += value;
    here.sum_of_squares += value * value;
    ++here.count;
    if (!here.has_waiting) {
      here.waiting = value;
      here.has_waiting = true;
      return;
    }
    value = 0.5 * (here.waiting + value);  // a block of the next level
    here.has_waiting = false;
  }
}

double BlockAverage::mean() const {
  if (count() == 0) return std::numeric_limits<double>::quiet_NaN();
  return levels_.front().sum / static_cast<double>(levels_.front().count);
}

double BlockAverage::error(std::uint64_t least_block) const {
  const auto standard_error = [](const Level& level) {
    const auto n = static_cast<double>(level.count);
    const double variance = (level.sum_of_squares - level.sum * level.sum / n) / (n - 1.0);
    return std::sqrt(std::max(variance, 0.0) / n);
  };
  double largest = std::numeric_limits<double>::quiet_NaN();
  if (count() < 2) return largest;
  if (least_block <= 1) largest = standard_error(levels_.front());
  std::uint64_t block = 1;
  for (const Level& level : levels_) {
    if (block >= least_block && level.count >= kLeastBlocks) {
      largest =
          std::isnan(largest) ? standard_error(level) : std::max(largest, standard_error(level));
    }
    block *= 2;
  }
  return largest;
}

}  // namespace carom
