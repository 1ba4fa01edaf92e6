#include "python_simulation.hpp"

#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "carom/checkpoint.hpp"
#include "carom/classic_input.hpp"
#include "carom/formats.hpp"
#include "carom/gsd.hpp"
#include "carom/trajectory.hpp"

namespace carom::python {

namespace {

// Python runs its SIGINT handler only when the main thread runs Python code, which it does not
// while the engine works. During a run a handler of our own records the signal in the
// Simulation's stop flag (the library honours it within milliseconds, events or not); the
// previous handler is put back after, and given the signal, so that Python does with it what it
// would have done (raise KeyboardInterrupt, or call the user's handler).
std::atomic<int> interrupt_signal{0};

extern "C" void record_interrupt(int signal) {
  interrupt_signal.store(signal);
}

class InterruptHandler {
 public:
  explicit InterruptHandler(bool install) : installed_(install) {
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

 private:
  bool installed_;
  struct sigaction previous_ = {};
};

// Logs every collision of the run it observes.
template <std::size_t D>
class CollisionLogger final : public Observer<D> {
 public:
  explicit CollisionLogger(std::vector<LoggedCollision>& log)
      : Observer<D>(Trigger::each_event()), log_(log) {}
  void observe(const Simulation<D>& simulation) override {
    const Event& e = simulation.last_event();
    log_.push_back({e.time, e.first, e.partner});
  }

 private:
  std::vector<LoggedCollision>& log_;
};

// A system of dimension D from float64 arrays whose shapes the Python layer has checked.
template <std::size_t D>
System<D> system_from(const py::array_t<double>& positions, const py::array_t<double>& velocities,
                      const py::array_t<double>& box, const py::array_t<double>& radii,
                      const py::array_t<double>& masses, Boundary boundary) {
  const auto n = static_cast<std::size_t>(positions.shape(0));
  const auto p = positions.unchecked<2>();
  const auto v = velocities.unchecked<2>();
  const auto b = box.unchecked<1>();
  const auto r = radii.unchecked<1>();
  const auto m = masses.unchecked<1>();
  System<D> system;
  system.box.boundary = boundary;
  for (std::size_t k = 0; k < D; ++k) system.box.size[k] = b(k);
  system.particles.reserve(n);
  system.records.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    Particle<D> particle;
    for (std::size_t k = 0; k < D; ++k) {
      particle.position[k] = p(i, k);
      particle.velocity[k] = v(i, k);
    }
    particle.radius = r(i);
    system.add(particle, m(i));
  }
  check_start(system);
  return system;
}

void require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument(message);
}

}  // namespace

PythonSimulation::PythonSimulation(AnySimulation simulation, std::string source)
    : simulation_(std::move(simulation)), source_(std::move(source)) {}

PythonSimulation PythonSimulation::from_arrays(const py::array_t<double>& positions,
                                               const py::array_t<double>& velocities,
                                               const py::array_t<double>& box,
                                               const py::array_t<double>& radii,
                                               const py::array_t<double>& masses, Boundary boundary,
                                               const Settings& settings) {
  require(positions.ndim() == 2 && (positions.shape(1) == 2 || positions.shape(1) == 3),
          "positions must be an (N, 2) or (N, 3) array");
  const auto n = positions.shape(0), d = positions.shape(1);
  require(velocities.ndim() == 2 && velocities.shape(0) == n && velocities.shape(1) == d,
          fmt::format("velocities must have the shape of positions, ({}, {})", n, d));
  require(box.ndim() == 1 && box.shape(0) == d, fmt::format("box must hold {} sides", d));
  require(radii.ndim() == 1 && radii.shape(0) == n, fmt::format("radii must hold {} values", n));
  require(masses.ndim() == 1 && masses.shape(0) == n, fmt::format("masses must hold {} values", n));
  if (d == 2) {
    return {AnySimulation(std::in_place_type<Simulation<2>>,
                          system_from<2>(positions, velocities, box, radii, masses, boundary),
                          settings),
            "(arrays)"};
  }
  return {
      AnySimulation(std::in_place_type<Simulation<3>>,
                    system_from<3>(positions, velocities, box, radii, masses, boundary), settings),
      "(arrays)"};
}

PythonSimulation PythonSimulation::read(const std::string& path, std::optional<Boundary> boundary,
                                        std::optional<Rule> rule, Settings settings,
                                        std::optional<double> temperature, std::uint64_t seed) {
  if (rule) settings.rule.rule = *rule;
  check_settings(settings);
  return std::visit(
      [&](auto&& input) {
        using System = std::remove_cvref_t<decltype(input.system)>;
        settings.rule.rule = rule.value_or(
            default_rule(input.record, input.system.box.boundary, settings.rule.restitution));
        if (temperature) draw_velocities(input.system, *temperature, seed);
        return PythonSimulation(AnySimulation(std::in_place_type<Simulation<System::dimension>>,
                                              std::move(input.system), settings),
                                path);
      },
      read_any_start_file(path, boundary));
}

