// One task of a sweep in its folder: what carom init and carom run (or compress) would do alone,
// resumed from what an earlier attempt left.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "carom/atomic_file.hpp"
#include "carom/compress_run.hpp"
#include "carom/formats.hpp"
#include "carom/run.hpp"
#include "carom/start.hpp"
#include "carom/sweep.hpp"
#include "json_text.hpp"
#include "sweep/task_spec.hpp"

namespace carom {

namespace {

namespace fs = std::filesystem;
constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_text(const fs::path& path, const std::string& text) {
  AtomicFile file(path.string());
  file.stream() << text;
  file.commit();
}

std::string commands_text(const sweep::TaskSpec& spec) {
  std::string text;
  for (const std::string& command : spec.commands) text += command + '\n';
  return text;
}

// The named columns of the last row of a run's time series (its running means and errors).
double last_logged(const fs::path& log, const std::string& column) {
  std::ifstream in(log);
  std::string header, line, last;
  if (!std::getline(in, header)) return kNotMeasured;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  std::vector<std::string> names, fields;
  std::stringstream h(header), l(last);
  for (std::string field; std::getline(h, field, ',');) names.push_back(field);
  for (std::string field; std::getline(l, field, ',');) fields.push_back(field);
  for (std::size_t i = 0; i < names.size() && i < fields.size(); ++i) {
    if (names[i] == column && !fields[i].empty()) return std::stod(fields[i]);
  }
  return kNotMeasured;
}

// The keys of a summary's "transport" and "shear" that results.csv shows, under the same names
// (a task has one or the other: a sheared run measures its viscosity directly).
constexpr std::array<const char*, 7> kTransportMeasures = {
    "self_diffusion",        "self_diffusion_error", "self_diffusion_yeh_hummer", "shear_viscosity",
    "shear_viscosity_error", "thermal_conductivity", "thermal_conductivity_error"};
constexpr std::array<const char*, 5> kShearMeasures = {
    "shear_rate", "shear_stress", "shear_stress_error", "shear_viscosity", "shear_viscosity_error"};

double number(const nlohmann::json& summary, const char* key) {
  const auto found = summary.find(key);
  return found != summary.end() && found->is_number() ? found->get<double>() : kNotMeasured;
}

// What a done task measured, from its summary (and a run's time series for the errors).
TaskResult done_result(const std::vector<std::string>& names, const fs::path& folder) {
  const nlohmann::json summary = parse_json(read_text(folder / task_files::kSummary));
  TaskResult result;
  result.status = TaskStatus::done;
  result.dimension = summary.value("dimension", 0);
  result.wall_seconds = number(summary, "wall_seconds");
  for (const std::string& name : names) {
    double value = kNotMeasured;
    for (const char* section : {"transport", "shear"}) {
      const auto found = summary.find(section);
      if (found != summary.end() && found->is_object() && found->contains(name)) {
        value = number(*found, name.c_str());
      }
    }
    if (name == "shear_rate" && summary.contains("shear") && summary["shear"].is_object()) {
      value = number(summary["shear"], "rate");
    }
    if (name == "Z") value = number(summary, "compressibility_factor");
    if (name == "Z_error") value = last_logged(folder / task_files::kLog, "Z_error");
    if (name == "pressure_error") value = last_logged(folder / task_files::kLog, "pressure_error");
    if (name == "pressure" || name == "temperature" || name == "collision_rate" ||
        name == "packing_fraction" || name == "time") {
      value = number(summary, name.c_str());
    }
    if (name == "events") value = number(summary, "events");
    result.measures.emplace_back(name, value);
  }
  return result;
}

template <std::size_t D>
void write_initial(const InitialOptions& options, const fs::path& path) {
  AtomicFile file(path.string());
  write_start(file.stream(), make_initial<D>(options), Rule::elastic);
  file.commit();
}

// carom init's start, unless the task reads its own.
void make_start(const sweep::TaskSpec& spec) {
  if (spec.start_file) return;
  if (spec.dimension == 3) {
    write_initial<3>(spec.initial, spec.start.path);
  } else {
    write_initial<2>(spec.initial, spec.start.path);
  }
}

TaskStatus run(const sweep::TaskSpec& spec, const fs::path& folder, const TaskHooks& hooks) {
  const fs::path checkpoint = folder / task_files::kCheckpoint;
  const bool resumed = fs::exists(checkpoint);
  const auto begin = [&] {
    if (resumed) return resume_start(checkpoint.string());
    make_start(spec);
    return load_start(spec.start);
  };
  Runner runner(begin());
  // The checkpoint holds the measurement window, open or still to open: continued as carom run
  // --resume continues it, without --equilibrate.
  RunSpec run_spec = spec.run;
  if (resumed) run_spec.measure_from.reset();
  RunHooks run_hooks;
  run_hooks.stop = hooks.stop;
  if (hooks.progress) {
    run_hooks.progress = [&](const AnySimulation& simulation, const RunProgress&) {
      hooks.progress(spec.run.end_time > 0.0 ? simulation.time() / spec.run.end_time : 1.0);
    };
  }
  return runner.run(run_spec, run_hooks).status == RunStatus::stopped ? TaskStatus::stopped
                                                                      : TaskStatus::done;
}

TaskStatus compress(const sweep::TaskSpec& spec, const fs::path& folder, const TaskHooks& hooks) {
  make_start(spec);
  CompressionHooks compression_hooks;
  compression_hooks.stop = hooks.stop;
  if (hooks.progress && spec.compress.settings.target) {
    compression_hooks.progress = [&](const CompressionProgress& p) {
      hooks.progress(p.packing_fraction / *spec.compress.settings.target);
    };
  }
  const CompressionResult result = carom::compress(
      read_start_system(spec.start.path, spec.compress_boundary), spec.compress, compression_hooks);
  if (result.summary.status == "interrupted") return TaskStatus::stopped;
  {
    AtomicFile packing((folder / task_files::kPacking).string());
    write_start(packing.stream(), result.packing, Rule::elastic);
    packing.commit();
  }
  AtomicFile summary((folder / task_files::kSummary).string());
  write_json(summary.stream(), result.summary);
  summary.commit();
  return TaskStatus::done;
}

fs::path task_folder(const SweepPlan& plan, std::size_t index, const std::string& out_dir) {
  if (index >= plan.tasks().size()) {
    throw RequestError(fmt::format("{} has {} tasks, numbered from 0: there is no task {}",
                                   plan.name(), plan.tasks().size(), index));
  }
  return fs::path(out_dir) / plan.tasks()[index].name;
}

// The temporary files (AtomicFile's FILE.tmp.XXXXXX) of an attempt killed while it wrote.
void remove_leftovers(const fs::path& folder) {
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (entry.path().filename().string().find(".tmp.") != std::string::npos) {
      fs::remove(entry.path());
    }
  }
}

}  // namespace

