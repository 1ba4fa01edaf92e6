// The state points of a sweep: its tasks grouped by every axis but `seed`, each measure's mean
// over the done tasks and its standard error. summary.csv and the report show these numbers.
#pragma once

#include <string>
#include <vector>

#include "carom/sweep/sweep.hpp"

namespace carom::sweep {

struct Estimate {
  double mean, error;  // NaN: nothing to average, or no error to give
};

struct StatePoint {
  std::vector<std::string> values;  // of the axes, as the plan writes them
  std::size_t tasks = 0, done = 0;
  std::vector<Estimate> estimates;  // one a measure
  std::size_t drifted = 0;          // done tasks whose Z drifted (carom::drifted)
};

struct StatePoints {
  std::vector<std::string> axes;      // every swept key but seed
  std::vector<std::string> measures;  // measure_names(kind) but the *_error ones and Z_drift
  bool drift_measured = false;        // the tasks have a Z_drift (runs, not compressions)
  std::vector<StatePoint> points;     // in the order of their first task
};

// The error of a state point with two or more done tasks is the standard error of their mean
// (the sample standard deviation over sqrt(n)); with one, that task's own `<measure>_error`.
StatePoints state_points(const SweepPlan& plan, const std::vector<TaskResult>& results);

}  // namespace carom::sweep
