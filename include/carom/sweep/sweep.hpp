// A sweep: many runs or compressions made from one plan file, each a task in its own folder,
// what `carom sweep` (on this machine's cores, or on MPI ranks) and carom.sweep (on Dask) do.
//
// A plan (TOML) has a [start] (carom init's options, or `file = "start.txt"`), a [run] (carom
// run's options, `end_time` first) or a [compress] (carom compress's), and a [sweep] of axes,
// lists of values of any of those keys, whose Cartesian product makes the tasks:
//
//   carom::SweepPlan plan = carom::SweepPlan::read("eos.toml");
//   for (std::size_t i = 0; i < plan.tasks().size(); ++i) carom::run_task(plan, i, "eos");
//   carom::write_sweep_tables(plan, "eos", carom::read_task_results(plan, "eos"));
//
// A task is exactly the commands task_commands() prints (carom init, then carom run or carom
// compress), whatever runs it: its files are theirs, bit for bit. Tasks are resumable: a task
// whose summary is in its folder is finished (done, or failed as a compression that jammed short
// of its target); one with a checkpoint continues it; any other starts over. Where a task runs,
// or on how many workers, changes nothing in what it writes; a lock keeps any two runners from
// one task (task.lock) and any two sweeps from one folder (sweep.lock).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "carom/io/classic_input.hpp"
#include "carom/run/request.hpp"

namespace carom {

// A plan that cannot be run, with the file, line and key: "eos.toml:7: [sweep] phi: ...".
class PlanError : public RequestError {
  using RequestError::RequestError;
};

// A key's value, as TOML gives it (numbers that must be integers stay integers).
using PlanValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

// One key of a task's start, run or compression, and the plan line it comes from.
struct PlanSetting {
  std::string key;  // as in the plan: carom's option without its dashes, '-' as '_'
  PlanValue value;
  int line = 0;
  bool swept = false;  // from a [sweep] axis
};

enum class TaskKind { run, compress };

struct SweepTask {
  std::string name;  // its folder: "phi=0.3,seed=1", the swept keys in the plan's order ("task"
                     // when nothing is swept)
  // The swept keys and their values as the plan writes them ("0.3", "elastic").
  std::vector<std::pair<std::string, std::string>> point;
  std::vector<PlanSetting> start;   // carom init's options, or `file`
  std::vector<PlanSetting> action;  // carom run's (end_time included) or carom compress's
  // carom compress's, when the run starts from the start compressed (a plan with [compress] and
  // [run]: the start a gas, the run at the packing the compression reaches).
  std::vector<PlanSetting> compression;
};

class SweepPlan {
 public:
  // Reads and checks a plan: every key known and of its type, every axis a non-empty list, every
  // task's options accepted by what will run them. Throws PlanError naming the line.
  static SweepPlan read(const std::string& path);
  // The same from the plan's text; `name` names it in messages and `folder` is where a start
  // `file` is looked for (the plan's folder).
  static SweepPlan parse(std::string_view text, const std::string& name, const std::string& folder);

  const std::string& name() const { return name_; }
  const std::string& text() const { return text_; }
  const std::string& folder() const { return folder_; }
  TaskKind kind() const { return kind_; }
  // Whether each run starts from its start compressed first ([compress] and [run]).
  bool compresses_start() const { return compresses_start_; }
  // The swept keys, in the plan's order.
  const std::vector<std::string>& axes() const { return axes_; }
  const std::vector<SweepTask>& tasks() const { return tasks_; }
  // The measures of results.csv (measure_names).
  const std::vector<std::string>& measures() const { return measures_; }
  // A start `file`'s boundary (its box's, as read) and the rule it records: what each task's
  // checks take when [run] does not say (the file is read once, with the plan).
  const StartRecord& start_file_record() const { return start_file_record_; }

