#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "carom/core/system.hpp"
#include "carom/engine/compression.hpp"

namespace carom::cli {

struct CompressArguments {
  std::string input;
  double target = 0.0;
  bool jam = false;
  std::optional<Boundary> boundary;  // the file's record, else walls
  CompressionSettings settings;
  std::string output;
  std::string summary;
  bool unit_diameter = false;  // rescale the result to a mean diameter of 1
  bool quiet = false;
  std::optional<double> progress;  // seconds between status lines, whatever stderr is
};

// Declares `carom compress` on `app`, filling `args` when parsed.
CLI::App* add_compress_command(CLI::App& app, CompressArguments& args);

void compress_command(CompressArguments args);

}  // namespace carom::cli
