// A sweep on this machine: the tasks not yet done, handed out in the plan's order to `jobs`
// threads, each running one task at a time.
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <utility>

#include "carom/sweep/sweep.hpp"

namespace carom {

std::vector<TaskResult> run_sweep(const SweepPlan& plan, const std::string& out_dir, unsigned jobs,
                                  const SweepHooks& hooks, const std::string& report) {
  PreparedSweep sweep = prepare_sweep(plan, out_dir, report);
  std::vector<TaskResult>& results = sweep.results;
  const std::vector<std::size_t>& waiting = sweep.waiting;
  const auto stopped = [&] { return hooks.stop != nullptr && hooks.stop->load() != 0; };

  std::mutex mutex;
  std::condition_variable changed;
  std::vector<double> fraction(results.size(), 0.0);
  for (std::size_t i = 0; i < results.size(); ++i) {
    fraction[i] = results[i].status == TaskStatus::done ? 1.0 : 0.0;
  }
  std::size_t next = 0, running = 0, working = 0;
  const auto work = [&] {
    while (true) {
      std::size_t index = 0;
      {
        std::lock_guard lock(mutex);
        if (next == waiting.size() || stopped()) {
          --working;
          changed.notify_all();
          return;
        }
        index = waiting[next++];
        ++running;
      }
      TaskHooks task_hooks;
      task_hooks.stop = hooks.stop;
      task_hooks.progress = [&, index](double f) {
        std::lock_guard lock(mutex);
        fraction[index] = std::clamp(f, 0.0, 1.0);
      };
      TaskResult result;
      try {
        result = run_task(plan, index, out_dir, task_hooks);
      } catch (const std::exception& e) {
        result = TaskResult::with(TaskStatus::failed, e.what());
      }
      {
        std::lock_guard lock(mutex);
        fraction[index] = result.status == TaskStatus::stopped ? fraction[index] : 1.0;
        results[index] = std::move(result);
        --running;
      }
      changed.notify_all();
    }
  };

  const auto begun = std::chrono::steady_clock::now();
  const auto tell_progress = [&] {
    if (!hooks.progress) return;
    SweepProgress p;
    {
      std::lock_guard lock(mutex);
      p.total = results.size();
      p.running = running;
      for (std::size_t i = 0; i < results.size(); ++i) {
        p.done += results[i].status == TaskStatus::done ? 1 : 0;
        p.failed += results[i].status == TaskStatus::failed ? 1 : 0;
        p.fraction += fraction[i] / static_cast<double>(results.size());
      }
    }
    p.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begun).count();
    hooks.progress(p);
  };

  const unsigned threads = static_cast<unsigned>(
      std::min<std::size_t>(std::max(jobs, 1u), std::max<std::size_t>(waiting.size(), 1)));
  working = threads;
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work);
  {
    std::unique_lock lock(mutex);
    while (working > 0) {
      changed.wait_for(lock, std::chrono::milliseconds(500));
      lock.unlock();
      tell_progress();
      lock.lock();
    }
  }
  for (std::thread& thread : pool) thread.join();
  tell_progress();
  finish_sweep(plan, out_dir, results, report);
  return std::move(results);
}

}  // namespace carom