 private:
  std::string name_, text_, folder_;
  TaskKind kind_ = TaskKind::run;
  bool compresses_start_ = false;
  std::vector<std::string> axes_;
  std::vector<SweepTask> tasks_;
  std::vector<std::string> measures_;
  StartRecord start_file_record_;
};

// The files of a task, in its folder.
namespace task_files {
inline constexpr const char* kCommands = "task.txt";     // task_commands(), one a line
inline constexpr const char* kStart = "start.txt";       // carom init's start (not with `file`)
inline constexpr const char* kSummary = "summary.json";  // there only when the task is done
inline constexpr const char* kLog = "log.csv";           // a run's time series
inline constexpr const char* kCheckpoint = "checkpoint.ckpt";  // a run's state
inline constexpr const char* kPacking = "packing.txt";         // a compression's packing
// The summary of the compression that made a run's packing, written after it: there only when
// that compression ended (at its target, or jammed before it).
inline constexpr const char* kCompression = "compression.json";
inline constexpr const char* kError = "error.txt";  // why the task failed
inline constexpr const char* kLock = "task.lock";   // held while the task runs
// All of them: a plan's dump or event log may take none of these names, nor that of a temporary
// file of one (AtomicFile::is_temporary_of: carom makes some beside any file it writes).
inline constexpr std::array kOwn = {kCommands, kStart,       kSummary, kLog, kCheckpoint,
                                    kPacking,  kCompression, kError,   kLock};
// Those written whole (AtomicFile): an attempt killed while it wrote one leaves its temporary,
// which a resumed task removes.
inline constexpr std::array kWrittenWhole = {kCommands, kStart,       kSummary, kCheckpoint,
                                             kPacking,  kCompression, kError};
}  // namespace task_files

// In a sweep's folder: held while a sweep runs there.
inline constexpr const char* kSweepLock = "sweep.lock";
// The sweep's report page, unless another is named.
inline constexpr const char* kReportPage = "report.html";

// A lock held while the object lives: an open file description lock (fcntl F_OFD_SETLK) on a
// lock file, held by the open file (two in one process exclude each other), which the OS
// releases when the holder ends, however it ends (a SIGKILL, a crash; a machine's end where the
// file system's server gives its locks up, as NFS does), so that no lock outlives its holder.
// Works across machines where the shared file system keeps such locks for all of them (NFS,
// GPFS, BeeGFS with global locks, Lustre mounted with -o flock; Lustre's -o localflock keeps
// them for one node only); on one that keeps none (Lustre's default)
// taking it throws RequestError, saying so. The file stays (removing it would let two holders
// lock two files of one name); while held, it says who holds it.
class HeldLock {
 public:
  // Takes the lock of `path` (made if missing), or nothing if another holder has it. Throws
  // RequestError if the file cannot be made or its file system keeps no locks.
  static std::optional<HeldLock> try_take(const std::string& path);
  // Who holds the lock of `path`, as the holder wrote it ("pid 4242 on node7"), "" if unknown.
  static std::string holder(const std::string& path);

  HeldLock(HeldLock&& other) noexcept;
  HeldLock& operator=(HeldLock&& other) noexcept;
  HeldLock(const HeldLock&) = delete;
  HeldLock& operator=(const HeldLock&) = delete;
  ~HeldLock();
  void release();  // before the end of its life

 private:
  explicit HeldLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

// out_dir's sweep lock (out_dir/sweep.lock), held by whatever runs a sweep there, so that two
// sweeps never run in one folder at once (a job resubmitted while the first still runs).
// Throws RequestError naming the holder when another sweep holds it. out_dir must exist.
HeldLock lock_sweep_folder(const std::string& out_dir);

// The carom commands that do what the task does, alone, with its files in `folder`.
std::vector<std::string> task_commands(const SweepPlan& plan, std::size_t index,
                                       const std::string& folder);

enum class TaskStatus { done, failed, stopped, pending };

// "done", "failed", "stopped" or "pending": results.csv's status column.
std::string_view status_name(TaskStatus status);

// What a task measured: its summary's observables, by the names of results.csv.
struct TaskResult {
  TaskStatus status = TaskStatus::pending;
  std::string error;                                     // why it failed
  int dimension = 0;                                     // of its particles, once started
  std::vector<std::pair<std::string, double>> measures;  // NaN: not measured
  double wall_seconds = 0.0;                             // its last piece's

