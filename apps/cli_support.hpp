// Pieces the carom subcommands share: usage errors, named choices, output files.
#pragma once

#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "carom/atomic_file.hpp"

namespace carom::cli {

// A problem with the command line or its arguments, reported with exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A run stopped by a signal after writing its checkpoint; the exit code is 128 + the signal.
struct Interrupted : std::runtime_error {
  Interrupted(int signal, const std::string& checkpoint)
      : std::runtime_error("interrupted; the run so far is saved in " + checkpoint +
                           ": continue it with 'carom run --resume " + checkpoint + " END_TIME'"),
        signal(signal) {}
  int signal;
};

// An option whose value is one of a few names; help lists them and anything else is refused.
template <class T>
CLI::Option* add_choice(CLI::App* app, const std::string& flag, T& target,
                        const std::vector<std::pair<std::string, T>>& names,
                        const std::string& help) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : names) keys.push_back(key);
  return app
      ->add_option_function<std::string>(
          flag,
          [&target, names](const std::string& chosen) {
            for (const auto& [key, value] : names) {
              if (CLI::detail::to_lower(chosen) == key) target = value;
            }
          },
          help)
      ->check(CLI::IsMember(keys, CLI::ignore_case))
      ->default_str(keys.front());
}

// Where a command writes: standard output, or a file that appears only when complete. Opened
// before any work, so that an unwritable path fails at once.
class Output {
 public:
  explicit Output(const std::string& path) {
    if (path.empty() || path == "-") return;
    try {
      file_ = std::make_unique<AtomicFile>(path);
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
  }
  std::ostream& stream() { return file_ ? file_->stream() : std::cout; }
  void commit() {
    if (file_) {
      file_->commit();
    } else if (!std::cout.flush()) {
      throw std::runtime_error("cannot write to standard output");
    }
  }

 private:
  std::unique_ptr<AtomicFile> file_;
};

// A number from the command line, finite; `what` names it in the message.
double parse_number(const std::string& text, const std::string& what);

}  // namespace carom::cli
