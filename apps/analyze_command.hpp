#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

namespace carom::cli {

struct AnalyzeArguments {
  std::string trajectory;
  std::string output;  // JSON ("-": standard output)
  std::string html;
  std::string log;
  std::string from_time, bin_width, r_max, contact_width, order_cutoff;
  bool from_centre_of_mass = false;  // --com
  std::string k_max, fs_k;
  std::optional<std::string> only;  // --only: the analyses to compute (absent: every one)
};

// Declares `carom analyze` on `app`, filling `args` when parsed.
CLI::App* add_analyze_command(CLI::App& app, AnalyzeArguments& args);

void analyze_command(const AnalyzeArguments& args);

}  // namespace carom::cli