  // The measure named `name`, NaN if there is none.
  double measure(std::string_view name) const;

  static TaskResult with(TaskStatus status, std::string error = {}) {
    TaskResult result;
    result.status = status;
    result.error = std::move(error);
    return result;
  }
};

// The measures of the plan's tasks, in results.csv's order: a run's (with `transport = true`,
// its transport coefficients too; with `shear`, the shear's) or a compression's.
// A run's include Z_drift, its summary's drift verdict: how many standard errors Z moved from the
// first half of the measurement window to the second (blank without a verdict). Past
// DriftVerdict::kWarning the task was still changing while measured: the console, summary.csv
// and the report flag it.
inline constexpr std::string_view kDriftMeasure = "Z_drift";
// And Z_correlation: the lag-one autocorrelation of the verdict's blocks' Z, in units of the
// spread independent blocks would give it (1 / sqrt(blocks)). Past
// DriftVerdict::kCorrelationWarning, Z fluctuated over longer than a block and its error
// understates the uncertainty: the console and the report flag it.
inline constexpr std::string_view kCorrelationMeasure = "Z_correlation";
// Whether a task's Z drifted past DriftVerdict::kWarning standard errors.
bool drifted(const TaskResult& result);
// Whether a task's Z blocks were correlated past DriftVerdict::kCorrelationWarning.
bool blocks_correlated(const TaskResult& result);
// What every front end says of a task whose Z did not settle, from its Z_drift and
// Z_correlation: that it drifted, or else that its blocks are correlated; nothing where neither
// (NaN: no verdict, no correlation).
std::optional<std::string> unsettled_warning(double z_drift, double z_correlation);
std::optional<std::string> unsettled_warning(const TaskResult& result);
const std::vector<std::string>& measure_names(const SweepPlan& plan);

struct TaskHooks {
  const std::atomic<int>* stop = nullptr;  // nonzero stops the task (its checkpoint saved)
  // Now and then, the task's fraction done (0 to 1), from whatever thread runs it.
  std::function<void(double)> progress;
};

// Runs task `index` of `plan` in out_dir/<task name>/, going on from what an earlier attempt left
// there (finished, its summary there: read; a checkpoint: continued; else from the start). A
// task that cannot be done (a state point the options cannot make) is failed, its error in
// error.txt; so is a compression that jams short of its target (its packing and summary kept,
// as carom compress keeps them when it exits 1); a stopped one keeps its checkpoint. Holds the
// task's lock (task.lock) while it works: while another holds it (an earlier sweep's Dask worker
// still at the task), waits for it, stopped by hooks.stop meanwhile. Throws RequestError only
// when the folder holds another task's files.
TaskResult run_task(const SweepPlan& plan, std::size_t index, const std::string& out_dir,
                    const TaskHooks& hooks = {});

// What the tasks' folders hold now: done (a summary), failed (error.txt and no summary, or a
// compression's summary that says it jammed short of its target) or pending.
std::vector<TaskResult> read_task_results(const SweepPlan& plan, const std::string& out_dir);

// Refuses (RequestError), before anything is written, a sweep into out_dir that could not
// finish or would destroy what it reads: an out_dir that cannot be a writable folder (a file,
// under a file); a task folder that is a file or holds the files of another task (its task.txt
// differs: the plan changed); a table or a report page that is a folder, or a page whose folder
// is missing; and an output that is an input or another of the sweep's own files, however spelled
// (./, .., symbolic or hard links): the report page (`report`, empty for out_dir/report.html)
// must not be the plan, a start file, a table, a lock or any task's file, and nothing the sweep
// writes may be the plan or a start file.
void check_sweep_folder(const SweepPlan& plan, const std::string& out_dir,
                        const std::string& report = {});

// Throws std::invalid_argument unless `results` has one result for each task of `plan`.
void check_task_results(const SweepPlan& plan, const std::vector<TaskResult>& results);

// out_dir/results.csv (a row a task: the swept keys, status, the measures, the error) and
// out_dir/summary.csv (a row a state point, every axis but `seed`: each measure's mean and
// standard error over the done tasks), written atomically; full precision, and the same bytes
// whatever ran the tasks. Throws what check_task_results throws.
void write_sweep_tables(const SweepPlan& plan, const std::string& out_dir,
                        const std::vector<TaskResult>& results);

struct SweepProgress {
  std::size_t total = 0, done = 0, failed = 0, running = 0;
  double fraction = 0.0;  // of the work, counting each running task's part
  double wall_seconds = 0.0;
};

struct SweepHooks {
  const std::atomic<int>* stop = nullptr;  // stops every running task (checkpoints saved)
  // Called about twice a second from the thread that called run_sweep.
  std::function<void(const SweepProgress&)> progress;
};

// A sweep from its first step to its last, whatever hands its tasks out: run_sweep's threads,
// run_sweep_mpi's ranks, carom.sweep's Dask workers. Each runner calls prepare_sweep, runs the
// waiting tasks as it can, and calls finish_sweep with every task's result.
struct PreparedSweep {
  HeldLock folder_lock;              // out_dir's sweep.lock: kept until finish_sweep has returned
  std::vector<TaskResult> results;   // every task's, as its folder held it (read_task_results)
  std::vector<std::size_t> waiting;  // the tasks not done, in the plan's order: to run
};

// Refuses what check_sweep_folder refuses, makes out_dir, takes its lock (lock_sweep_folder:
// refused while another sweep runs there) and reads what the tasks' folders hold.
PreparedSweep prepare_sweep(const SweepPlan& plan, const std::string& out_dir,
                            const std::string& report = {});

// Where the report of a sweep into out_dir goes: `report`, or out_dir/report.html if empty.
std::string sweep_report_page(const std::string& out_dir, const std::string& report = {});

// Writes the tables (write_sweep_tables) and the report page (sweep_report_page) of `results`,
// every task's in the plan's order, each whole or not at all.
void finish_sweep(const SweepPlan& plan, const std::string& out_dir,
                  const std::vector<TaskResult>& results, const std::string& report = {});

// The results of tasks whose runner got back only each one's status and error (carom.sweep's
// Dask workers: what they return must pickle): `returned[k]` is task waiting[k]'s. What the tasks'
// folders hold now where they agree (their measures included), else what was returned: a failure
// that never reached error.txt (a task folder that could not be written) counts, as with the
// other runners, so that results.csv is the same whatever ran the tasks. Throws
// std::invalid_argument unless there is one returned result for each waiting task.
std::vector<TaskResult> returned_results(const SweepPlan& plan, const std::string& out_dir,
                                         const std::vector<std::size_t>& waiting,
                                         const std::vector<TaskResult>& returned);

// Runs every task not yet done on `jobs` threads of this process, between prepare_sweep and
// finish_sweep (the lock held to the end). Returns every task's result, in the plan's order.
std::vector<TaskResult> run_sweep(const SweepPlan& plan, const std::string& out_dir, unsigned jobs,
                                  const SweepHooks& hooks = {}, const std::string& report = {});

// The swept observables against the first swept axis other than `seed`, with error bars, and
// the equation of state of hard disks (Henderson) or spheres (Kolafa, Labik and Malijevsky)
// beside Z where one applies: a self-contained HTML page.
void write_sweep_report(std::ostream& out, const SweepPlan& plan,
                        const std::vector<TaskResult>& results);

}  // namespace carom
