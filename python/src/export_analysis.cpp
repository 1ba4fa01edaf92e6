// carom.analyze: the library's trajectory analysis (carom analyze), as JSON text the Python side
// turns into a dict of numpy arrays.
#include <pybind11/stl.h>

#include <optional>
#include <sstream>
#include <string>

#include "carom/analysis/analysis_spec.hpp"
#include "exports.hpp"

namespace carom::python {

namespace py = pybind11;

void export_analysis(py::module_& m) {
  m.def(
      "analyze",
      [](const std::string& trajectory, double equilibrate, double bin_width, double r_max,
         double contact_width, double k_max, double fs_k, double order_cutoff, bool com,
         const std::optional<std::string>& log, const std::optional<std::string>& html,
         const std::optional<std::string>& only) {
        std::string json;
        AnalysisSelection selection;
        if (only) selection = parse_analysis_selection(*only);  // ValueError, with the GIL
        {
          // Reading and analysing a long trajectory takes a while: other threads may run.
          py::gil_scoped_release release;
          AnalysisSpec spec;
          spec.trajectory = {"trajectory", trajectory};
          spec.log = {"log", log.value_or("")};
          spec.html = {"html", html.value_or("")};
          spec.options.from_time = equilibrate;
          spec.options.rdf = {bin_width, r_max};
          spec.options.contact_width = contact_width;
          spec.options.k_max = k_max;
          spec.options.fs_k = fs_k;
          spec.options.bond_order.cutoff = order_cutoff;
          spec.options.from_centre_of_mass = com;
          spec.options.only = selection;
          std::ostringstream out;
          write_analysis_json(out, analyze(spec));
          json = out.str();
        }
        return json;
      },
      py::arg("trajectory"), py::arg("equilibrate"), py::arg("bin_width"), py::arg("r_max"),
      py::arg("contact_width"), py::arg("k_max"), py::arg("fs_k"), py::arg("order_cutoff"),
      py::arg("com"), py::arg("log"), py::arg("html"), py::arg("only"));
}

}  // namespace carom::python
