// carom sweep: many runs or compressions from one plan, on this machine's cores or MPI ranks.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

namespace carom::cli {

struct SweepArguments {
  std::string plan;
  std::string output;  // the folder; default: the plan's name without .toml
  bool dry_run = false;
  unsigned jobs = 0;  // 0: every core
  std::string html;   // default DIR/report.html
  bool quiet = false;
  std::optional<double> progress;
};

CLI::App* add_sweep_command(CLI::App& app, SweepArguments& args);
// Returns the exit code: 0 every task done, 100 + K when K tasks failed (127 for 27 or more).
int sweep_command(const SweepArguments& args);

// What --version adds: the MPI library carom sweep runs on, or that there is none.
std::string sweep_version_note();

}  // namespace carom::cli
