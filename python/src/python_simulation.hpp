// The Simulation the Python module exposes: the library's Runner (an AnySimulation and the
// files its runs stream) with what Python adds around it: numpy arrays, the GIL released while
// the engine works, Ctrl-C, and a collision log drained after each run. No dimension appears
// here: the library's dimension-free entry points choose it.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/compress_run.hpp"
#include "carom/run/run.hpp"
#include "carom/run/run_report.hpp"

namespace carom::python {

namespace py = pybind11;

class PythonSimulation {
 public:
  explicit PythonSimulation(Start start);

  // From arrays: positions and velocities (N, D), box (D), radii and masses (N), all float64,
  // and the types' names with each particle's index into them (N, uint32), shapes checked by the
  // Python layer; names and indices by the library's check_start.
  static PythonSimulation from_arrays(
      const py::array_t<double>& positions, const py::array_t<double>& velocities,
      const py::array_t<double>& box, const py::array_t<double>& radii,
      const py::array_t<double>& masses, std::vector<std::string> type_names,
      const py::array_t<std::uint32_t>& types, Boundary boundary, const Settings& settings);

  // Runs `spec` (Runner::run) with the GIL released; Ctrl-C stops it within milliseconds at a
  // whole instant and raises KeyboardInterrupt (or runs the user's SIGINT handler and goes on).
  // With `collisions`, every collision is logged for collisions(). Returns what the command line
  // would warn of Z, each after its kind ("drift", "correlation": DriftVerdict's warnings), for
  // Python's warnings.
  std::vector<std::pair<std::string, std::string>> run(RunSpec spec, bool collisions);
  // The collisions logged since the last drain, as a structured array (time, i, j).
  py::array collisions();
  // A new simulation (the same settings, time 0) of this one's particles at time() compressed
  // as carom compress does, and the json of its summary; the GIL is released while it works, and
  // Ctrl-C raises KeyboardInterrupt within a stretch of N events, leaving this one whole.
  std::pair<PythonSimulation, std::string> compress(CompressionSpec spec) const;

  const AnySimulation& simulation() const { return runner_.simulation(); }
  AnySimulation& simulation() { return runner_.simulation(); }
  const std::string& source() const { return runner_.start().source; }
  py::array_t<double> box() const;
  // Every particle at time(): (N, D) arrays, copies (the stored states are lazy).
  py::array_t<double> positions() const;
  py::array_t<double> velocities() const;
  py::array_t<std::int32_t> images() const;
  py::array_t<double> radii() const;
  py::array_t<double> masses() const;
  py::array_t<std::uint32_t> types() const;
  std::vector<std::string> type_names() const { return simulation().type_names(); }
  py::array_t<std::uint64_t> wall_collisions() const;
  py::array_t<std::uint64_t> pair_collisions() const;

  // The command line's output at time(): table, csv, or json (with particles, or the summary).
  std::string text(Format format, bool particles = true) const;
  void measure_from(double t);
  void save(const std::string& path) const;

 private:
  Runner runner_;
  std::vector<Event> log_;
};

}  // namespace carom::python
