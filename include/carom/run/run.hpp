// A whole run, outputs included, in no particular dimension: what `carom run`, the Python
// module's Simulation.run and the sweep runner all do, here once. A RunSpec (a value: the end
// time, the measurement window, every file to write and how often, the checks) is handed to a
// Runner, which owns the Simulation and the streamed files it writes:
//
//   carom::Runner runner(carom::load_start({.path = "gas.txt"}));
//   carom::RunSpec spec{.end_time = 200.0, .measure_from = 50.0};
//   spec.dump = "movie.gsd", spec.dump_every = 1.0;
//   carom::RunOutcome outcome = runner.run(spec);   // outcome.report: what --format json adds
//
// Streamed files (frames, the event log, the time series) are written as the run goes and kept
// when it stops early; a run that continues a checkpoint continues them (what they hold from
// after the checkpoint, written by a run killed later, is cut off first), so that pieces of a
// run give the files of one. A checkpoint is saved at the end, on the cadence asked for, when
// the run is stopped, and when a write fails as the run goes; the summary appears whole at the
// end or not at all. The Runner keeps the streamed files open from one run() to the next that
// names them again with the same cadence (the Python module's habit of running in pieces).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "carom/run/any_simulation.hpp"
#include "carom/run/request.hpp"
#include "carom/run/run_report.hpp"
#include "carom/run/start.hpp"

namespace carom {

// What a run does, as carom run's options say (their names are in the comments).
struct RunSpec {
  double end_time = 0.0;                    // END_TIME: absolute, not before the run's time
  std::optional<double> measure_from;       // --equilibrate: the measurement window opens then
  std::string dump;                         // --dump: frames (.xyz, .lammpstrj, .gsd)
  double dump_every = 0.0;                  // --every
  std::string events;                       // --events: every collision, csv
  std::string log;                          // --log: the time series, csv
  double log_every = 0.0;                   // --log-every
  std::string summary;                      // --summary: the json summary, written at the end
  std::string checkpoint;                   // --checkpoint: saved at the end and when stopped
  // --final: the state at the end as a start file, at full precision (write_final_state; .gsd
  // or the classic start format), written when the run reaches its end, as the summary is.
  std::string final_state;
  std::optional<Trigger> checkpoint_every;  // --checkpoint-every: also this often
  // --transport: self-diffusion, shear viscosity and thermal conductivity over the measurement
  // window (transport.hpp), in the summary; a periodic box only.
  bool transport = false;
  bool check = false;             // --check: invariants checked as the run goes
  std::uint64_t check_every = 0;  // --check-every: events between overlap checks (0: N,
                                  // at least 1000)
};

// What a run reports as it goes, to a front end that shows it.
struct RunProgress {
  double start_time = 0.0, end_time = 0.0;  // of this run
  double wall_seconds = 0.0;                // since it began
  std::uint64_t events = 0;                 // processed in that time
};

// How a run talks to its caller: everything here is optional.
struct RunHooks {
  // Nonzero stops the run after the event being processed (a signal handler's flag, say).
  const std::atomic<int>* stop = nullptr;
  // The classic assignment's step-by-step trace (TraceWriter), written here: the start, every
  // collision, and the end state once the end time is reached.
  std::ostream* trace = nullptr;
  // Called every few thousand events (kProgressEvents) while the run goes.
  std::function<void(const AnySimulation&, const RunProgress&)> progress;
  // Every collision of the run, appended here as it happens.
  std::vector<Event>* collisions = nullptr;
};

inline constexpr std::uint64_t kProgressEvents = 4096;

// How a run ended, and what its summary says of it.
struct RunOutcome {
  RunStatus status = RunStatus::reached;  // reached, or stopped by the flag
  RunReport report;
};

// A run that failed as it went (a write that failed: a full disk), whose state up to then is
// saved in `checkpoint` (at `time`), from where it continues.
class SavedRunError : public std::runtime_error {
 public:
  SavedRunError(const std::string& cause, std::string checkpoint, double time);
  const std::string& checkpoint() const { return checkpoint_; }
  double time() const { return time_; }

 private:
  std::string checkpoint_;
  double time_;
};

// --checkpoint-every's cadence: a whole number of events ("1000000") or seconds ("600s").
// Throws RequestError for anything else.
Trigger checkpoint_cadence(const std::string& every);

// Throws RequestError for what no run can do, whatever it runs from: a cadence that is not a
// positive number, one without its file or a file without its cadence, a cadence without a
// checkpoint, a negative measurement start, two outputs that are one file.
void check_run_spec(const RunSpec& spec);

// The checks of Runner::check that need the run's box but not its particles, for a run from time
// `now`: an end time beyond what a double resolves (RunLengthError), more than 10^7 frames or log
// rows, --transport without a periodic box, in a sheared one or with event chains (RequestError).
// carom sweep checks every task's run with it before any runs.
void check_run_in_box(const RunSpec& spec, double now, bool periodic, bool sheared,
                      SamplerKind sampler);

class Runner {
 public:
  explicit Runner(Start start);
  ~Runner();
  Runner(Runner&&) noexcept;
  Runner& operator=(Runner&&) noexcept;

  // Throws what run(spec) would refuse before running anything: RequestError (check_run_spec,
  // and against the run: more than 10^7 frames or rows, a dump the disk cannot hold, a window
  // that opens before the run's time or, with no checkpoint, after its end, an unwritable
  // checkpoint or summary) and RunLengthError (an end time the run cannot reach). A front end's
  // own outputs, {option, path} (the command line's -o), are checked against the run's files
  // and its input too.
  void check(const RunSpec& spec, const std::vector<NamedFile>& other_outputs = {}) const;
  // Runs to spec.end_time, writing what spec names. Returns when the end time is reached or the
  // stop flag is set (status stopped: the checkpoint, if any, is saved; the summary is not
  // written). Throws what check() throws, JamError and InvariantError (nothing saved: the state
  // is not sound), SavedRunError, and std::runtime_error when a streamed file could not be
  // written (the end state saved in the checkpoint, if any).
  RunOutcome run(const RunSpec& spec, const RunHooks& hooks = {});
  // Writes the checkpoint of the run so far to `path` (atomically): what a run's --checkpoint
  // holds when saved at that instant, the last run()'s window records with the state, so that a
  // run resumed from it to the same end reports that run's summary.
  void save(const std::string& path) const;

  AnySimulation& simulation();
  const AnySimulation& simulation() const;
  const Start& start() const;
  // What the json output says of the runs so far (the wall time and events of every run()).
  RunReport report() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace carom
