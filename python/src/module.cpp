// carom._carom: the compiled half of the carom package (python/carom/ is the other).
#include "carom/version.hpp"
#include "exports.hpp"

PYBIND11_MODULE(_carom, m) {
  m.doc() = "carom's engine (use the carom package, which documents it)";
  m.attr("__version__") = carom::kVersion;
  carom::python::export_errors(m);
  carom::python::export_specs(m);
  carom::python::export_simulation(m);
  carom::python::export_analysis(m);
  carom::python::export_sweep(m);
}
