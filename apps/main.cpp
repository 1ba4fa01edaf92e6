// The carom command line: parses arguments, calls the library, formats. Exit codes: 0 success,
// 2 usage or input error, 1 runtime failure.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <string>

#include "carom/classic_input.hpp"
#include "carom/version.hpp"
#include "cli_support.hpp"
#include "init_command.hpp"
#include "run_command.hpp"
#include "view_command.hpp"

namespace carom::cli {

double parse_number(const std::string& text, const std::string& what) {
  try {
    return parse_finite_double(text);
  } catch (const std::invalid_argument& e) {
    throw UsageError(what + ": " + e.what());
  }
}

}  // namespace carom::cli

int main(int argc, char** argv) {
  using namespace carom::cli;
  constexpr int kUsageError = 2;
  constexpr int kRuntimeError = 1;

  CLI::App app{"carom: event-driven molecular dynamics of hard disks.\n", "carom"};
  app.set_version_flag("--version", std::string("carom ") + carom::kVersion);
  app.require_subcommand(1);
  app.footer(R"(Examples:
  carom run examples/walls_only.txt 20                   the seed's first case
  carom run examples/normal.txt 20 --trace               every collision, step by step
  carom init --n 4096 --phi 0.5 --seed 1 -o gas.txt      a start file
  carom run gas.txt 100 --rule elastic --boundary periodic --format json
  carom run gas.txt 20 --dump movie.xyz --every 0.1 && carom view movie.xyz -o movie.html

Run 'carom run --help', 'carom init --help' or 'carom view --help' for each command's options.)");

  RunArguments run_args;
  InitArguments init_args;
  CLI::App* run = add_run_command(app, run_args);
  CLI::App* init = add_init_command(app, init_args);
  ViewArguments view_args;
  CLI::App* view = add_view_command(app, view_args);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kUsageError;
  }

  const std::string command = run->parsed() ? "run" : init->parsed() ? "init" : "view";
  try {
    if (run->parsed()) run_command(run_args);
    if (init->parsed()) init_command(init_args);
    if (view->parsed()) view_command(view_args);
    return 0;
  } catch (const Interrupted& e) {
    std::cerr << "carom: " << e.what() << '\n';
    return 128 + e.signal;
  } catch (const UsageError& e) {
    std::cerr << "carom: error: " << e.what() << "\nRun 'carom " << command
              << " --help' for usage.\n";
    return kUsageError;
  } catch (const carom::InputError& e) {
    std::cerr << "carom: error: " << e.what() << '\n';
    return kUsageError;
  } catch (const std::exception& e) {
    std::cerr << "carom: error: " << e.what() << '\n';
    return kRuntimeError;
  }
}