PythonSimulation PythonSimulation::init(const InitRequest& request, const Settings& settings) {
  check_settings(settings);
  try {
    if (request.dimension == 3) {
      return {AnySimulation(std::in_place_type<Simulation<3>>, make_initial<3>(request.options),
                            settings),
              "(carom.init)"};
    }
    require(request.dimension == 2, "dim must be 2 (disks) or 3 (spheres)");
    return {AnySimulation(std::in_place_type<Simulation<2>>, make_initial<2>(request.options),
                          settings),
            "(carom.init)"};
  } catch (const InitialError& e) {
    throw std::invalid_argument(e.what());
  }
}

PythonSimulation PythonSimulation::resume(const std::string& path) {
  std::ifstream file = open_input(path);
  return std::visit(
      [&](const auto& checkpoint) {
        using System = std::remove_cvref_t<decltype(checkpoint.system)>;
        return PythonSimulation(
            AnySimulation(std::in_place_type<Simulation<System::dimension>>, checkpoint),
            checkpoint.source);
      },
      read_checkpoint(file, path));
}

void PythonSimulation::open_dump(const std::string& path, double every) {
  require(every > 0.0 && std::isfinite(every), "dump needs every > 0: the time between frames");
  auto dump = std::make_unique<Dump>();
  dump->path = path;
  dump->every = every;
  std::visit(
      [&](auto& simulation) {
        constexpr std::size_t D = std::remove_reference_t<decltype(simulation.state())>::dimension;
        auto format = trajectory_format_for<D>(path);  // refuses an unknown ending first
        // The file the open trajectory writes to is closed first, so that naming it again (with
        // another period) starts it anew; any other file is opened while that one stays intact.
        if (dump_ && dump_->path == path) close_dump();
        dump->file.open(path, std::ios::binary | std::ios::trunc);
        require(dump->file.is_open(), fmt::format("cannot write '{}'", path));
        close_dump();
        auto writer = std::make_shared<FrameWriter<D>>(dump->file, std::move(format), every);
        dump->writer = writer.get();
        // A new file: its first frame is now, when now is on its grid.
        simulation.add_observer(std::move(writer),
                                std::remove_reference_t<decltype(simulation)>::FirstLook::now);
      },
      simulation_);
  dump_ = std::move(dump);
}

void PythonSimulation::close_dump() {
  if (!dump_) return;
  std::visit(
      [&](auto& simulation) {
        constexpr std::size_t D = std::remove_reference_t<decltype(simulation.state())>::dimension;
        simulation.remove_observer(static_cast<const Observer<D>*>(dump_->writer));
      },
      simulation_);
  dump_.reset();
}

void PythonSimulation::run(double t, const std::optional<std::string>& dump, double every,
                           bool collisions) {
  std::visit([&](const auto& simulation) { simulation.check_target(t); }, simulation_);
  if (!dump) {
    close_dump();
  } else if (!dump_ || dump_->path != *dump || dump_->every != every) {
    open_dump(*dump, every);  // checks and opens the new file, then lets the old one go
  }
  std::visit(
      [&](auto& simulation) {
        constexpr std::size_t D = std::remove_reference_t<decltype(simulation.state())>::dimension;
        if (collisions && !logger_) {
          auto logger = std::make_shared<CollisionLogger<D>>(log_);
          logger_ = logger.get();
          simulation.add_observer(std::move(logger));
        } else if (!collisions && logger_) {
          simulation.remove_observer(static_cast<const Observer<D>*>(logger_));
          logger_ = nullptr;
        }
      },
      simulation_);
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t events_before = events();
  // The wall time and the events of this run, however it ends.
  const auto account = [&] {
    wall_seconds_ +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    events_run_ += events() - events_before;
  };
  // Only the main thread sees SIGINT in Python; a run in another thread is not interrupted.
  const bool main_thread = py::module_::import("threading")
                               .attr("current_thread")()
                               .is(py::module_::import("threading").attr("main_thread")());
  for (;;) {
    RunStatus status = RunStatus::reached;
    try {
      const InterruptHandler handler(main_thread);
      py::gil_scoped_release release;
      status = std::visit(
          [&](auto& simulation) {
            simulation.set_stop_flag(main_thread ? &interrupt_signal : nullptr);
            const RunStatus s = simulation.run_until(t);
            simulation.set_stop_flag(nullptr);
            return s;
          },
          simulation_);
    } catch (...) {
      std::visit([](auto& simulation) { simulation.set_stop_flag(nullptr); }, simulation_);
      account();
      throw;
    }
    if (status == RunStatus::reached) break;
    // Stopped by SIGINT: Python's own handler (back in place) gets it now.
    std::raise(SIGINT);
    if (PyErr_CheckSignals() != 0) {
      account();
      throw py::error_already_set();
    }
  }
  account();
}

