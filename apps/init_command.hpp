#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "carom/run/start.hpp"

namespace carom::cli {

struct InitArguments {
  InitSpec spec;
  bool lattice = false;
  bool random = false;
  std::string species;  // --species as given, read by init_command
  std::string output;
};

// Declares `carom init` and its options on `app`, filling `args` when parsed.
CLI::App* add_init_command(CLI::App& app, InitArguments& args);

void init_command(InitArguments args);

}  // namespace carom::cli
