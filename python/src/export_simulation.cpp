// carom._carom.Simulation: the binding of PythonSimulation, made from the requests of
// export_specs.cpp. The Python package (python/carom/) documents it; options that name a choice
// take the CLI's words ("elastic", "periodic", ...), from the library's tables.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include "exports.hpp"
#include "python_simulation.hpp"
#include "specs.hpp"

namespace carom::python {

namespace {

Settings settings_from(py::handle rule, double restitution, double tc, py::handle engine,
                       py::handle sampler, double chain_length, std::uint64_t seed) {
  Settings settings;
  settings.rule = {choice<Rule>("rule", rule), restitution, tc};
  settings.engine = choice<EngineKind>("engine", engine);
  settings.sampler = {choice<SamplerKind>("sampler", sampler), chain_length, seed};
  return settings;
}

// The library's defaults, which the Python package's signatures show (carom/__init__.py reads
// them from here rather than repeating them).
py::dict defaults() {
  const Settings settings;
  const InitialOptions initial;
  const CompressionSettings compression;
  const StartSpec start;
  const InitSpec init;
  py::dict d;
  d["rule"] = std::string(name_of(init.rule));
  d["restitution"] = settings.rule.restitution;
  d["tc"] = settings.rule.elastic_within;
  d["engine"] = std::string(name_of(settings.engine));
  d["sampler"] = std::string(name_of(settings.sampler.kind));
  d["chain_length"] = settings.sampler.chain_length;
  d["seed"] = start.seed;
  d["boundary"] = std::string(name_of(initial.boundary));
  d["kT"] = initial.temperature;
  d["aspect"] = initial.aspect;
  d["polydispersity"] = initial.polydispersity;
  d["dim"] = init.dimension;
  d["rate"] = compression.rate;
  d["compress_kT"] = compression.temperature;
  d["jam_pressure"] = compression.jammed_pressure;
  d["radius"] = kDefaultRadius;
  d["mass"] = ParticleRecord{}.mass;
  d["placement"] = std::string(name_of(initial.placement));
  return d;
}

template <class E>
py::list names() {
  py::list list;
  for (const auto& [name, value] : EnumNames<E>::table) list.append(std::string(name));
  return list;
}

// The names of each choice, the default first: the library's tables (core/names.hpp).
py::dict choices() {
  py::dict d;
  d["rule"] = names<Rule>();
  d["sampler"] = names<SamplerKind>();
  d["boundary"] = names<Boundary>();
  d["engine"] = names<EngineKind>();
  d["thermostat"] = names<ThermostatKind>();
  d["placement"] = names<Placement>();
  d["format"] = names<Format>();
  return d;
}

const Settings& settings_of(const PythonSimulation& s) { return s.simulation().settings(); }

bool chains(const PythonSimulation& s) {
  return settings_of(s).sampler.kind == SamplerKind::ecmc;
}

// A setting of dynamics, or None under event chains.
template <class T>
py::object of_dynamics(const PythonSimulation& s, T value) {
  return chains(s) ? py::object(py::none()) : py::cast(std::move(value));
}

}  // namespace

void export_simulation(py::module_& m) {
  using namespace py::literals;
  m.attr("defaults") = defaults();
  m.attr("names") = choices();
  py::class_<PythonSimulation>(m, "Simulation")
      .def_static(
          "from_arrays",
          [](const py::array_t<double>& positions, const py::array_t<double>& velocities,
             const py::array_t<double>& box, const py::array_t<double>& radii,
             const py::array_t<double>& masses, std::vector<std::string> types,
             const py::array_t<std::uint32_t>& type_index, py::handle boundary, py::handle rule,
             double restitution, double tc, py::handle engine, py::handle sampler,
             double chain_length, std::uint64_t seed) {
            return PythonSimulation::from_arrays(
                positions, velocities, box, radii, masses, std::move(types), type_index,
                choice<Boundary>("boundary", boundary),
                settings_from(rule, restitution, tc, engine, sampler, chain_length, seed));
          },
          "positions"_a, "velocities"_a, "box"_a, "radii"_a, "masses"_a, "types"_a, "typeid"_a,
          "boundary"_a, "rule"_a, "restitution"_a, "tc"_a, "engine"_a, "sampler"_a,
          "chain_length"_a, "seed"_a)
      .def_static("read", [](const StartSpec& spec) { return PythonSimulation(load_start(spec)); })
      .def_static("init",
                  [](const InitStart& init) {
                    try {
                      return PythonSimulation(init_start(init.spec.dimension, init.spec.options,
                                                         init.settings, init.shear));
                    } catch (const InitialError& e) {
                      throw std::invalid_argument(e.what());
                    }
                  })
      .def_static(
          "resume", [](const std::string& path) { return PythonSimulation(resume_start(path)); },
          "path"_a)
      .def("run", &PythonSimulation::run, "spec"_a, "collisions"_a)
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
      // What only dynamics has is None under event chains, as in the summary.
      .def_property_readonly("rule",
                             [](const PythonSimulation& s) {
                               return of_dynamics(s, std::string(name_of(
                                                         settings_of(s).rule.rule)));
                             })
      .def_property_readonly(
          "restitution",
          [](const PythonSimulation& s) { return of_dynamics(s, settings_of(s).rule.restitution); })
      .def_property_readonly(
          "tc",
          [](const PythonSimulation& s) {
            return of_dynamics(s, settings_of(s).rule.elastic_within);
          })
      .def_property_readonly("engine",
                             [](const PythonSimulation& s) {
                               return of_dynamics(s, std::string(name_of(settings_of(s).engine)));
                             })
      .def_property_readonly(
          "sampler",
          [](const PythonSimulation& s) {
            return std::string(name_of(settings_of(s).sampler.kind));
          })
      .def_property_readonly("chain_length",
                             [](const PythonSimulation& s) -> py::object {
                               if (!chains(s)) return py::none();
                               return py::float_(settings_of(s).sampler.chain_length);
                             })
      .def_property_readonly("source", &PythonSimulation::source)
      .def_property_readonly("positions", &PythonSimulation::positions)
      .def_property_readonly("images", &PythonSimulation::images)
      .def_property_readonly("velocities", &PythonSimulation::velocities)
      .def_property_readonly("radii", &PythonSimulation::radii)
      .def_property_readonly("masses", &PythonSimulation::masses)
      .def_property_readonly("typeid", &PythonSimulation::types)
      .def_property_readonly("types", &PythonSimulation::type_names)
      .def_property_readonly("wall_collisions", &PythonSimulation::wall_collisions)
      .def_property_readonly("pair_collisions", &PythonSimulation::pair_collisions)
      .def(
          "json",
          [](const PythonSimulation& s, bool particles) { return s.text(Format::json, particles); },
          "particles"_a)
      .def(
          "text",
          [](const PythonSimulation& s, py::handle format) {
            return s.text(choice<Format>("format", format));
          },
          "format"_a)
      .def("reset_measurement", [](PythonSimulation& s) { s.simulation().reset_measurement(); })
      .def("measure_from", &PythonSimulation::measure_from, "t"_a)
      .def("save", &PythonSimulation::save, "path"_a);
}

}  // namespace carom::python
