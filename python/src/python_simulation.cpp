#include "python_simulation.hpp"

#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace carom::python {

namespace {

// Python runs its SIGINT handler only when the main thread runs Python code, which it does not
// while the engine works. During a run a handler of our own records the signal in the library's
// stop flag (honoured within milliseconds, events or not); the previous handler is put back
// after, and given the signal, so that Python does with it what it would have done (raise
// KeyboardInterrupt, or call the user's handler).
std::atomic<int> interrupt_signal{0};

extern "C" void record_interrupt(int signal) {
  interrupt_signal.store(signal);
}

bool on_main_thread() {
  const py::module_ threading = py::module_::import("threading");
  return threading.attr("current_thread")().is(threading.attr("main_thread")());
}

// Only the main thread sees SIGINT in Python: elsewhere nothing is installed and the flag is
// none.
class InterruptHandler {
 public:
  InterruptHandler() : installed_(on_main_thread()) {
    if (!installed_) return;
    interrupt_signal.store(0);
    struct sigaction action = {};
    action.sa_handler = record_interrupt;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_);
  }
  ~InterruptHandler() {
    if (installed_) sigaction(SIGINT, &previous_, nullptr);
  }
  InterruptHandler(const InterruptHandler&) = delete;
  InterruptHandler& operator=(const InterruptHandler&) = delete;

  const std::atomic<int>* flag() const { return installed_ ? &interrupt_signal : nullptr; }
  // Gives a recorded SIGINT to Python's own handler (back in place once this is destroyed):
  // throws what it raises (KeyboardInterrupt), and returns if it raised nothing.
  static void deliver() {
    std::raise(SIGINT);
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }

 private:
  bool installed_;
  struct sigaction previous_ = {};
};

template <class T>
py::array_t<T> vectors(const AnySimulation& s) {
  return py::array_t<T>(
      {static_cast<py::ssize_t>(s.size()), static_cast<py::ssize_t>(s.dimension())});
}
template <class T>
py::array_t<T> scalars(const AnySimulation& s) {
  return py::array_t<T>(static_cast<py::ssize_t>(s.size()));
}

}  // namespace

PythonSimulation::PythonSimulation(Start start) : runner_(std::move(start)) {}

PythonSimulation PythonSimulation::from_arrays(
    const py::array_t<double>& positions, const py::array_t<double>& velocities,
    const py::array_t<double>& box, const py::array_t<double>& radii,
    const py::array_t<double>& masses, std::vector<std::string> type_names,
    const py::array_t<std::uint32_t>& types, Boundary boundary, const Settings& settings) {
  ParticleArrays arrays;
  arrays.dimension = static_cast<int>(positions.shape(1));
  arrays.n = static_cast<std::size_t>(positions.shape(0));
  arrays.positions = positions.data();
  arrays.velocities = velocities.data();
  arrays.box = box.data();
  arrays.radii = radii.data();
  arrays.masses = masses.data();
  arrays.type_names = std::move(type_names);
  arrays.types = types.data();
  arrays.boundary = boundary;
  return PythonSimulation(arrays_start(arrays, settings));
}

std::vector<std::pair<std::string, std::string>> PythonSimulation::run(RunSpec spec,
                                                                       bool collisions) {
  RunHooks hooks;
  if (collisions) hooks.collisions = &log_;
  for (;;) {
    RunOutcome outcome;
    {
      const InterruptHandler handler;
      hooks.stop = handler.flag();
      py::gil_scoped_release release;
      outcome = runner_.run(spec, hooks);
    }
    if (outcome.status == RunStatus::reached) {
      std::vector<std::pair<std::string, std::string>> warnings;
      if (const auto& verdict = outcome.report.drift) {
        if (const auto drift = verdict->drift_warning()) warnings.emplace_back("drift", *drift);
        if (const auto blocks = verdict->correlation_warning()) {
          warnings.emplace_back("correlation", *blocks);
        }
      }
      return warnings;
    }
    // Stopped by SIGINT: Python's own handler gets it now; if it raises nothing, run on.
    InterruptHandler::deliver();
    spec.measure_from.reset();  // opened already
  }
}

