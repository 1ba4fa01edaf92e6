#include "carom/analysis/analysis_spec.hpp"

#include <optional>
#include <utility>

#include "carom/io/atomic_file.hpp"

namespace carom {

Analysis analyze(const AnalysisSpec& spec) {
  try {
    check_selection(spec.options);  // before a long trajectory is read
  } catch (const std::invalid_argument& e) {
    throw AnalysisError(e.what());
  }
  check_files_apart({spec.trajectory, spec.log}, {spec.json, spec.html});
  std::optional<LogTable> log;
  if (!spec.log.path.empty()) log = read_log_table(spec.log.path);
  // Opened before the work, so that an output that cannot be made fails at once.
  std::optional<AtomicFile> json, page;
  if (!spec.json.path.empty()) json.emplace(spec.json.path);
  if (!spec.html.path.empty()) page.emplace(spec.html.path);
  Analysis analysis;
  try {
    analysis =
        analyze(read_trajectory_frames(spec.trajectory.path), spec.trajectory.path, spec.options);
  } catch (const std::invalid_argument& e) {
    throw AnalysisError(e.what());
  }
  analysis.log = std::move(log);
  if (json) {
    write_analysis_json(json->stream(), analysis);
    json->commit();
  }
  if (page) {
    write_report_html(page->stream(), analysis);
    page->commit();
  }
  return analysis;
}

}  // namespace carom