std::pair<PythonSimulation, py::dict> PythonSimulation::compress(
    const CompressionSettings& settings, bool unit_diameter) const {
  return std::visit(
      [&](const auto& simulation) -> std::pair<PythonSimulation, py::dict> {
        using Sim = std::remove_cvref_t<decltype(simulation)>;
        constexpr std::size_t D = std::remove_cvref_t<decltype(simulation.state())>::dimension;
        System<D> start = simulation.state();
        start.particles = simulation.snapshot();
        for (Particle<D>& p : start.particles) p.time = 0.0;
        start.epoch = 0.0;
        Compression<D> compression(std::move(start), settings);
        const bool main_thread = py::module_::import("threading")
                                     .attr("current_thread")()
                                     .is(py::module_::import("threading").attr("main_thread")());
        while (compression.status() == CompressionStatus::running) {
          {
            const InterruptHandler handler(main_thread);
            py::gil_scoped_release release;
            compression.run(compression.system().size());
          }
          if (main_thread && interrupt_signal.load() != 0) {
            std::raise(SIGINT);
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
          }
        }
        py::dict summary;
        summary["status"] =
            compression.status() == CompressionStatus::jammed ? "jammed" : "reached_target";
        summary["packing_fraction"] = compression.packing_fraction();
        summary["compressibility_factor"] = compression.compressibility_factor();
        summary["rate"] = settings.rate;
        summary["time"] = compression.time();
        summary["events"] = compression.events();
        System<D> packing = compression.system();
        if (unit_diameter) scale_lengths(packing, 1.0 / mean_diameter(packing));
        summary["mean_diameter"] = mean_diameter(packing);
        summary["unit_diameter"] = unit_diameter;
        return {PythonSimulation(AnySimulation(std::in_place_type<Sim>, std::move(packing),
                                               simulation.settings()),
                                 source_),
                summary};
      },
      simulation_);
}

py::array PythonSimulation::collisions() {
  // A structured array: time (float64), i and j (int64; j < 0 is a wall label).
  py::list fields;
  fields.append(py::make_tuple("time", "<f8"));
  fields.append(py::make_tuple("i", "<i8"));
  fields.append(py::make_tuple("j", "<i8"));
  const py::dtype dtype = py::dtype::from_args(fields);
  py::array out(dtype, std::vector<py::ssize_t>{static_cast<py::ssize_t>(log_.size())});
  static_assert(sizeof(LoggedCollision) == 24, "the dtype's 8 + 8 + 8 bytes, unpadded");
  if (!log_.empty()) {
    std::memcpy(out.mutable_data(), log_.data(), log_.size() * sizeof(LoggedCollision));
  }
  log_.clear();
  return out;
}

double PythonSimulation::time() const {
  return std::visit([](const auto& s) { return s.time(); }, simulation_);
}
std::uint64_t PythonSimulation::events() const {
  return std::visit([](const auto& s) { return s.counts().events; }, simulation_);
}
std::size_t PythonSimulation::size() const {
  return std::visit([](const auto& s) { return s.state().size(); }, simulation_);
}
int PythonSimulation::dimension() const {
  return simulation_.index() == 0 ? 2 : 3;
}

py::array_t<double> PythonSimulation::box() const {
  return std::visit(
      [](const auto& s) {
        const auto& size = s.state().box.size;
        py::array_t<double> out(static_cast<py::ssize_t>(size.c.size()));
        std::copy(size.c.begin(), size.c.end(), out.mutable_data());
        return out;
      },
      simulation_);
}

std::string PythonSimulation::boundary() const {
  return std::visit([](const auto& s) { return std::string(name_of(s.state().box.boundary)); },
                    simulation_);
}
std::string PythonSimulation::rule() const {
  return std::visit([](const auto& s) { return std::string(name_of(s.settings().rule.rule)); },
                    simulation_);
}
double PythonSimulation::restitution() const {
  return std::visit([](const auto& s) { return s.settings().rule.restitution; }, simulation_);
}
double PythonSimulation::tc() const {
  return std::visit([](const auto& s) { return s.settings().rule.elastic_within; }, simulation_);
}
std::string PythonSimulation::engine() const {
  return std::visit([](const auto& s) { return std::string(name_of(s.settings().engine)); },
                    simulation_);
}

