#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

namespace carom::cli {

struct ViewArguments {
  std::string trajectory;
  std::string output;
  std::uint64_t stride = 1;  // every stride-th frame
  std::string frames;        // A:B, the frames from A up to (not including) B
};

// Declares `carom view` on `app`, filling `args` when parsed.
CLI::App* add_view_command(CLI::App& app, ViewArguments& args);

void view_command(const ViewArguments& args);

}  // namespace carom::cli
