// The carom command line: parses arguments, builds a Simulation, attaches outputs, formats.
// Exit codes: 0 success, 2 usage or input error, 1 runtime failure, 128 + N stopped by signal N.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "analyze_command.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/run/request.hpp"
#include "carom/sweep/sweep.hpp"
#include "carom/version.hpp"
#include "cli_support.hpp"
#include "compress_command.hpp"
#include "init_command.hpp"
#include "run_command.hpp"
#include "sweep_command.hpp"
#include "view_command.hpp"

namespace carom::cli {

namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The known word closest to `word`, if it is close enough to be what was meant.
std::string closest(const std::string& word, const std::vector<std::string>& known) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const std::string& candidate : known) {
    const std::size_t d = edit_distance(word, candidate);
    if (d < best_distance) {
      best = candidate;
      best_distance = d;
    }
  }
  return best;
}

// "did you mean" for the words of the command line the parser did not know: options of the
// subcommand in use, or subcommands.
std::string suggestions(const CLI::App& app, const CLI::App* command, int argc, char** argv) {
  std::vector<std::string> options, commands;
  for (const CLI::App* sub : app.get_subcommands({})) commands.push_back(sub->get_name());
  if (command != nullptr) {
    for (const CLI::Option* option : command->get_options()) {
      for (const std::string& name : option->get_lnames()) options.push_back("--" + name);
    }
  }
  std::string said;
  for (int i = 1; i < argc; ++i) {
    const std::string word = std::string(argv[i]).substr(0, std::string(argv[i]).find('='));
    std::string guess;
    if (word.rfind("--", 0) == 0 && command != nullptr &&
        std::find(options.begin(), options.end(), word) == options.end()) {
      guess = closest(word, options);
    } else if (i == 1 && command == nullptr && word[0] != '-') {
      guess = closest(word, commands);
    }
    if (!guess.empty()) said += "\n  '" + word + "': did you mean '" + guess + "'?";
  }
  return said;
}

}  // namespace

}  // namespace carom::cli

int main(int argc, char** argv) {
  using namespace carom::cli;
  constexpr int kUsageError = 2;
  constexpr int kRuntimeError = 1;

  CLI::App app{"carom: event-driven molecular dynamics of hard disks and spheres.\n", "carom"};
  app.set_version_flag("--version",
                       std::string("carom ") + carom::kVersion + "\n" + sweep_version_note());
  app.require_subcommand(1);
  app.footer(R"(Examples:
  carom run examples/walls_only.txt 20                   the classic assignment's first case
  carom run examples/normal.txt 20 --trace               every collision, step by step
  carom init --n 4096 --phi 0.5 --boundary periodic -o gas.txt    a start (it records its box)
  carom init --dim 3 --n 4000 --phi 0.45 --boundary periodic -o spheres.txt   hard spheres (FCC)
  carom run gas.txt 100 --format json                    elastic, periodic: as gas.txt records
  carom run gas.txt 20 --dump movie.xyz --every 0.1 && carom view movie.xyz -o movie.html
  carom run gas.txt 40 --dump run.gsd --every 0.5 && carom analyze run.gsd --html report.html
  carom compress spheres.txt --jam -o jammed.txt         grow until jammed (~0.64)

  carom sweep eos.toml -o eos                            a plan's runs, on every core (or mpirun)

Run 'carom COMMAND --help' (run, init, compress, sweep, view, analyze) for each command's options.)");

  RunArguments run_args;
  InitArguments init_args;
  CLI::App* run = add_run_command(app, run_args);
  CLI::App* init = add_init_command(app, init_args);
  ViewArguments view_args;
  CLI::App* view = add_view_command(app, view_args);
  AnalyzeArguments analyze_args;
  CLI::App* analyze = add_analyze_command(app, analyze_args);
  CompressArguments compress_args;
  CLI::App* compress = add_compress_command(app, compress_args);
  SweepArguments sweep_args;
  CLI::App* sweep = add_sweep_command(app, sweep_args);

  if (argc <= 1) {
    std::cout << app.help();
    return 0;
  }
  // The command named on the line, for messages (the parser may fail before it knows).
  CLI::App* named = nullptr;
  for (CLI::App* command : {run, init, view, analyze, compress, sweep}) {
    if (command->get_name() == argv[1]) named = command;
  }
  const std::string usage = named != nullptr ? "carom " + named->get_name() : "carom";
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::cerr << "carom: error: " << e.what() << suggestions(app, named, argc, argv) << "\nRun '"
              << usage << " --help' for usage.\n";
    return kUsageError;
  }

  // Only a run and a compression have state worth saving on a signal; the others stop at once,
  // as any program.
  if (run->parsed() || compress->parsed() || sweep->parsed()) {
    carom::install_stop_handlers(stop_signal());
  }
  try {
    if (run->parsed()) run_command(run_args);
    if (init->parsed()) init_command(init_args);
    if (view->parsed()) view_command(view_args);
    if (analyze->parsed()) analyze_command(analyze_args);
    if (compress->parsed()) compress_command(compress_args);
    if (sweep->parsed()) return sweep_command(sweep_args);
    return 0;
  } catch (const Interrupted& e) {
    std::cerr << "carom: " << e.what() << '\n';
    return 128 + e.signal;
  } catch (const UsageError& e) {
    std::cerr << "carom: error: " << e.what() << "\nRun '" << usage << " --help' for usage.\n";
    return kUsageError;
  } catch (const carom::PlanError& e) {  // names the plan's line: the help would not help
    std::cerr << "carom: error: " << e.what() << '\n';
    return kUsageError;
  } catch (const carom::RequestError& e) {  // the library's word for the same
    std::cerr << "carom: error: " << e.what() << "\nRun '" << usage << " --help' for usage.\n";
    return kUsageError;
  } catch (const carom::InputError& e) {
    std::cerr << "carom: error: " << e.what() << '\n';
    return kUsageError;
  } catch (const std::exception& e) {
    // A stop signal may have cut a write short: say so rather than report the write.
    if (const int signal = stop_signal().load(); signal != 0) {
      std::cerr << "carom: " << carom::describe_signal(signal) << ": nothing was written\n";
      return 128 + signal;
    }
    std::cerr << "carom: error: " << e.what() << '\n';
    return kRuntimeError;
  }
}