std::vector<std::string> measure_names(const SweepPlan& plan) {
  if (plan.kind() == TaskKind::compress) return {"packing_fraction", "Z", "time", "events"};
  std::vector<std::string> names = {
      "Z",           "Z_error",        "pressure",        "pressure_error",
      "temperature", "collision_rate", "packing_fraction"};
  const auto any_task = [&plan](auto&& asks) {
    return std::any_of(plan.tasks().begin(), plan.tasks().end(), [&](const SweepTask& task) {
      return std::any_of(task.action.begin(), task.action.end(), asks);
    });
  };
  const auto add = [&names](const auto& more) {
    for (const char* name : more) {
      if (std::find(names.begin(), names.end(), name) == names.end()) names.emplace_back(name);
    }
  };
  if (any_task(
          [](const PlanSetting& s) { return s.key == "transport" && std::get<bool>(s.value); })) {
    add(kTransportMeasures);
  }
  if (any_task([](const PlanSetting& s) { return s.key == "shear"; })) add(kShearMeasures);
  return names;
}

std::vector<std::string> task_commands(const SweepPlan& plan, std::size_t index,
                                       const std::string& folder) {
  task_folder(plan, index, folder);  // refuses an index out of range
  return sweep::task_spec(plan, plan.tasks()[index], folder).commands;
}

void check_sweep_folder(const SweepPlan& plan, const std::string& out_dir) {
  for (std::size_t i = 0; i < plan.tasks().size(); ++i) {
    const fs::path folder = task_folder(plan, i, out_dir);
    const fs::path commands = folder / task_files::kCommands;
    if (!fs::exists(commands)) continue;
    const sweep::TaskSpec spec = sweep::task_spec(plan, plan.tasks()[i], folder.string());
    if (read_text(commands) != commands_text(spec)) {
      throw RequestError(fmt::format(
          "{} holds the files of another task (its {} differs from what {} now makes it: the "
          "plan changed); give another -o, or remove the folder to run the task again",
          folder.string(), task_files::kCommands, plan.name()));
    }
  }
}

TaskResult run_task(const SweepPlan& plan, std::size_t index, const std::string& out_dir,
                    const TaskHooks& hooks) {
  const fs::path folder = task_folder(plan, index, out_dir);
  const sweep::TaskSpec spec = sweep::task_spec(plan, plan.tasks()[index], folder.string());
  fs::create_directories(folder);
  const fs::path commands = folder / task_files::kCommands;
  if (!fs::exists(commands)) {
    write_text(commands, commands_text(spec));
  } else if (read_text(commands) != commands_text(spec)) {
    check_sweep_folder(plan, out_dir);  // throws, saying what differs
  }
  const fs::path error = folder / task_files::kError;
  if (fs::exists(folder / task_files::kSummary)) return done_result(measure_names(plan), folder);
  fs::remove(error);
  remove_leftovers(folder);
  try {
    const TaskStatus status =
        plan.kind() == TaskKind::run ? run(spec, folder, hooks) : compress(spec, folder, hooks);
    if (status == TaskStatus::stopped) return TaskResult::with(TaskStatus::stopped);
    return done_result(measure_names(plan), folder);
  } catch (const std::exception& e) {
    // Whatever the task could not do is its own failure: the sweep goes on.
    TaskResult failed = TaskResult::with(TaskStatus::failed, e.what());
    write_text(error, failed.error + '\n');
    return failed;
  }
}

std::vector<TaskResult> read_task_results(const SweepPlan& plan, const std::string& out_dir) {
  std::vector<TaskResult> results;
  for (std::size_t i = 0; i < plan.tasks().size(); ++i) {
    const fs::path folder = task_folder(plan, i, out_dir);
    if (fs::exists(folder / task_files::kSummary)) {
      results.push_back(done_result(measure_names(plan), folder));
    } else if (fs::exists(folder / task_files::kError)) {
      std::string error = read_text(folder / task_files::kError);
      while (!error.empty() && error.back() == '\n') error.pop_back();
      results.push_back(TaskResult::with(TaskStatus::failed, error));
    } else {
      results.push_back(TaskResult::with(TaskStatus::pending));
    }
  }
  return results;
}

}  // namespace carom
