#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

#include "carom/engine/engine.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/run_report.hpp"

namespace carom::cli {

struct RunArguments {
  std::string input;
  std::string end_time;
  Format format = Format::table;
  bool trace = false;
  std::string output;
  std::string summary;
  bool transport = false;
  std::string dump;
  double every = 0.0;
  std::string events;
  std::string log;
  double log_every = 0.0;
  std::string checkpoint;
  std::string checkpoint_every;
  bool resume = false;
  bool check = false;
  std::uint64_t check_every = 0;
  std::optional<Rule> rule;  // default_rule
  double restitution = 1.0;
  double tc = kDefaultTc;
  std::optional<Boundary> boundary;  // the file's record, else walls
  std::optional<double> equilibrate;
  EngineKind engine = EngineKind::fast;
  bool quiet = false;
  std::optional<double> progress;     // seconds between status lines, whatever stderr is
  std::optional<double> temperature;  // --kT: draw new velocities at this kT
  std::uint64_t seed = 1;             // --seed: for them
  ThermostatKind thermostat = ThermostatKind::none;
  std::optional<double> thermostat_every, thermostat_rate;
  std::optional<double> shear;
  bool velocity_profile = false;
};

// Declares `carom run` and its options on `app`, filling `args` when parsed.
CLI::App* add_run_command(CLI::App& app, RunArguments& args);

void run_command(const RunArguments& args);

}  // namespace carom::cli
