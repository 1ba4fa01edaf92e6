// carom analyze whole: a trajectory and a run's log read, analysed, and the result written as
// JSON and as a report page. The command line and carom.analyze both call analyze(AnalysisSpec);
// they only parse their arguments and format what it returns.
#pragma once

#include <stdexcept>

#include "carom/analysis/analysis.hpp"
#include "carom/run/request.hpp"

namespace carom {

// The trajectory cannot be analysed as asked (no frame left after options.from_time, frames that
// do not share one box, a bin the box cannot have): what analyze(frames, ...) refuses, told apart
// from a refused request (a RequestError), which the command line words differently.
class AnalysisError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// What to analyse and where the results go. Each file is named in messages by its `option`: the
// command line's words unless a front end gives its own.
struct AnalysisSpec {
  NamedFile trajectory{"the input TRAJECTORY", ""};  // a .gsd or extended .xyz trajectory
  NamedFile log{"--log", ""};                        // a carom run --log table to add; "": none
  NamedFile json{"-o", ""};                          // where the JSON goes; "": not written
  NamedFile html{"--html", ""};                      // where the report page goes; "": not written
  AnalysisOptions options;
};

// Reads spec.trajectory (and spec.log), analyses it and writes spec.json and spec.html, each
// whole or not at all; returns the analysis, for a front end's own summary or JSON. Refuses
// first, before any work, an output that is an input or another output (check_files_apart:
// RequestError); throws InputError for a file that cannot be read, AnalysisError for frames that
// cannot be analysed as asked, std::runtime_error for an output that cannot be written.
Analysis analyze(const AnalysisSpec& spec);

}  // namespace carom
