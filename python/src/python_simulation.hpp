// The Simulation the Python module exposes: a carom::AnySimulation (the dimension chosen once,
// when it is made) with what a Python session adds around it: the file it began from, a
// trajectory kept open from one run() to the next, and a collision log drained after each run.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "carom/compression.hpp"
#include "carom/formats.hpp"
#include "carom/initial.hpp"
#include "carom/simulation.hpp"

namespace carom::python {

namespace py = pybind11;

// One logged collision: time, the particle, and its partner (a particle, or a wall label < 0).
struct LoggedCollision {
  double time;
  std::int64_t i;
  std::int64_t j;
};

// The options carom init takes (the CLI's names), and the run's settings.
struct InitRequest {
  int dimension = 2;
  InitialOptions options;
};

class PythonSimulation {
 public:
  PythonSimulation(AnySimulation simulation, std::string source);

  // From arrays: positions and velocities (N, D), box (D), radii and masses (N), all float64.
  static PythonSimulation from_arrays(const py::array_t<double>& positions,
                                      const py::array_t<double>& velocities,
                                      const py::array_t<double>& box,
                                      const py::array_t<double>& radii,
                                      const py::array_t<double>& masses, Boundary boundary,
                                      const Settings& settings);
  // From a start file: the boundary and rule asked for, else the file's (default_rule);
  // `settings`' own rule is not used. With a temperature, new velocities (draw_velocities).
  static PythonSimulation read(const std::string& path, std::optional<Boundary> boundary,
                               std::optional<Rule> rule, Settings settings,
                               std::optional<double> temperature, std::uint64_t seed);
  static PythonSimulation init(const InitRequest& request, const Settings& settings);
  static PythonSimulation resume(const std::string& path);

  // Runs to time t with the GIL released; Ctrl-C stops it within milliseconds at a whole
  // instant and raises KeyboardInterrupt (or runs the user's SIGINT handler and goes on). With
  // `dump`, frames go to that file every `every` (kept open while the next run names the same
  // file and period, so pieces give one file); with `collisions`, every collision is logged.
  void run(double t, const std::optional<std::string>& dump, double every, bool collisions);
  // The collisions logged since the last drain, as a structured array (time, i, j).
  py::array collisions();
  // A new simulation (the same settings, time 0) of this one's particles at time() compressed
  // as carom compress does, and its summary; the GIL is released while it works, and
  // Ctrl-C raises KeyboardInterrupt within a stretch of N events, leaving this one whole.
  // With `unit_diameter`, the packing rescaled to a mean diameter of 1 (scale_lengths).
  std::pair<PythonSimulation, py::dict> compress(const CompressionSettings& settings,
                                                 bool unit_diameter) const;

  double time() const;
  std::uint64_t events() const;
  std::size_t size() const;
  int dimension() const;
  py::array_t<double> box() const;
  std::string boundary() const;
  std::string rule() const;
  double restitution() const;
  double tc() const;
  std::string engine() const;
  const std::string& source() const { return source_; }
  // Every particle at time(): (N, D) arrays, copies (the stored states are lazy).
  py::array_t<double> positions() const;
  py::array_t<double> velocities() const;
  // Image flags at the simulation's time, (N, D) int32: the unwrapped position is the position
  // plus image times the box (always 0 with walls).
  py::array_t<std::int32_t> images() const;
  py::array_t<double> radii() const;
  py::array_t<double> masses() const;
  py::array_t<std::uint64_t> wall_collisions() const;
  py::array_t<std::uint64_t> pair_collisions() const;

  // The json the CLI writes (--summary without particles; --format json with them).
  std::string json(bool particles) const;
  // The CLI's table or csv output at time().
  std::string text(Format format) const;
  void reset_measurement();
  void measure_from(double t);
  void save(const std::string& path) const;

 private:
  struct Dump {
    std::string path;
    double every = 0.0;
    std::ofstream file;
    const void* writer = nullptr;  // the FrameWriter<D> observing the simulation
  };
  void open_dump(const std::string& path, double every);
  void close_dump();

  AnySimulation simulation_;
  std::string source_;
  RunReport report() const;  // what the json output says of the runs so far

  double wall_seconds_ = 0.0;     // in run(), over this object's life
  std::uint64_t events_run_ = 0;  // the events of that time
  std::unique_ptr<Dump> dump_;
  std::vector<LoggedCollision> log_;
  const void* logger_ = nullptr;  // the collision logger observing the simulation, if any
};

}  // namespace carom::python
