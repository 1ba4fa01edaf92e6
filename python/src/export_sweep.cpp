// carom._carom's sweep: SweepPlan, and the steps of a sweep that carom.sweep takes around its
// Dask workers (prepare_sweep, run a task, stop the tasks, returned_results, finish_sweep). A bad
// plan (PlanError) or a folder holding other tasks (RequestError) is a std::invalid_argument, which
// pybind11 raises as ValueError.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

#include "carom/run/z_drift.hpp"
#include "carom/sweep/sweep.hpp"
#include "exports.hpp"

namespace carom::python {

namespace {

namespace py = pybind11;

// A task's error as Python text: it may name a file whose name is not UTF-8, which pybind11's
// strict decoding would raise UnicodeDecodeError for; decoded as os.fsdecode decodes a name
// (surrogateescape), so the name survives.
py::str error_text(const std::string& error) {
  PyObject* text =
      PyUnicode_DecodeUTF8(error.data(), static_cast<Py_ssize_t>(error.size()), "surrogateescape");
  if (text == nullptr) throw py::error_already_set();  // out of memory: any bytes decode so
  return py::reinterpret_steal<py::str>(text);
}

// Each task's swept keys and their values as the plan types them (bool, int, float, str, list),
// in the axes' order.
py::list points(const SweepPlan& plan) {
  py::list all;
  for (const SweepTask& task : plan.tasks()) {
    py::dict point;
    for (const std::string& axis : plan.axes()) {
      for (const auto* settings : {&task.start, &task.action}) {
        for (const PlanSetting& s : *settings) {
          if (s.swept && s.key == axis) point[py::str(axis)] = py::cast(s.value);
        }
      }
    }
    all.append(point);
  }
  return all;
}

// The stop flags of the tasks this process runs for a carom.sweep, by the sweep's token.
// carom.sweep, stopped (Ctrl-C), calls stop_tasks(token) on every Dask worker: a worker's thread
// cannot be interrupted, and a cancelled future does not stop it, so the flags do. A token once
// stopped stops the tasks of its sweep that start later too (one already handed to a worker).
class SweepStops {
 public:
  static SweepStops& of_this_process() {
    static SweepStops stops;
    return stops;
  }
  void stop(const std::string& token) {
    std::lock_guard lock(mutex_);
    stopped_.insert(token);
    for (auto [it, end] = running_.equal_range(token); it != end; ++it) it->second->store(1);
  }

  // `stop` raised by stop(token) while it lives (at once if the sweep is already stopped).
  class Registration {
   public:
    Registration(const std::string& token, std::atomic<int>& stop) {
      if (token.empty()) return;
      SweepStops& stops = of_this_process();
      std::lock_guard lock(stops.mutex_);
      if (stops.stopped_.count(token) != 0) stop.store(1);
      entry_ = stops.running_.emplace(token, &stop);
    }
    ~Registration() {
      if (!entry_) return;
      SweepStops& stops = of_this_process();
      std::lock_guard lock(stops.mutex_);
      stops.running_.erase(*entry_);
    }
    Registration(const Registration&) = delete;
    Registration& operator=(const Registration&) = delete;

   private:
    std::optional<std::multimap<std::string, std::atomic<int>*>::iterator> entry_;
  };

