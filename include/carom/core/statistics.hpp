// Means and their standard errors, of independent values and of correlated series.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace carom {

// The mean of `values` and the squared standard error of that mean (their variance over n - 1,
// over n), taken as independent: for block or interval means that are.
std::pair<double, double> mean_and_variance_of_mean(std::span<const double> values);

// The lag-one autocorrelation of `values`: the covariance of consecutive values over their
// variance (both about the mean of all). Near -1/n for independent values, within about
// 1/sqrt(n); values correlated over longer than one step give more. NaN for fewer than three
// values or none that differ by more than round-off. Where `follows` is given (one flag a
// value), only the pairs whose second value follows the first (follows[i] != 0: no gap between
// values i - 1 and i) are counted, scaled up to the n - 1 of a series without gaps; NaN where
// there are none.
double lag_one_autocorrelation(std::span<const double> values,
                               std::span<const std::uint8_t> follows = {});

// The mean of a series of correlated values and its standard error by block averaging (Flyvbjerg
// and Petersen 1989): values are averaged in pairs, pairs of pairs, ..., and the standard error
// of the mean is estimated at each level; correlated values make it grow with the block size
// until blocks are independent. error() reports the largest estimate over the levels that still
// have at least kLeastBlocks blocks. O(log n) per value, exact in any order of adding.
class BlockAverage {
 public:
  static constexpr std::uint64_t kLeastBlocks = 16;
  void add(double value);
  std::uint64_t count() const { return levels_.empty() ? 0 : levels_.front().count; }
  double mean() const;  // NaN before any value
  // The largest standard error over the levels of blocks of at least `least_block` values that
  // hold kLeastBlocks blocks or more, and the values themselves' when `least_block` is 1 (the
  // levels' blocks are 1, 2, 4, ... values). NaN with fewer than two values, or when no level
  // qualifies.
  double error(std::uint64_t least_block = 1) const;
  void clear() { levels_.clear(); }

 private:
  struct Level {
    double sum = 0.0, sum_of_squares = 0.0;
    std::uint64_t count = 0;
    double waiting = 0.0;  // the first of a pair still to be averaged into the next level
    bool has_waiting = false;
  };
  std::vector<Level> levels_;
};

}  // namespace carom
