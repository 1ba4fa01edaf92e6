// The drift verdict: whether Z settled over a run's measurement window.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>

#include "carom/core/fluxes.hpp"
#include "carom/core/measurement.hpp"
#include "carom/engine/simulation.hpp"

namespace carom {

// Whether Z settled over the measurement window: Z over equal blocks of the window, the first
// half of them against the second. A run still equilibrating shows a drift of many standard
// errors.
struct DriftVerdict {
  double first = 0.0, second = 0.0;  // mean Z over each half's blocks
  double sigmas = 0.0;               // (second - first) / the standard error of the difference
  std::size_t intervals = 0;         // blocks
  // The lag-one autocorrelation of the blocks' Z: near 0 when they are independent, as the
  // standard errors over them assume (NaN, null in the summary, when their Z differ by no more
  // than round-off).
  double block_correlation = std::numeric_limits<double>::quiet_NaN();
  // Past this many standard errors a run says it was not equilibrated.
  static constexpr double kWarning = 3.0;
  bool drifted() const { return drifted_by(sigmas); }
  static bool drifted_by(double sigmas) { return std::abs(sigmas) > kWarning; }  // NaN: not
  // Past this many times 1 / sqrt(blocks) (the spread of independent blocks' autocorrelation),
  // Z remembers itself from one block to the next: its fluctuations outlast a block, and the
  // standard errors over the blocks understate the uncertainty.
  static constexpr double kCorrelationWarning = 2.0;
  // block_correlation in units of that spread: a sweep's Z_correlation.
  double correlation_spreads() const {
    return correlation_spreads_of(block_correlation, static_cast<double>(intervals));
  }
  static double correlation_spreads_of(double correlation, double blocks) {
    return correlation * std::sqrt(blocks);
  }
  bool blocks_correlated() const { return correlated_by(correlation_spreads()); }
  static bool correlated_by(double spreads) { return spreads > kCorrelationWarning; }  // NaN: not
  // What each warning advises, in the words of every front end and of the sweep's.
  static constexpr const char* kDriftAdvice =
      "the system was still changing while measured (equilibrate longer)";
  static constexpr const char* kCorrelationAdvice =
      "Z fluctuates over longer than a block, so its standard error understates the uncertainty "
      "(measure over a longer window, or compare independent runs)";
  // What every front end says of a verdict, in these words: that Z drifted (where drifted()),
  // and, where it did not, that its blocks are correlated (where blocks_correlated()); nothing
  // where Z settled over independent blocks.
  std::optional<std::string> drift_warning() const;
  std::optional<std::string> correlation_warning() const;
};

// What the blocks of a window give: the drift verdict, and the standard errors of Z's mean and
// the pressure tensor's over the blocks (taken as independent), each once there are as many
// blocks as a verdict needs.
struct BlockErrors {
  std::optional<DriftVerdict> verdict;
  std::optional<double> compressibility_factor;
  std::optional<SymmetricTensor> pressure_tensor;
  double block_length = 0.0;
};

// The verdict and errors from a record's blocks, measured in `simulation` (which gives N and the
// volume, as for the window's own Z).
template <std::size_t D>
BlockErrors block_errors(const DriftRecord& record, const Simulation<D>& simulation);

// Cuts the measurement window into blocks between consecutive multiples of a length, 20 to 40 of
// them: the length starts short (2^-20 time units, or 2^-40 of the window's start if longer)
// and doubles whenever there are 40, two blocks becoming one. The blocks so depend on the
// window's start and on how far it has come, never on where the run will end: a run in pieces,
// or resumed to a later end, has the blocks of one run to its last end, and reports the same
// verdict and errors. (Data between the window's start and the first multiple of the length, and
// after the last, is in no block: less than a block at either end.)
template <std::size_t D>
class ZDrift final : public Observer<D> {
 public:
  // Fewer blocks than this in a half give no verdict.
  static constexpr std::size_t kLeastPerHalf = 4;
  // Blocks are merged in pairs when there are this many.
  static constexpr std::size_t kMostBlocks = 40;
  // Continues `earlier` (a checkpoint's, of the window that starts at window_start).
  explicit ZDrift(double window_start, const std::optional<DriftRecord>& earlier = std::nullopt);
  void observe(const Simulation<D>& simulation) override;
  const DriftRecord& record() const { return record_; }

 private:
  // Looks at the run every record.block_length, adding to `record`.
  explicit ZDrift(DriftRecord record);
  // Merges the blocks in pairs: the boundaries that are multiples of twice the length are kept.
  void coarsen();
  DriftRecord record_;
};

}  // namespace carom
