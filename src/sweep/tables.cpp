// A sweep's tables: results.csv (a row a task) and summary.csv (a row a state point, the seeds
// averaged). Numbers in their shortest exact form, rows in the plan's order: the same bytes
// whatever ran the tasks, in whatever order.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "carom/io/atomic_file.hpp"
#include "carom/run/z_drift.hpp"
#include "carom/sweep/sweep.hpp"
#include "state_points.hpp"

namespace carom {

namespace {

std::string field(double value) {
  return std::isfinite(value) ? fmt::format("{}", value) : "";
}

// A csv field: quoted when it holds a comma, a quote or a line break, each line break (\n or \r,
// which readers also split rows at) written as a space, so that a row is always one line.
std::string quoted(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) {
    q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' || c == '\r' ? ' ' : c);
  }
  return q + "\"";
}

void write_results(std::ostream& out, const SweepPlan& plan,
                   const std::vector<TaskResult>& results) {
  const std::vector<std::string>& measures = measure_names(plan);
  for (const std::string& axis : plan.axes()) out << axis << ',';
  out << "status";
  for (const std::string& name : measures) out << ',' << name;
  out << ",error\n";
  for (std::size_t i = 0; i < results.size(); ++i) {
    for (const auto& [axis, value] : plan.tasks()[i].point) out << quoted(value) << ',';
    out << status_name(results[i].status);
    for (const std::string& name : measures) out << ',' << field(results[i].measure(name));
    out << ',' << quoted(results[i].error) << '\n';
  }
}

void write_summary(std::ostream& out, const SweepPlan& plan,
                   const std::vector<TaskResult>& results) {
  const sweep::StatePoints s = sweep::state_points(plan, results);
  for (const std::string& axis : s.axes) out << axis << ',';
  out << "tasks,done";
  for (const std::string& name : s.measures) out << ',' << name << "_mean," << name << "_error";
  if (s.drift_measured) out << ",drifted";
  out << '\n';
  for (const sweep::StatePoint& point : s.points) {
    for (const std::string& value : point.values) out << quoted(value) << ',';
    out << point.tasks << ',' << point.done;
    for (const sweep::Estimate& e : point.estimates) {
      out << ',' << field(e.mean) << ',' << field(e.error);
    }
    if (s.drift_measured) out << ',' << point.drifted;
    out << '\n';
  }
}

}  // namespace

bool drifted(const TaskResult& result) {
  return DriftVerdict::drifted_by(result.measure(kDriftMeasure));
}

bool blocks_correlated(const TaskResult& result) {
  return DriftVerdict::correlated_by(result.measure(kCorrelationMeasure));
}

std::optional<std::string> unsettled_warning(double z_drift, double z_correlation) {
  if (DriftVerdict::drifted_by(z_drift)) {
    return fmt::format("Z drifted by {:.1f} standard errors over its measurement window: {}",
                       z_drift, DriftVerdict::kDriftAdvice);
  }
  if (DriftVerdict::correlated_by(z_correlation)) {
    return fmt::format("Z's blocks are correlated ({} = {:.2f}): {}", kCorrelationMeasure,
                       z_correlation, DriftVerdict::kCorrelationAdvice);
  }
  return std::nullopt;
}

std::optional<std::string> unsettled_warning(const TaskResult& result) {
  return unsettled_warning(result.measure(kDriftMeasure), result.measure(kCorrelationMeasure));
}

double TaskResult::measure(std::string_view name) const {
  for (const auto& [n, value] : measures) {
    if (n == name) return value;
  }
  return std::nan("");
}

std::string_view status_name(TaskStatus status) {
  switch (status) {
    case TaskStatus::done:
      return "done";
    case TaskStatus::failed:
      return "failed";
    case TaskStatus::stopped:
      return "stopped";
    case TaskStatus::pending:
      return "pending";
  }
  return "?";
}

void check_task_results(const SweepPlan& plan, const std::vector<TaskResult>& results) {
  if (results.size() != plan.tasks().size()) {
    throw std::invalid_argument(fmt::format("{} has {} tasks, but {} results were given",
                                            plan.name(), plan.tasks().size(), results.size()));
  }
}

void write_sweep_tables(const SweepPlan& plan, const std::string& out_dir,
                        const std::vector<TaskResult>& results) {
  check_task_results(plan, results);
  const std::filesystem::path folder(out_dir);
  {
    AtomicFile file((folder / "results.csv").string());
    write_results(file.stream(), plan, results);
    file.commit();
  }
  AtomicFile file((folder / "summary.csv").string());
  write_summary(file.stream(), plan, results);
  file.commit();
}

}  // namespace carom