 private:
  std::mutex mutex_;
  std::multimap<std::string, std::atomic<int>*> running_;
  std::set<std::string> stopped_;
};

// Python runs its SIGINT handler only on the main thread, and only while that thread runs
// Python, which it does not while a task works. So the task works on a thread of its own while
// this one looks for signals every 50 ms, the GIL released in between; what the handler raises
// (KeyboardInterrupt) stops the task, its checkpoint saved, and is raised once it has stopped.
// Off the main thread (a Dask worker's) no signal is ever seen: there the sweep's token stops it
// (SweepStops).
TaskResult run_task_interruptibly(const SweepPlan& plan, std::size_t index,
                                  const std::string& out_dir, const std::string& sweep_id) {
  std::atomic<int> stop{0};
  const SweepStops::Registration registration(sweep_id, stop);
  TaskHooks hooks;
  hooks.stop = &stop;
  std::packaged_task<TaskResult()> work([&] { return run_task(plan, index, out_dir, hooks); });
  std::future<TaskResult> result = work.get_future();
  std::thread worker(std::move(work));
  const auto join = [&] {
    py::gil_scoped_release release;
    worker.join();
  };
  for (;;) {
    {
      py::gil_scoped_release release;
      if (result.wait_for(std::chrono::milliseconds(50)) == std::future_status::ready) break;
    }
    if (PyErr_CheckSignals() != 0) {
      stop.store(1);
      join();
      throw py::error_already_set();
    }
  }
  join();
  return result.get();
}

// Waits until no one holds the locks of tasks `indices` (their workers stopped and saved), taking
// and dropping each; Ctrl-C gives up the wait (KeyboardInterrupt).
void wait_for_tasks(const SweepPlan& plan, const std::string& out_dir,
                    const std::vector<std::size_t>& indices) {
  for (const std::size_t index : indices) {
    if (index >= plan.tasks().size()) continue;
    const std::filesystem::path lock =
        std::filesystem::path(out_dir) / plan.tasks()[index].name / task_files::kLock;
    if (!std::filesystem::exists(lock)) continue;
    while (!HeldLock::try_take(lock.string())) {
      {
        py::gil_scoped_release release;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
  }
}

}  // namespace

void export_sweep(py::module_& m) {
  using namespace py::literals;
  py::class_<SweepPlan>(m, "SweepPlan")
      .def_static("read", &SweepPlan::read, "path"_a)
      .def_static(
          "parse",
          [](const std::string& text, const std::string& name, const std::string& folder) {
            return SweepPlan::parse(text, name, folder);
          },
          "text"_a, "name"_a, "folder"_a)
      // Paths as bytes: they need not be UTF-8 (the plan's text, TOML, is).
      .def_property_readonly("name", [](const SweepPlan& p) { return py::bytes(p.name()); })
      .def_property_readonly("text", &SweepPlan::text)
      .def_property_readonly("folder", [](const SweepPlan& p) { return py::bytes(p.folder()); })
      .def_property_readonly(
          "kind", [](const SweepPlan& p) { return p.kind() == TaskKind::run ? "run" : "compress"; })
      .def_property_readonly("compresses_start", &SweepPlan::compresses_start)
      .def_property_readonly("axes", &SweepPlan::axes)
      .def_property_readonly("tasks",
                             [](const SweepPlan& p) {
                               std::vector<std::string> names;
                               for (const SweepTask& task : p.tasks()) names.push_back(task.name);
                               return names;
                             })
      .def_property_readonly("points", &points)
      .def(
          "commands",
          [](const SweepPlan& p, std::size_t index, const std::string& folder) {
            return task_commands(p, index, folder);
          },
          "index"_a, "folder"_a);

  py::class_<TaskResult>(m, "TaskResult")
      // A result as a Dask worker returned it, its status's name and its error's bytes, for
      // returned_results.
      .def(py::init([](const std::string& status, const std::string& error) {
             for (const TaskStatus s : {TaskStatus::done, TaskStatus::failed, TaskStatus::stopped,
                                        TaskStatus::pending}) {
               if (status_name(s) == status) return TaskResult::with(s, error);
             }
             throw std::invalid_argument(fmt::format("no task status is named '{}'", status));
           }),
           "status"_a, "error"_a);

  // (status, error): what a Dask task sends back, plain Python that pickles. `sweep_id`: the
  // token stop_tasks stops it by ("" for none).
  m.def(
      "run_task",
      [](const SweepPlan& plan, std::size_t index, const std::string& out_dir,
         const std::string& sweep_id) {
        const TaskResult result = run_task_interruptibly(plan, index, out_dir, sweep_id);
        return py::make_tuple(std::string(status_name(result.status)), error_text(result.error));
      },
      "plan"_a, "index"_a, "out_dir"_a, "sweep_id"_a = "");
  m.def(
      "stop_tasks",
      [](const std::string& sweep_id) { SweepStops::of_this_process().stop(sweep_id); },
      "sweep_id"_a);
  m.def("wait_for_tasks", &wait_for_tasks, "plan"_a, "out_dir"_a, "indices"_a);
  // carom.sweep's first step and last, as every runner's (prepare_sweep, finish_sweep): the
  // prepared sweep is a context manager, whose end lets go of the folder's lock.
  py::class_<PreparedSweep>(m, "PreparedSweep")
      .def_readonly("waiting", &PreparedSweep::waiting)
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](PreparedSweep& sweep, const py::args&) { sweep.folder_lock.release(); });
  m.def("prepare_sweep", &prepare_sweep, "plan"_a, "out_dir"_a, "report"_a = "");
  m.def("returned_results", &returned_results, "plan"_a, "out_dir"_a, "waiting"_a, "returned"_a);
  m.def("finish_sweep", &finish_sweep, "plan"_a, "out_dir"_a, "results"_a, "report"_a = "");
  // Past this many standard errors of Z_drift a task was still changing while measured.
  m.attr("DRIFT_WARNING") = DriftVerdict::kWarning;
  // Past this many spreads of independent blocks' autocorrelation, Z_correlation says a task's Z
  // fluctuated over longer than a block.
  m.attr("CORRELATION_WARNING") = DriftVerdict::kCorrelationWarning;
  m.def("unsettled_warning",
        py::overload_cast<double, double>(&unsettled_warning), "z_drift"_a, "z_correlation"_a);
}

}  // namespace carom::python
