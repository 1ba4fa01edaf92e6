#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

#include "carom/run/run.hpp"
#include "carom/run/run_report.hpp"
#include "carom/run/start.hpp"

namespace carom::cli {

// What `carom run` is asked: the library's own descriptions of the start and of the run, which
// the options fill directly, and what only the command line knows.
struct RunArguments {
  StartSpec start;  // FILE, --rule, --restitution, --tc, --boundary, --engine, --kT, --seed,
                    // --sampler, --chain-length
  RunSpec run;      // the outputs, their cadences, --equilibrate, --transport, --check
  std::string end_time;
  std::string checkpoint_every;  // a number of events or of seconds: checkpoint_cadence
  Format format = Format::table;
  bool trace = false;
  std::string output;
  bool resume = false;
  bool quiet = false;
  std::optional<double> progress;  // seconds between status lines, whatever stderr is
  // Made into StartSpec's thermostat and shear by the library's requests (thermostat_request,
  // shear_request), which check them together.
  ThermostatKind thermostat = ThermostatKind::none;
  std::optional<double> thermostat_every, thermostat_rate;
  std::optional<double> shear;
  bool velocity_profile = false;
  bool seed_given = false;  // --seed was given (it needs something to seed)
};

// Declares `carom run` and its options on `app`, filling `args` when parsed.
CLI::App* add_run_command(CLI::App& app, RunArguments& args);

void run_command(const RunArguments& args);

}  // namespace carom::cli
