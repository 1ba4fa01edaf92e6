// A run's time series, like LAMMPS' thermo output: one row per interval with the temperature,
// pressure, compressibility factor and collision rate over it, and running averages with a
// block-average error bar.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "carom/simulation.hpp"

namespace carom {

// The mean of `values` and the squared standard error of that mean (their variance over n - 1,
// over n), taken as independent: for block or interval means that are.
std::pair<double, double> mean_and_variance_of_mean(std::span<const double> values);

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
  double mean() const;   // NaN before any value
  double error() const;  // NaN with fewer than two values
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

// Writes a CSV row every `every` (at t = 0, every, 2 every, ...; flushed, so an interrupted run
// keeps its rows):
//   time,events,pair_collisions,virial,wall_momentum,temperature,pressure,Z,collision_rate,
//   pressure_mean,pressure_error,Z_mean,Z_error
// events to wall_momentum are the run's running totals (Counts); temperature is kT at the row's
// time; pressure, Z = P V / (N kT) and the collision rate (per particle) are measured over the
// interval since the previous row; the means and errors (BlockAverage) are over the rows whose
// interval lies in the measurement window (none while equilibrating). Empty fields: not measured
// (the first row, or no row yet in the window). Throws std::runtime_error when the stream fails.
template <std::size_t D>
class TimeSeriesWriter final : public Observer<D> {
 public:
  static constexpr const char* kHeader =
      "time,events,pair_collisions,virial,wall_momentum,temperature,pressure,Z,collision_rate,"
      "pressure_mean,pressure_error,Z_mean,Z_error\n";
  TimeSeriesWriter(std::ostream& out, double every)
      : Observer<D>(Trigger::every_time(every)), out_(out) {}
  // The header of a log: kHeader's columns, then the pressure tensor over the row's interval
  // (pxx, pyy, pxy; in 3D pxx, pyy, pzz, pxy, pxz, pyz) and its Einstein-Helfand moment, the
  // integral of V P_ab since the run began keeping its fluxes (Gxx, ...: running totals, like
  // virial).
  static std::string header();
  void observe(const Simulation<D>& simulation) override;
  // The running means and errors of Z (what a progress line shows).
  const BlockAverage& compressibility() const { return z_; }
  // The length of the leading part of a log holding the header and the rows before `t` (or at
  // it, when `inclusive`): what a resumed run keeps before appending. The writer takes up the
  // running totals and averages of the kept rows, so that the rows it appends are those of a run
  // never interrupted.
  std::uint64_t resume(std::istream& in, double t, bool inclusive, const Simulation<D>& simulation);

 private:
  // One row's own values, as written.
  struct Row {
    double time = 0.0;
    Counts totals;
    double pressure = 0.0, z = 0.0;
    bool measured = false;
  };
  // Counts a row written (or kept from before a resume) into the averages when its interval
  // lies in the measurement window.
  void take(const Row& row, std::optional<double> window_start);

  std::ostream& out_;
  bool started_ = false;
  Row last_;                            // the previous row
  std::optional<double> window_start_;  // the measurement window the averages are over
  BlockAverage pressure_, z_;
};

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
  const DriftRecord& record() const { return record_; }

 private:
  DriftRecord record_;
};

// A time-series log (carom run --log FILE.csv) as read back: its columns, and rows of numbers
// (NaN where a field is empty: not measured yet).
struct LogTable {
  std::string file;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};
// Throws InputError naming the file and line for anything that is not such a table.
LogTable read_log_table(const std::string& path);

}  // namespace carom
