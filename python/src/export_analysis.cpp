// carom.analyze: the library's trajectory analysis (carom analyze), as JSON text the Python side
// turns into a dict of numpy arrays.
#include <pybind11/stl.h>

#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "carom/analysis/analysis.hpp"
#include "carom/io/atomic_file.hpp"
#include "carom/run/request.hpp"
#include "exports.hpp"

namespace carom::python {

namespace py = pybind11;

void export_analysis(py::module_& m) {
  m.def(
      "analyze",
      [](const std::string& trajectory, double equilibrate, double bin_width, double r_max,
         double contact_width, const std::optional<std::string>& log,
         const std::optional<std::string>& html) {
        std::string json;
        {
          // Reading and analysing a long trajectory takes a while: other threads may run.
          py::gil_scoped_release release;
          AnalysisOptions options;
          options.from_time = equilibrate;
          options.rdf = {bin_width, r_max};
          options.contact_width = contact_width;
          // What can fail at once does so before the work, as on the command line.
          check_files_apart({{"trajectory", trajectory}, {"log", log.value_or("")}},
                            {{"html", html.value_or("")}});
          std::optional<LogTable> table;
          if (log) table = read_log_table(*log);
          std::optional<AtomicFile> page;
          if (html) page.emplace(*html);
          Analysis analysis = analyze(read_trajectory_frames(trajectory), trajectory, options);
          analysis.log = std::move(table);
          if (page) {
            write_report_html(page->stream(), analysis);
            page->commit();
          }
          std::ostringstream out;
          write_analysis_json(out, analysis);
          json = out.str();
        }
        return json;
      },
      py::arg("trajectory"), py::arg("equilibrate"), py::arg("bin_width"), py::arg("r_max"),
      py::arg("contact_width"), py::arg("log"), py::arg("html"));
}

}  // namespace carom::python
