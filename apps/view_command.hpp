#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace carom::cli {

struct ViewArguments {
  std::string trajectory;
  std::string output;
};

// Declares `carom view` on `app`, filling `args` when parsed.
CLI::App* add_view_command(CLI::App& app, ViewArguments& args);

void view_command(const ViewArguments& args);

}  // namespace carom::cli
