// carom._carom.Simulation: the binding of PythonSimulation. Names and defaults are the Python
// package's (python/carom/__init__.py), which documents them; options that name a choice take
// the CLI's words ("elastic", "periodic", ...).
#include <fmt/format.h>
#include <pybind11/stl.h>

#include "exports.hpp"
#include "python_simulation.hpp"

namespace carom::python {

namespace {

template <class E>
E choice(const std::string& option, const std::string& name) {
  if (const auto value = from_name<E>(name)) return *value;
  throw std::invalid_argument(
      fmt::format("{} must be {}, got '{}'", option, names_list<E>(), name));
}

// None (left to the file) or a choice.
template <class E>
std::optional<E> choice(const std::string& option, const std::optional<std::string>& name) {
  if (!name) return std::nullopt;
  return choice<E>(option, *name);
}

Settings settings_from(const std::string& rule, double restitution, double tc,
                       const std::string& engine) {
  Settings settings;
  settings.rule = {choice<Rule>("rule", rule), restitution, tc};
  settings.engine = choice<EngineKind>("engine", engine);
  return settings;
}

Placement placement_from(const std::string& name) {
  if (name == "auto") return Placement::automatic;
  if (name == "random") return Placement::random;
  if (name == "lattice") return Placement::lattice;
  throw std::invalid_argument(
      fmt::format("placement must be auto, random or lattice, got '{}'", name));
}

// The library's defaults, which the Python package's signatures show (carom/__init__.py reads
// them from here rather than repeating them).
py::dict defaults() {
  const Settings settings;
  const InitialOptions initial;
  const CompressionSettings compression;
  const StartSpec start;
  py::dict d;
  d["rule"] = std::string(name_of(Rule::elastic));  // the physical rule: Python's default
  d["restitution"] = settings.rule.restitution;
  d["tc"] = settings.rule.elastic_within;
  d["engine"] = std::string(name_of(settings.engine));
  d["seed"] = start.seed;
  d["boundary"] = std::string(name_of(initial.boundary));
  d["kT"] = initial.temperature;
  d["aspect"] = initial.aspect;
  d["polydispersity"] = initial.polydispersity;
  d["dim"] = 2;  // disks
  d["rate"] = compression.rate;
  d["compress_kT"] = compression.temperature;
  d["jam_pressure"] = compression.jammed_pressure;
  d["radius"] = kDefaultRadius;
  d["mass"] = ParticleRecord{}.mass;
  d["placement"] = "auto";
  return d;
}

}  // namespace

void export_simulation(py::module_& m) {
  using namespace py::literals;
  m.attr("defaults") = defaults();
  py::class_<PythonSimulation>(m, "Simulation")
      .def_static(
          "from_arrays",
          [](const py::array_t<double>& positions, const py::array_t<double>& velocities,
             const py::array_t<double>& box, const py::array_t<double>& radii,
             const py::array_t<double>& masses, const std::string& boundary,
             const std::string& rule, double restitution, double tc, const std::string& engine) {
            return PythonSimulation::from_arrays(positions, velocities, box, radii, masses,
                                                 choice<Boundary>("boundary", boundary),
                                                 settings_from(rule, restitution, tc, engine));
          },
          "positions"_a, "velocities"_a, "box"_a, "radii"_a, "masses"_a, "boundary"_a, "rule"_a,
          "restitution"_a, "tc"_a, "engine"_a)
      .def_static(
          "read",
          [](const std::string& path, const std::optional<std::string>& boundary,
             const std::optional<std::string>& rule, double restitution, double tc,
             const std::string& engine, std::optional<double> kT, std::uint64_t seed,
             const std::string& thermostat, std::optional<double> thermostat_every,
             std::optional<double> thermostat_rate, std::optional<double> shear,
             bool velocity_profile) {
            StartSpec spec{path,
                           choice<Boundary>("boundary", boundary),
                           choice<Rule>("rule", rule),
                           restitution,
                           tc,
                           choice<EngineKind>("engine", engine),
                           kT,
                           seed,
                           thermostat_request(choice<ThermostatKind>("thermostat", thermostat), kT,
                                              thermostat_every, thermostat_rate, seed),
                           shear_request(shear, velocity_profile)};
            return PythonSimulation(load_start(spec));
          },
          "path"_a, "boundary"_a, "rule"_a, "restitution"_a, "tc"_a, "engine"_a, "kT"_a, "seed"_a,
          "thermostat"_a, "thermostat_every"_a, "thermostat_rate"_a, "shear"_a,
          "velocity_profile"_a)
      .def_static(
          "init",
          [](int dim, std::uint64_t n, double phi, const std::vector<double>& box, double aspect,
             std::optional<double> radius, double polydispersity, double kT, std::uint64_t seed,
             const std::string& boundary, const std::string& placement, const std::string& rule,
             double restitution, double tc, const std::string& engine,
             const std::string& thermostat, std::optional<double> thermostat_every,
             std::optional<double> thermostat_rate, std::optional<double> shear,
             bool velocity_profile) {
            InitialOptions o;
            o.n = n;
            o.packing_fraction = phi;
            o.box = box;
            o.aspect = aspect;
            o.radius = radius;
            o.polydispersity = polydispersity;
            o.temperature = kT;
            o.seed = seed;
            o.boundary = choice<Boundary>("boundary", boundary);
            o.placement = placement_from(placement);
            try {
              Settings settings = settings_from(rule, restitution, tc, engine);
              settings.thermostat =
                  thermostat_request(choice<ThermostatKind>("thermostat", thermostat), kT,
                                     thermostat_every, thermostat_rate, seed);
              return PythonSimulation(
                  init_start(dim, o, settings, shear_request(shear, velocity_profile)));
            } catch (const InitialError& e) {
              throw std::invalid_argument(e.what());
            }
          },
          "dim"_a, "n"_a, "phi"_a, "box"_a, "aspect"_a, "radius"_a, "polydispersity"_a, "kT"_a,
          "seed"_a, "boundary"_a, "placement"_a, "rule"_a, "restitution"_a, "tc"_a, "engine"_a,
          "thermostat"_a, "thermostat_every"_a, "thermostat_rate"_a, "shear"_a,
          "velocity_profile"_a)
      .def_static(
          "resume", [](const std::string& path) { return PythonSimulation(resume_start(path)); },
          "path"_a)
      .def(
          "run",
          [](PythonSimulation& self, double t, const std::string& dump, double every,
             const std::string& log, double log_every, const std::string& events,
             const std::string& checkpoint, const std::optional<std::string>& checkpoint_every,
             const std::string& summary, bool check, std::uint64_t check_every,
             std::optional<double> equilibrate, bool transport, bool collisions) {
            RunSpec spec;
            spec.end_time = t;
            spec.measure_from = equilibrate;
            spec.dump = dump;
            spec.dump_every = every;
            spec.log = log;
            spec.log_every = log_every;
            spec.events = events;
            spec.checkpoint = checkpoint;
            if (checkpoint_every) spec.checkpoint_every = checkpoint_cadence(*checkpoint_every);
            spec.summary = summary;
            spec.check = check;
            spec.check_every = check_every;
            spec.transport = transport;
            self.run(std::move(spec), collisions);
          },
          "t"_a, "dump"_a, "every"_a, "log"_a, "log_every"_a, "events"_a, "checkpoint"_a,
          "checkpoint_every"_a, "summary"_a, "check"_a, "check_every"_a, "equilibrate"_a,
          "transport"_a, "collisions"_a)
      .def("collisions", &PythonSimulation::collisions)
      .def(
          "compress",
          [](const PythonSimulation& self, std::optional<double> target, double rate,
             double temperature, double jammed_pressure, bool unit_diameter) {
            CompressionSpec spec;
            spec.settings.target = target;
            spec.settings.rate = rate;
            spec.settings.temperature = temperature;
            spec.settings.jammed_pressure = jammed_pressure;
            spec.settings.engine = self.simulation().settings().engine;
            spec.unit_diameter = unit_diameter;
            return self.compress(spec);
          },
          "phi"_a, "rate"_a, "kT"_a, "jam_pressure"_a, "unit_diameter"_a)
      .def_property_readonly("time",
                             [](const PythonSimulation& s) { return s.simulation().time(); })
      .def_property_readonly(
          "events", [](const PythonSimulation& s) { return s.simulation().counts().events; })
      .def_property_readonly("n", [](const PythonSimulation& s) { return s.simulation().size(); })
      .def_property_readonly("dim",
                             [](const PythonSimulation& s) { return s.simulation().dimension(); })
      .def_property_readonly("box", &PythonSimulation::box)
      .def_property_readonly("shear_shift",
                             [](const PythonSimulation& s) { return s.simulation().shear_shift(); })
      .def_property_readonly(
          "boundary",
          [](const PythonSimulation& s) { return std::string(name_of(s.simulation().boundary())); })
      .def_property_readonly("rule",
                             [](const PythonSimulation& s) {
                               return std::string(name_of(s.simulation().settings().rule.rule));
                             })
      .def_property_readonly(
          "restitution",
          [](const PythonSimulation& s) { return s.simulation().settings().rule.restitution; })
      .def_property_readonly(
          "tc",
          [](const PythonSimulation& s) { return s.simulation().settings().rule.elastic_within; })
      .def_property_readonly("engine",
                             [](const PythonSimulation& s) {
                               return std::string(name_of(s.simulation().settings().engine));
                             })
      .def_property_readonly("source", &PythonSimulation::source)
      .def_property_readonly("positions", &PythonSimulation::positions)
      .def_property_readonly("images", &PythonSimulation::images)
      .def_property_readonly("velocities", &PythonSimulation::velocities)
      .def_property_readonly("radii", &PythonSimulation::radii)
      .def_property_readonly("masses", &PythonSimulation::masses)
      .def_property_readonly("wall_collisions", &PythonSimulation::wall_collisions)
      .def_property_readonly("pair_collisions", &PythonSimulation::pair_collisions)
      .def(
          "json",
          [](const PythonSimulation& s, bool particles) { return s.text(Format::json, particles); },
          "particles"_a)
      .def(
          "text",
          [](const PythonSimulation& s, const std::string& format) {
            return s.text(choice<Format>("format", format));
          },
          "format"_a)
      .def("reset_measurement", [](PythonSimulation& s) { s.simulation().reset_measurement(); })
      .def("measure_from", &PythonSimulation::measure_from, "t"_a)
      .def("save", &PythonSimulation::save, "path"_a);
}

}  // namespace carom::python
