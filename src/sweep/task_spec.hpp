// What a task's settings ask for, as the library's own descriptions (InitialOptions, StartSpec,
// RunSpec, CompressionSpec) and as the carom commands that do the same alone.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "carom/engine/initial.hpp"
#include "carom/run/compress_run.hpp"
#include "carom/run/run.hpp"
#include "carom/run/start.hpp"
#include "carom/sweep/sweep.hpp"

namespace carom::sweep {

struct TaskSpec {
  TaskKind kind = TaskKind::run;
  std::optional<std::string> start_file;  // `file`, from the plan's folder; else carom init's:
  int dimension = 2;
  InitialOptions initial;
  // The task's start: carom init's (start.txt in the task's folder), or the start file.
  std::string start_path;
  // A run: its start read as carom run reads it (the path is the start file), then the run,
  // whose files are in the task's folder.
  StartSpec start;
  RunSpec run;
  std::string checkpoint_every = "600s";  // the run's cadence, as carom run takes it
  // A compression, of the start read in compress_boundary: the task's, or the run's start's when
  // the run starts from the start compressed (compresses_start; the run's start is the packing).
  CompressionSpec compress;
  bool compresses_start = false;
  std::optional<Boundary> compress_boundary;
  // The commands: carom init's (none with `file`), then carom run's or compress's, or compress's
  // and then run's.
  std::vector<std::string> commands;
  // Why the task's swept seed seeds nothing its run keeps (the tasks of its state point would be
  // one run), or nullopt.
  std::optional<std::string> idle_seed;
};

// The task's description with its files in `folder` (and its start `file` at `start_file`, if
// given, rather than in the plan's folder). Throws PlanError, naming the plan's line, for options
// the library refuses (a packing fraction above close packing, a restitution of 2, a shear between
// walls), checked as each command would before running.
TaskSpec task_spec(const SweepPlan& plan, const SweepTask& task, const std::string& folder,
                   const std::optional<std::string>& start_file = std::nullopt);

// The measures of the plan's tasks, in results.csv's order (what measure_names returns, worked out
// once, from every task, when the plan is read).
std::vector<std::string> measures_of(const SweepPlan& plan);

// A PlanError for `setting` of `task`: "PLAN:LINE: [SECTION] KEY = VALUE (task NAME): WHY".
PlanError setting_error(const SweepPlan& plan, const SweepTask* task, const PlanSetting& setting,
                        std::string_view section, const std::string& why);

// The value as the plan wrote it (a number in its shortest exact form).
std::string value_text(const PlanValue& value);

}  // namespace carom::sweep