std::pair<PythonSimulation, std::string> PythonSimulation::compress(CompressionSpec spec) const {
  spec.input = source();
  CompressionResult result;
  {
    const InterruptHandler handler;
    CompressionHooks hooks;
    hooks.stop = handler.flag();
    py::gil_scoped_release release;
    result = carom::compress(runner_.simulation().snapshot_system(), spec, hooks);
  }
  if (interrupt_signal.load() != 0 && result.summary.status == "interrupted") {
    InterruptHandler::deliver();
  }
  std::ostringstream summary;
  write_json(summary, result.summary);
  Start start{AnySimulation(std::move(result.packing), simulation().settings()),
              "",
              source(),
              false,
              "",
              std::nullopt,
              WindowRecords{}};
  return {PythonSimulation(std::move(start)), summary.str()};
}

py::array PythonSimulation::collisions() {
  // A structured array: time (float64), i and j (int64; j < 0 is a wall label).
  py::list fields;
  fields.append(py::make_tuple("time", "<f8"));
  fields.append(py::make_tuple("i", "<i8"));
  fields.append(py::make_tuple("j", "<i8"));
  const py::dtype dtype = py::dtype::from_args(fields);
  py::array out(dtype, std::vector<py::ssize_t>{static_cast<py::ssize_t>(log_.size())});
  struct Row {
    double time;
    std::int64_t i, j;
  };
  static_assert(sizeof(Row) == 24, "the dtype's 8 + 8 + 8 bytes, unpadded");
  auto* rows = static_cast<Row*>(out.mutable_data());
  for (std::size_t k = 0; k < log_.size(); ++k) {
    rows[k] = {log_[k].time, log_[k].first, log_[k].partner};
  }
  log_.clear();
  return out;
}

py::array_t<double> PythonSimulation::box() const {
  const std::vector<double> sides = simulation().box();
  py::array_t<double> out(static_cast<py::ssize_t>(sides.size()));
  std::copy(sides.begin(), sides.end(), out.mutable_data());
  return out;
}

py::array_t<double> PythonSimulation::positions() const {
  auto out = vectors<double>(simulation());
  simulation().positions(out.mutable_data());
  return out;
}
py::array_t<double> PythonSimulation::velocities() const {
  auto out = vectors<double>(simulation());
  simulation().velocities(out.mutable_data());
  return out;
}
py::array_t<std::int32_t> PythonSimulation::images() const {
  auto out = vectors<std::int32_t>(simulation());
  simulation().images(out.mutable_data());
  return out;
}
py::array_t<double> PythonSimulation::radii() const {
  auto out = scalars<double>(simulation());
  simulation().radii(out.mutable_data());
  return out;
}
py::array_t<double> PythonSimulation::masses() const {
  auto out = scalars<double>(simulation());
  simulation().masses(out.mutable_data());
  return out;
}
py::array_t<std::uint32_t> PythonSimulation::types() const {
  auto out = scalars<std::uint32_t>(simulation());
  simulation().types(out.mutable_data());
  return out;
}
py::array_t<std::uint64_t> PythonSimulation::wall_collisions() const {
  auto out = scalars<std::uint64_t>(simulation());
  simulation().wall_collisions(out.mutable_data());
  return out;
}
py::array_t<std::uint64_t> PythonSimulation::pair_collisions() const {
  auto out = scalars<std::uint64_t>(simulation());
  simulation().pair_collisions(out.mutable_data());
  return out;
}

std::string PythonSimulation::text(Format format, bool particles) const {
  std::ostringstream out;
  write_result(out, simulation(), format, runner_.report(), particles);
  return out.str();
}

void PythonSimulation::measure_from(double t) {
  if (!(t >= 0.0 && std::isfinite(t))) {
    throw std::invalid_argument(fmt::format("measure_from needs a time >= 0, got {}", t));
  }
  runner_.simulation().measure_from(t);
}

void PythonSimulation::save(const std::string& path) const {
  // As carom run --checkpoint: never over the start file read, though a resumed checkpoint may
  // be saved where it was read.
  const Start& start = runner_.start();
  check_files_apart({{"the file read", start_file_path(start.input), start.resumed ? "path" : ""}},
                    {{"path", path}});
  runner_.save(path);
}

}  // namespace carom::python
