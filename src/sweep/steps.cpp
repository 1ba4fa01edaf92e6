// The first and last steps of a sweep, the same whatever runs its tasks.
#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>

#include "carom/io/atomic_file.hpp"
#include "carom/sweep/sweep.hpp"

namespace carom {

PreparedSweep prepare_sweep(const SweepPlan& plan, const std::string& out_dir,
                            const std::string& report) {
  check_sweep_folder(plan, out_dir, report);
  std::filesystem::create_directories(out_dir);
  PreparedSweep sweep{lock_sweep_folder(out_dir), read_task_results(plan, out_dir), {}};
  for (std::size_t i = 0; i < sweep.results.size(); ++i) {
    if (sweep.results[i].status != TaskStatus::done) sweep.waiting.push_back(i);
  }
  return sweep;
}

std::string sweep_report_page(const std::string& out_dir, const std::string& report) {
  return report.empty() ? (std::filesystem::path(out_dir) / kReportPage).string() : report;
}

void finish_sweep(const SweepPlan& plan, const std::string& out_dir,
                  const std::vector<TaskResult>& results, const std::string& report) {
  write_sweep_tables(plan, out_dir, results);
  AtomicFile page(sweep_report_page(out_dir, report));
  write_sweep_report(page.stream(), plan, results);
  page.commit();
}

std::vector<TaskResult> returned_results(const SweepPlan& plan, const std::string& out_dir,
                                         const std::vector<std::size_t>& waiting,
                                         const std::vector<TaskResult>& returned) {
  if (returned.size() != waiting.size()) {
    throw std::invalid_argument(fmt::format("{} tasks were run, but {} results were returned",
                                            waiting.size(), returned.size()));
  }
  std::vector<TaskResult> results = read_task_results(plan, out_dir);
  for (std::size_t k = 0; k < waiting.size(); ++k) {
    TaskResult& held = results.at(waiting[k]);
    if (held.status != returned[k].status || held.error != returned[k].error) held = returned[k];
  }
  return results;
}

}  // namespace carom
