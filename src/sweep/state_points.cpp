#include "state_points.hpp"

#include <fmt/format.h>

#include <cmath>
#include <unordered_map>

namespace carom::sweep {

namespace {

bool is_error(const std::string& name) {
  return name.size() > 6 && name.compare(name.size() - 6, 6, "_error") == 0;
}

Estimate estimate(const std::vector<const TaskResult*>& done, const std::string& name) {
  double sum = 0.0;
  std::size_t count = 0;
  const TaskResult* only = nullptr;
  for (const TaskResult* result : done) {
    const double x = result->measure(name);
    if (!std::isfinite(x)) continue;
    sum += x;
    ++count;
    only = result;
  }
  if (count == 0) return {std::nan(""), std::nan("")};
  const double n = static_cast<double>(count);
  const double mean = sum / n;
  if (count == 1) return {mean, only->measure(name + "_error")};
  double sum_of_squares = 0.0;
  for (const TaskResult* result : done) {
    const double x = result->measure(name);
    if (std::isfinite(x)) sum_of_squares += (x - mean) * (x - mean);
  }
  return {mean, std::sqrt(sum_of_squares / (n - 1.0) / n)};
}

}  // namespace

StatePoints state_points(const SweepPlan& plan, const std::vector<TaskResult>& results) {
  check_task_results(plan, results);
  StatePoints s;
  std::vector<std::size_t> kept;
  for (std::size_t a = 0; a < plan.axes().size(); ++a) {
    if (plan.axes()[a] == "seed") continue;
    kept.push_back(a);
    s.axes.push_back(plan.axes()[a]);
  }
  for (const std::string& name : measure_names(plan)) {
    // A drift is a verdict on one run: counted (StatePoint::drifted), not averaged.
    if (name == kDriftMeasure) {
      s.drift_measured = true;
    } else if (!is_error(name) && name != kCorrelationMeasure) {
      s.measures.push_back(name);
    }
  }
  std::vector<std::vector<const TaskResult*>> done;
  // Each state point's index, by its values (hashed: 100,000 state points are grouped in
  // milliseconds, where a search of those seen so far took minutes).
  std::unordered_map<std::string, std::size_t> point_of;
  for (std::size_t i = 0; i < results.size(); ++i) {
    std::vector<std::string> values;
    std::string key;
    for (std::size_t a : kept) {
      const std::string& value = plan.tasks()[i].point[a].second;
      key += fmt::format("{}:{}", value.size(), value);  // sized, so no two lists join alike
      values.push_back(value);
    }
    const auto [found, added] = point_of.emplace(std::move(key), s.points.size());
    const std::size_t p = found->second;
    if (added) {
      s.points.push_back({std::move(values), 0, 0, {}});
      done.emplace_back();
    }
    ++s.points[p].tasks;
    if (results[i].status == TaskStatus::done) {
      ++s.points[p].done;
      if (drifted(results[i])) ++s.points[p].drifted;
      done[p].push_back(&results[i]);
    }
  }
  for (std::size_t p = 0; p < s.points.size(); ++p) {
    for (const std::string& name : s.measures) {
      s.points[p].estimates.push_back(estimate(done[p], name));
    }
  }
  return s;
}

}  // namespace carom::sweep