namespace {

// An (N, D) array of one vector of every particle at the simulation's time.
template <class Pick>
py::array_t<double> per_particle_vectors(const AnySimulation& any, Pick pick) {
  return std::visit(
      [&](const auto& s) {
        const auto& system = s.state();
        constexpr std::size_t D = std::remove_cvref_t<decltype(system)>::dimension;
        py::array_t<double> out(
            {static_cast<py::ssize_t>(system.size()), static_cast<py::ssize_t>(D)});
        double* data = out.mutable_data();
        const double now_stored = s.stored_time();
        for (std::size_t i = 0; i < system.size(); ++i) {
          // Each particle brought to the simulation's time on its own: no copy of the state.
          const auto now = synchronised(system.particles[i], system.box, now_stored);
          const auto& v = pick(now);
          for (std::size_t k = 0; k < D; ++k) data[i * D + k] = v[k];
        }
        return out;
      },
      any);
}

// An (N,) array of one number per particle.
template <class T, class Pick>
py::array_t<T> per_particle(const AnySimulation& any, Pick pick) {
  return std::visit(
      [&](const auto& s) {
        const auto& system = s.state();
        py::array_t<T> out(static_cast<py::ssize_t>(system.size()));
        T* data = out.mutable_data();
        for (std::size_t i = 0; i < system.size(); ++i) {
          data[i] = pick(system.particles[i], system.records[i]);
        }
        return out;
      },
      any);
}

}  // namespace

py::array_t<double> PythonSimulation::positions() const {
  return per_particle_vectors(
      simulation_, [](const auto& p) -> const auto& { return p.position; });
}
py::array_t<double> PythonSimulation::velocities() const {
  return per_particle_vectors(
      simulation_, [](const auto& p) -> const auto& { return p.velocity; });
}
py::array_t<std::int32_t> PythonSimulation::images() const {
  return std::visit(
      [&](const auto& s) {
        const auto& system = s.state();
        constexpr std::size_t D = std::remove_cvref_t<decltype(system)>::dimension;
        py::array_t<std::int32_t> out(
            {static_cast<py::ssize_t>(system.size()), static_cast<py::ssize_t>(D)});
        std::int32_t* data = out.mutable_data();
        const double now_stored = s.stored_time();
        for (std::size_t i = 0; i < system.size(); ++i) {
          // The flags as the particle's flight to now wraps it, as a trajectory frame has them.
          std::array<std::int32_t, 3> image = system.records[i].image;
          synchronised(system.particles[i], system.box, now_stored, image);
          for (std::size_t k = 0; k < D; ++k) data[i * D + k] = image[k];
        }
        return out;
      },
      simulation_);
}

py::array_t<double> PythonSimulation::radii() const {
  return per_particle<double>(simulation_, [](const auto& p, const auto&) { return p.radius; });
}
py::array_t<double> PythonSimulation::masses() const {
  return per_particle<double>(simulation_, [](const auto&, const auto& r) { return r.mass; });
}
py::array_t<std::uint64_t> PythonSimulation::wall_collisions() const {
  return per_particle<std::uint64_t>(simulation_,
                                     [](const auto&, const auto& r) { return r.wall_collisions; });
}
py::array_t<std::uint64_t> PythonSimulation::pair_collisions() const {
  return per_particle<std::uint64_t>(simulation_,
                                     [](const auto&, const auto& r) { return r.pair_collisions; });
}

RunReport PythonSimulation::report() const {
  RunReport report;
  report.input = source_;
  report.wall_seconds = wall_seconds_;
  report.events = events_run_;
  return report;
}

std::string PythonSimulation::json(bool particles) const {
  std::ostringstream out;
  std::visit([&](const auto& s) { write_json(out, s, report(), particles); }, simulation_);
  return out.str();
}

std::string PythonSimulation::text(Format format) const {
  std::ostringstream out;
  std::visit(
      [&](const auto& s) {
        if (format == Format::table) write_table(out, s);
        if (format == Format::csv) write_csv(out, s);
        if (format == Format::json) write_json(out, s, report());
      },
      simulation_);
  return out.str();
}

void PythonSimulation::reset_measurement() {
  std::visit([](auto& s) { s.reset_measurement(); }, simulation_);
}

void PythonSimulation::measure_from(double t) {
  require(t >= 0.0 && std::isfinite(t), fmt::format("measure_from needs a time >= 0, got {}", t));
  std::visit([&](auto& s) { s.measure_from(t); }, simulation_);
}

void PythonSimulation::save(const std::string& path) const {
  std::visit([&](const auto& s) { save_checkpoint(path, s, source_); }, simulation_);
}

}  // namespace carom::python
