// The drift verdict: whether Z settled over a run's measurement window.
#pragma once

#include <cmath>
#include <cstddef>
#include <optional>

#include "carom/core/fluxes.hpp"
#include "carom/core/measurement.hpp"
#include "carom/engine/simulation.hpp"

namespace carom {

// Whether Z settled over the measurement window: Z over equal intervals (between multiples of
// `every`, counted from t = 0) that lie in the window, the first half of them against the
// second. A run still equilibrating shows a drift of many standard errors.
struct DriftVerdict {
  double first = 0.0, second = 0.0;  // mean Z over each half's intervals
  double sigmas = 0.0;               // (second - first) / the standard error of the difference
  std::size_t intervals = 0;
  // Past this many standard errors a run says it was not equilibrated.
  static constexpr double kWarning = 3.0;
  bool drifted() const { return std::abs(sigmas) > kWarning; }
};

template <std::size_t D>
class ZDrift final : public Observer<D> {
 public:
  // Fewer intervals than this in a half give no verdict.
  static constexpr std::size_t kLeastPerHalf = 4;
  // Intervals a window is cut into when its length is known.
  static constexpr double kIntervals = 20.0;
  // Continues `earlier` (a checkpoint's) when it has the same interval length.
  explicit ZDrift(double every, const std::optional<DriftRecord>& earlier = std::nullopt)
      : Observer<D>(Trigger::every_time(every)),
        record_(earlier && earlier->every == every ? *earlier
                                                   : DriftRecord{every, {}, {}, {}, {}}) {}
  void observe(const Simulation<D>& simulation) override;
  std::optional<DriftVerdict> verdict() const;
  // The standard error of the pressure tensor's mean over the intervals (taken as independent:
  // each is 1/20 of the window), once there are as many as a verdict needs.
  std::optional<SymmetricTensor> pressure_tensor_error() const;
  // The same for Z.
  std::optional<double> compressibility_factor_error() const;
  const DriftRecord& record() const { return record_; }

 private:
  DriftRecord record_;
};

}  // namespace carom
