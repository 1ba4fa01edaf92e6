// A sweep's tables: results.csv (a row a task) and summary.csv (a row a state point, the seeds
// averaged). Numbers in their shortest exact form, rows in the plan's order: the same bytes
// whatever ran the tasks, in whatever order.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "carom/atomic_file.hpp"
#include "carom/sweep.hpp"

namespace carom {

namespace {

std::string field(double value) {
  return std::isfinite(value) ? fmt::format("{}", value) : "";
}

std::string quoted(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}

bool is_error(const std::string& name) {
  return name.size() > 6 && name.compare(name.size() - 6, 6, "_error") == 0;
}

double measure(const TaskResult& result, const std::string& name) {
  for (const auto& [n, value] : result.measures) {
    if (n == name) return value;
  }
  return std::nan("");
}

void write_results(std::ostream& out, const SweepPlan& plan,
                   const std::vector<TaskResult>& results) {
  const std::vector<std::string>& measures = measure_names(plan.kind());
  for (const std::string& axis : plan.axes()) out << axis << ',';
  out << "status";
  for (const std::string& name : measures) out << ',' << name;
  out << ",error\n";
  for (std::size_t i = 0; i < results.size(); ++i) {
    for (const auto& [axis, value] : plan.tasks()[i].point) out << quoted(value) << ',';
    out << status_name(results[i].status);
    for (const std::string& name : measures) out << ',' << field(measure(results[i], name));
    out << ',' << quoted(results[i].error) << '\n';
  }
}

// The state points: every axis but seed, in the order their first task comes.
void write_summary(std::ostream& out, const SweepPlan& plan,
                   const std::vector<TaskResult>& results) {
  std::vector<std::size_t> kept;
  for (std::size_t a = 0; a < plan.axes().size(); ++a) {
    if (plan.axes()[a] != "seed") kept.push_back(a);
  }
  const auto point_of = [&](std::size_t task) {
    std::vector<std::string> point;
    for (std::size_t a : kept) point.push_back(plan.tasks()[task].point[a].second);
    return point;
  };
  std::vector<std::vector<std::string>> points;
  std::vector<std::vector<std::size_t>> members;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const std::vector<std::string> point = point_of(i);
    std::size_t p = 0;
    while (p < points.size() && points[p] != point) ++p;
    if (p == points.size()) {
      points.push_back(point);
      members.emplace_back();
    }
    members[p].push_back(i);
  }
  std::vector<std::string> measures;
  for (const std::string& name : measure_names(plan.kind())) {
    if (!is_error(name)) measures.push_back(name);
  }
  for (std::size_t a : kept) out << plan.axes()[a] << ',';
  out << "tasks,done";
  for (const std::string& name : measures) out << ',' << name << "_mean," << name << "_error";
  out << '\n';
  for (std::size_t p = 0; p < points.size(); ++p) {
    for (const std::string& value : points[p]) out << quoted(value) << ',';
    std::size_t done = 0;
    for (std::size_t i : members[p]) done += results[i].status == TaskStatus::done ? 1 : 0;
    out << members[p].size() << ',' << done;
    for (const std::string& name : measures) {
      double sum = 0.0, sum_of_squares = 0.0;
      std::size_t count = 0;
      const TaskResult* only = nullptr;
      for (std::size_t i : members[p]) {
        const double x = measure(results[i], name);
        if (results[i].status != TaskStatus::done || !std::isfinite(x)) continue;
        sum += x;
        ++count;
        only = &results[i];
      }
      const double mean = count > 0 ? sum / static_cast<double>(count) : std::nan("");
      for (std::size_t i : members[p]) {
        const double x = measure(results[i], name);
        if (results[i].status == TaskStatus::done && std::isfinite(x)) {
          sum_of_squares += (x - mean) * (x - mean);
        }
      }
      // The standard error over the seeds; one task alone has its run's own (block average).
      const double n = static_cast<double>(count);
      const double error = count >= 2   ? std::sqrt(sum_of_squares / (n - 1.0) / n)
                           : count == 1 ? measure(*only, name + "_error")
                                        : std::nan("");
      out << ',' << field(mean) << ',' << field(error);
    }
    out << '\n';
  }
}

}  // namespace

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
