#include "carom/mpi_sweep.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <thread>

namespace carom {

namespace {

constexpr int kAskTag = 1;     // a worker's request for a task: {last task, its status}
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

void hand_out(const SweepPlan& plan, const std::string& out_dir, int ranks,
              const SweepHooks& hooks) {
  const std::vector<TaskResult> before = read_task_results(plan, out_dir);
  std::vector<int> waiting;
  for (std::size_t i = 0; i < before.size(); ++i) {
    if (before[i].status != TaskStatus::done) waiting.push_back(static_cast<int>(i));
  }
  SweepProgress progress;
  progress.total = before.size();
  progress.done = before.size() - waiting.size();
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
    int last[2];
    MPI_Recv(last, 2, MPI_INT, status.MPI_SOURCE, kAskTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (last[0] >= 0) {
      --progress.running;
      if (last[1] == static_cast<int>(TaskStatus::done)) ++progress.done;
      if (last[1] == static_cast<int>(TaskStatus::failed)) ++progress.failed;
    }
    int task = kNoMoreTasks;
    // A worker whose task was stopped (a signal) is leaving: it gets no other.
    const bool leaving = last[0] >= 0 && last[1] == static_cast<int>(TaskStatus::stopped);
    if (next < waiting.size() && !stopped(hooks) && !leaving) {
      task = waiting[next++];
      ++progress.running;
    } else {
      --workers;
    }
    MPI_Send(&task, 1, MPI_INT, status.MPI_SOURCE, kAssignTag, MPI_COMM_WORLD);
  }
}

void work(const SweepPlan& plan, const std::string& out_dir, const SweepHooks& hooks) {
  int last[2] = {kNoMoreTasks, 0};
  while (true) {
    MPI_Send(last, 2, MPI_INT, 0, kAskTag, MPI_COMM_WORLD);
    int task = kNoMoreTasks;
    MPI_Recv(&task, 1, MPI_INT, 0, kAssignTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (task == kNoMoreTasks) return;
    TaskResult result;
    try {
      result = run_task(plan, static_cast<std::size_t>(task), out_dir, {hooks.stop, nullptr});
    } catch (const std::exception& e) {
      result = TaskResult::with(TaskStatus::failed, e.what());
    }
    last[0] = task;
    last[1] = static_cast<int>(result.status);
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
                              const SweepHooks& hooks) {
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
    outcome.results = run_sweep(plan, out_dir, jobs, hooks);
    return outcome;
  }
  std::string text = plan.text();
  int go_on = 1;
  if (outcome.rank == 0) {
    try {
      check_sweep_folder(plan, out_dir);
      std::filesystem::create_directories(out_dir);
    } catch (...) {
      go_on = 0;
      broadcast(text, go_on);
      throw;
    }
  }
  broadcast(text, go_on);
  if (go_on == 0) return outcome;
  if (outcome.rank == 0) {
    hand_out(plan, out_dir, outcome.ranks, hooks);
    outcome.results = read_task_results(plan, out_dir);
    write_sweep_tables(plan, out_dir, outcome.results);
  } else {
    work(SweepPlan::parse(text, plan.name(), plan.folder()), out_dir, hooks);
  }
  return outcome;
}

}  // namespace carom
