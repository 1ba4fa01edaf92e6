// Pieces the carom subcommands share: usage errors, the stop signal, named choices, output files.
#pragma once

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdint>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "carom/core/names.hpp"
#include "carom/io/atomic_file.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/run/request.hpp"
#include "carom/run/stop_signal.hpp"

namespace carom::cli {

// A problem with the command line or its arguments, reported with exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A command stopped by a signal; the exit code is 128 + the signal. The message says what was
// kept.
struct Interrupted : std::runtime_error {
  Interrupted(int signal, const std::string& what) : std::runtime_error(what), signal(signal) {}
  int signal;
};

// The signal (SIGINT, SIGTERM, SIGHUP) that asked the command to stop, or 0: main() has the
// library's opt-in handlers set it (carom/run/stop_signal.hpp); the simulation polls it.
inline std::atomic<int>& stop_signal() {
  static std::atomic<int> requested{0};
  return requested;
}

// Throws Interrupted(`what`) if a stop signal arrived.
inline void stop_if_asked(const std::string& what) {
  if (const int signal = stop_signal().load(); signal != 0) {
    throw Interrupted(signal, describe_signal(signal) + ": " + what);
  }
}

// An option whose value is one of an enum's names (its EnumNames table); help lists them,
// anything else is refused, and case does not matter. `target` is an E, or a std::optional<E>
// left empty when the option is not given (its default then comes from elsewhere: say where with
// default_str).
template <class E, class Target>
CLI::Option* add_choice(CLI::App* app, const std::string& flag, Target& target,
                        const std::string& help) {
  std::vector<std::string> keys;
  for (const auto& entry : EnumNames<E>::table) keys.emplace_back(entry.first);
  return app
      ->add_option_function<std::string>(
          flag,
          [&target](const std::string& chosen) {
            target = *from_name<E>(CLI::detail::to_lower(chosen));
          },
          help)
      ->check(CLI::IsMember(keys, CLI::ignore_case))
      ->default_str(keys.front());
}

// --progress SECONDS: a status line on stderr every SECONDS, terminal or not.
inline CLI::Option* add_progress_option(CLI::App* app, std::optional<double>& every) {
  return app
      ->add_option("--progress", every,
                   "Print a status line to stderr every SECONDS, whatever stderr is (for batch "
                   "jobs' logs; on a terminal one line is otherwise kept up to date)")
      ->type_name("SECONDS");
}

inline void check_progress(const std::optional<double>& every) {
  if (every && !(*every > 0.0 && *every <= 1e9)) {
    throw UsageError(fmt::format("--progress must be a number of seconds above 0, got {}", *every));
  }
}

// Where a command writes its result: standard output, or a file that appears only when complete.
// Opened before any work, so that an unwritable path fails at once; not committed when a stop
// signal arrived meanwhile.
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
    stop_if_asked("nothing was written");
    keep();
  }
  // Commits even after a stop signal: for a result that is valid however the work ended (the
  // packing a stopped compression reached).
  void keep() {
    if (file_) {
      file_->commit();
    } else if (!std::cout.flush()) {
      throw std::runtime_error("cannot write to standard output");
    }
  }

 private:
  std::unique_ptr<AtomicFile> file_;
};

// A whole number from the command line, from `least` to `most`: decimal digits only, so that
// "-5" is refused rather than wrapped round to 2^64 - 5 (as strtoull, CLI11's reading of an
// unsigned option, does), "010" is ten rather than octal eight, and "0x10" and "1.5" are
// refused. Throws CLI::ValidationError (a usage error) naming `option` and the range: "from
// least to most" when `most` is the option's own bound (`bounded`), else "at least least" (`most`
// is then only its type's).
std::uint64_t parse_whole(const std::string& text, const std::string& option, std::uint64_t least,
                          std::uint64_t most, bool bounded);

// An option (`names` as add_option's) taking a whole number from `least` to `most` (parse_whole;
// by default up to what `Integer` holds) into `target`: every integer option of carom is declared
// with this.
template <class Integer>
CLI::Option* add_whole_option(CLI::App* app, const std::string& names, Integer& target,
                              Integer least, const std::string& help,
                              std::optional<Integer> most = std::nullopt) {
  const std::string option = names.substr(names.rfind(',') + 1);  // the long name
  return app
      ->add_option_function<std::string>(
          names,
          [&target, option, least, most](const std::string& text) {
            target = static_cast<Integer>(parse_whole(
                text, option, static_cast<std::uint64_t>(least),
                static_cast<std::uint64_t>(most.value_or(std::numeric_limits<Integer>::max())),
                most.has_value()));
          },
          help)
      ->type_name("N");
}

// A number from the command line, finite; `what` names it in the message.
double parse_number(const std::string& text, const std::string& what);

// Lets through only what parse_number reads (no hex floats, infinities or NaN, nothing out of
// range): every numeric option checks its text with it, so all of them read numbers alike.
inline const CLI::Validator& finite_number() {
  static const CLI::Validator validator(
      [](std::string& text) -> std::string {
        try {
          parse_finite_double(text);
          return {};
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
      },
      "NUMBER");
  return validator;
}

}  // namespace carom::cli
