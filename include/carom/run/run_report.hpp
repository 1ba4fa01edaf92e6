// A run's result as the command line, Python and a sweep report it: the table, csv or json of
// the simulation at its time, with what the run adds (its input, timing, seed, drift verdict,
// error bars and transport coefficients).
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "carom/core/names.hpp"
#include "carom/run/any_simulation.hpp"
#include "carom/run/z_drift.hpp"

namespace carom {

enum class Format { table, csv, json };

template <>
struct EnumNames<Format> {
  static constexpr std::array<std::pair<std::string_view, Format>, 3> table{
      {{"table", Format::table}, {"csv", Format::csv}, {"json", Format::json}}};
};

// What a json result says beyond the simulation itself.
struct RunReport {
  std::string input;                  // the file the run began from
  double wall_seconds = 0.0;          // wall-clock time of the simulation (of this process)
  std::uint64_t events = 0;           // the events processed in that time
  std::optional<std::uint64_t> seed;  // of the velocities the run drew, if it drew any
  std::optional<DriftVerdict> drift;  // of Z over the measurement window, if measured
  // The standard error of the window's pressure tensor (ZDrift::pressure_tensor_error).
  std::optional<SymmetricTensor> pressure_tensor_error;
  // The same for Z (ZDrift::compressibility_factor_error).
  std::optional<double> compressibility_factor_error;
  // The transport coefficients of a run that measured them (--transport), once two blocks of
  // its window are done.
  std::optional<TransportEstimate> transport;
};

// The settings, the whole run's counts (from t = 0, across resumes), the measurement window's
// counts (window_*) and observables, the rate of this process's events and, with `particles`,
// every particle at the simulation's time; numbers in full precision.
template <std::size_t D>
void write_json(std::ostream& out, const Simulation<D>& simulation, const RunReport& report,
                bool particles = true);

// The result of a run at its time, in either dimension: `format` table, csv, or json (with
// every particle, or without: the summary).
void write_result(std::ostream& out, const AnySimulation& simulation, Format format,
                  const RunReport& report, bool particles = true);

}  // namespace carom
