#include "carom/sweep/mpi_sweep.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <thread>
#include <utility>

#include "io/json_text.hpp"

namespace carom {

namespace {

constexpr int kAskTag = 1;     // a worker's request for a task: what came of its last (Report)
constexpr int kAssignTag = 2;  // rank 0's answer: a task's index, or kNoMoreTasks
constexpr int kNoMoreTasks = -1;
// How often rank 0 looks for requests: it sleeps between looks, so that it takes no core from
// the workers (a blocking MPI receive spins).
constexpr auto kPollInterval = std::chrono::milliseconds(20);

// MPI_Init and MPI_Finalize, whatever leaves the scope.
struct MpiSession {
  MpiSession() {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (initialised == 0) MPI_Init(nullptr, nullptr);
  }
  ~MpiSession() {
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (finalised == 0) MPI_Finalize();
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

bool stopped(const SweepHooks& hooks) {
  return hooks.stop != nullptr && hooks.stop->load() != 0;
}

// Rank 0: sends `text` (the plan) and whether to go on to every other rank.
void broadcast(std::string& text, int& go_on) {
  MPI_Bcast(&go_on, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (go_on == 0) return;
  int size = static_cast<int>(text.size());
  MPI_Bcast(&size, 1, MPI_INT, 0, MPI_COMM_WORLD);
  text.resize(static_cast<std::size_t>(size));
  MPI_Bcast(text.data(), size, MPI_CHAR, 0, MPI_COMM_WORLD);
}

// What a worker sends rank 0 when it asks for a task: the task it ran last (kNoMoreTasks before
// its first) and its whole result, as run_task returned it. Rank 0 keeps these results, as
// run_sweep keeps its threads', so that results.csv and the exit code are the same whatever ran
// the tasks: a failure that never reached error.txt (a task folder that cannot be written)
// included.
struct Report {
  int task = kNoMoreTasks;
  TaskResult result;
};

// NaN (not measured; a clock not read) has no json number: null stands for it.
nlohmann::json number(double value) {
  return std::isnan(value) ? nlohmann::json(nullptr) : nlohmann::json(value);
}

double number_in(const nlohmann::json& json) {
  return json.is_null() ? std::nan("") : json.get<double>();
}

// dump_json and parse_json: an error may name a file whose name is not UTF-8.
std::string encode(const Report& report) {
  nlohmann::json measures = nlohmann::json::array();
  for (const auto& [name, value] : report.result.measures)
    measures.push_back({name, number(value)});
  return dump_json(nlohmann::json{{"task", report.task},
                                  {"status", static_cast<int>(report.result.status)},
                                  {"error", report.result.error},
                                  {"dimension", report.result.dimension},
                                  {"measures", measures},
                                  {"wall_seconds", number(report.result.wall_seconds)}});
}

Report decode(const std::string& text) {
  const nlohmann::json json = parse_json(text);
  Report report;
  report.task = json.at("task").get<int>();
  report.result.status = static_cast<TaskStatus>(json.at("status").get<int>());
  report.result.error = json.at("error").get<std::string>();
  report.result.dimension = json.at("dimension").get<int>();
  report.result.wall_seconds = number_in(json.at("wall_seconds"));
  for (const nlohmann::json& measure : json.at("measures")) {
    report.result.measures.emplace_back(measure[0].get<std::string>(), number_in(measure[1]));
  }
  return report;
}

// A worker's report, which rank 0 waits for: one that cannot be written is sent as a failure
// saying why, so that the worker never leaves without it.
std::string encode_surely(const Report& report) {
  try {
    return encode(report);
  } catch (const std::exception& e) {
    return encode(
        {report.task, TaskResult::with(TaskStatus::failed,
                                       fmt::format("its result could not be sent: {}", e.what()))});
  }
}

// Rank 0: hands the sweep's waiting tasks out to the ranks as they ask, until every rank has
// left; each task's result becomes what its worker reported.
void hand_out(PreparedSweep& sweep, int ranks, const SweepHooks& hooks) {
  std::vector<TaskResult>& results = sweep.results;
  const std::vector<std::size_t>& waiting = sweep.waiting;
  SweepProgress progress;
  progress.total = results.size();
  // The counter a result's status adds to, if any: the counts are kept as results arrive, since
  // counting them all again at each would take quadratic time over a sweep of 100,000 tasks.
  const auto counter = [&progress](const TaskResult& result) -> std::size_t* {
    if (result.status == TaskStatus::done) return &progress.done;
    if (result.status == TaskStatus::failed) return &progress.failed;
    return nullptr;
  };
  for (const TaskResult& result : results) {
    if (std::size_t* count = counter(result)) ++*count;
  }
  const auto begun = std::chrono::steady_clock::now();
  std::size_t next = 0;
  int workers = ranks - 1;
  auto reported = begun;
  while (workers > 0) {
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kAskTag, MPI_COMM_WORLD, &arrived, &status);
    const auto now = std::chrono::steady_clock::now();
    if (hooks.progress && now - reported > std::chrono::milliseconds(500)) {
      progress.wall_seconds = std::chrono::duration<double>(now - begun).count();
      progress.fraction = static_cast<double>(progress.done + progress.failed) /
                          static_cast<double>(std::max<std::size_t>(progress.total, 1));
      hooks.progress(progress);
      reported = now;
    }
    if (arrived == 0) {
      std::this_thread::sleep_for(kPollInterval);
      continue;
    }
    int size = 0;
    MPI_Get_count(&status, MPI_CHAR, &size);
    std::string text(static_cast<std::size_t>(size), '\0');
    MPI_Recv(text.data(), size, MPI_CHAR, status.MPI_SOURCE, kAskTag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    Report last = decode(text);
    // A worker whose task was stopped (a signal) is leaving: it gets no other.
    bool leaving = false;
    if (last.task != kNoMoreTasks) {
      --progress.running;
      leaving = last.result.status == TaskStatus::stopped;
      TaskResult& result = results.at(static_cast<std::size_t>(last.task));
      if (std::size_t* count = counter(result)) --*count;
      result = std::move(last.result);
      if (std::size_t* count = counter(result)) ++*count;
    }
    int task = kNoMoreTasks;
    if (next < waiting.size() && !stopped(hooks) && !leaving) {
      task = static_cast<int>(waiting[next++]);
      ++progress.running;
    } else {
      --workers;
    }
    MPI_Send(&task, 1, MPI_INT, status.MPI_SOURCE, kAssignTag, MPI_COMM_WORLD);
  }
}

void work(const SweepPlan& plan, const std::string& out_dir, const SweepHooks& hooks) {
  Report last;
  while (true) {
    std::string text = encode_surely(last);
    MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, 0, kAskTag, MPI_COMM_WORLD);
    int task = kNoMoreTasks;
    MPI_Recv(&task, 1, MPI_INT, 0, kAssignTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (task == kNoMoreTasks) return;
    last.task = task;
    try {
      last.result = run_task(plan, static_cast<std::size_t>(task), out_dir, {hooks.stop, nullptr});
    } catch (const std::exception& e) {
      last.result = TaskResult::with(TaskStatus::failed, e.what());
    }
  }
}

}  // namespace

std::string mpi_library_version() {
  char version[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(version, &length);
  std::string text(version, static_cast<std::size_t>(length));
  if (const auto end = text.find_first_of(",\n"); end != std::string::npos) text.resize(end);
  return text;
}

MpiSweepOutcome run_sweep_mpi(const SweepPlan& plan, const std::string& out_dir, unsigned jobs,
                              const SweepHooks& hooks, const std::string& report) {
  MpiSession session;
  MpiSweepOutcome outcome;
  MPI_Comm_rank(MPI_COMM_WORLD, &outcome.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &outcome.ranks);
  if (outcome.ranks == 1) {
    // A launcher that started several processes MPI cannot join (srun without --mpi=pmix, say)
    // would have each run every task, over each other's files.
    for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
      if (const char* launched = std::getenv(variable);
          launched != nullptr && std::atoi(launched) > 1) {
        throw RequestError(fmt::format(
            "launched as {} processes ({}), but MPI sees this one alone: the launcher and this "
            "carom's MPI ({}) do not match",
            launched, variable, mpi_library_version()));
      }
    }
    outcome.results = run_sweep(plan, out_dir, jobs, hooks, report);
    return outcome;
  }
  std::string text = plan.text();
  int go_on = 1;
  // Rank 0 holds the sweep's lock from its checks to its last table, as run_sweep does.
  std::optional<PreparedSweep> sweep;
  if (outcome.rank == 0) {
    try {
      sweep = prepare_sweep(plan, out_dir, report);
    } catch (...) {
      go_on = 0;
      broadcast(text, go_on);
      throw;
    }
  }
  broadcast(text, go_on);
  if (go_on == 0) return outcome;
  if (outcome.rank == 0) {
    hand_out(*sweep, outcome.ranks, hooks);
    finish_sweep(plan, out_dir, sweep->results, report);
    outcome.results = std::move(sweep->results);
  } else {
    work(SweepPlan::parse(text, plan.name(), plan.folder()), out_dir, hooks);
  }
  return outcome;
}

}  // namespace carom
