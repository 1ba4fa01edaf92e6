// The plan fuzzer's code path: any bytes as a sweep plan (SweepPlan::parse: the nesting bound,
// toml++, every key's type and every task's checks), and what is accepted made into each task's
// commands and, with made-up results, into results.csv, summary.csv and the report. Shared by the
// libFuzzer target and the replay test, so every corpus and regression plan also runs under plain
// `make test`.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "carom/sweep/sweep.hpp"

namespace carom::fuzz {

struct PlanOutcome {
  int refused = 0;   // PlanError: refused with a message naming the plan's line
  int accepted = 0;  // read, its tasks listed and tabled
  std::size_t tasks = 0;
  int violations = 0;  // another exception, or a message that names no line: a bug
};

// A scratch folder holding a start file (`file = "start.txt"` plans read it), made once.
inline const std::filesystem::path& plan_folder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("carom-fuzz-plan-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    std::ofstream(path / "start.txt") << "2\n0.5\n10 10\n2 2 1 0\n5 5 0 1\n";
    return path;
  }();
  return folder;
}

inline PlanOutcome plan(const std::uint8_t* data, std::size_t size) {
  PlanOutcome outcome;
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::filesystem::path& folder = plan_folder();
  try {
    const SweepPlan plan = SweepPlan::parse(text, "fuzz.toml", folder.string());
    ++outcome.accepted;
    outcome.tasks = plan.tasks().size();
    if (plan.tasks().size() > 1000) return outcome;  // keep it quick
    std::vector<TaskResult> results;
    for (std::size_t i = 0; i < plan.tasks().size(); ++i) {
      task_commands(plan, i, "out/" + plan.tasks()[i].name);
      // Done, failed (an error with line breaks and quotes) or pending, in turn.
      TaskResult result = TaskResult::with(i % 3 == 1 ? TaskStatus::failed : TaskStatus::pending,
                                           "broke,\r\n\"here\"");
      if (i % 3 == 0) {
        result = TaskResult::with(TaskStatus::done);
        result.dimension = 2;
        result.measures = {{"Z", 1.0 + 1e-16 * static_cast<double>(i)}, {"Z_error", 1e-3}};
      }
      results.push_back(result);
    }
    write_sweep_tables(plan, folder.string(), results);
    std::ostringstream page;
    write_sweep_report(page, plan, results);
  } catch (const PlanError& e) {
    ++outcome.refused;
    if (std::string(e.what()).rfind("fuzz.toml:", 0) != 0) ++outcome.violations;
  } catch (const std::exception&) {
    ++outcome.violations;
  }
  return outcome;
}

}  // namespace carom::fuzz
