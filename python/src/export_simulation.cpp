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

}  // namespace

void export_simulation(py::module_& m) {
  using namespace py::literals;
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
             const std::string& engine, std::optional<double> kT, std::uint64_t seed) {
            return PythonSimulation::read(
                path, choice<Boundary>("boundary", boundary), choice<Rule>("rule", rule),
                settings_from("elastic", restitution, tc, engine), kT, seed);
          },
          "path"_a, "boundary"_a, "rule"_a, "restitution"_a, "tc"_a, "engine"_a, "kT"_a, "seed"_a)
      .def_static(
          "init",
          [](int dim, std::uint64_t n, double phi, const std::vector<double>& box, double aspect,
             std::optional<double> radius, double polydispersity, double kT, std::uint64_t seed,
             const std::string& boundary, const std::string& placement, const std::string& rule,
             double restitution, double tc, const std::string& engine) {
            InitRequest request;
            request.dimension = dim;
            InitialOptions& o = request.options;
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
            return PythonSimulation::init(request, settings_from(rule, restitution, tc, engine));
          },
          "dim"_a, "n"_a, "phi"_a, "box"_a, "aspect"_a, "radius"_a, "polydispersity"_a, "kT"_a,
          "seed"_a, "boundary"_a, "placement"_a, "rule"_a, "restitution"_a, "tc"_a, "engine"_a)
      .def_static("resume", &PythonSimulation::resume, "path"_a)
      .def("run", &PythonSimulation::run, "t"_a, "dump"_a, "every"_a, "collisions"_a)
      .def("collisions", &PythonSimulation::collisions)
      .def(
          "compress",
          [](const PythonSimulation& self, std::optional<double> target, double rate,
             double temperature, double jammed_pressure, bool unit_diameter) {
            CompressionSettings settings;
            settings.target = target;
            settings.rate = rate;
            settings.temperature = temperature;
            settings.jammed_pressure = jammed_pressure;
            return self.compress(settings, unit_diameter);
          },
          "phi"_a, "rate"_a, "kT"_a, "jam_pressure"_a, "unit_diameter"_a)
      .def_property_readonly("time", &PythonSimulation::time)
      .def_property_readonly("events", &PythonSimulation::events)
      .def_property_readonly("n", &PythonSimulation::size)
      .def_property_readonly("dim", &PythonSimulation::dimension)
      .def_property_readonly("box", &PythonSimulation::box)
      .def_property_readonly("boundary", &PythonSimulation::boundary)
      .def_property_readonly("rule", &PythonSimulation::rule)
      .def_property_readonly("restitution", &PythonSimulation::restitution)
      .def_property_readonly("tc", &PythonSimulation::tc)
      .def_property_readonly("engine", &PythonSimulation::engine)
      .def_property_readonly("source", &PythonSimulation::source)
      .def_property_readonly("positions", &PythonSimulation::positions)
      .def_property_readonly("images", &PythonSimulation::images)
      .def_property_readonly("velocities", &PythonSimulation::velocities)
      .def_property_readonly("radii", &PythonSimulation::radii)
      .def_property_readonly("masses", &PythonSimulation::masses)
      .def_property_readonly("wall_collisions", &PythonSimulation::wall_collisions)
      .def_property_readonly("pair_collisions", &PythonSimulation::pair_collisions)
      .def("json", &PythonSimulation::json, "particles"_a)
      .def(
          "text",
          [](const PythonSimulation& s, const std::string& format) {
            return s.text(choice<Format>("format", format));
          },
          "format"_a)
      .def("reset_measurement", &PythonSimulation::reset_measurement)
      .def("measure_from", &PythonSimulation::measure_from, "t"_a)
      .def("save", &PythonSimulation::save, "path"_a);
}

}  // namespace carom::python
