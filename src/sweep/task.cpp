// One task of a sweep in its folder: what carom init and carom run (or compress) would do alone,
// resumed from what an earlier attempt left.
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>
#include <variant>

#include "carom/io/atomic_file.hpp"
#include "carom/run/compress_run.hpp"
#include "carom/run/run.hpp"
#include "carom/run/run_report.hpp"
#include "carom/run/start.hpp"
#include "carom/run/z_drift.hpp"
#include "carom/sweep/sweep.hpp"
#include "io/json_text.hpp"
#include "plan_keys.hpp"
#include "task_spec.hpp"

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

// The words of a command as a shell reads those task_spec writes (plain, or in single quotes with
// ' written '\'').
std::vector<std::string> shell_words(std::string_view command) {
  std::vector<std::string> words;
  std::string word;
  bool quoted = false, in_word = false;
  for (std::size_t i = 0; i < command.size(); ++i) {
    const char c = command[i];
    if (quoted) {
      if (c == '\'') {
        quoted = false;
      } else {
        word += c;
      }
    } else if (c == '\'') {
      quoted = in_word = true;
    } else if (c == '\\' && i + 1 < command.size()) {
      word += command[++i];
      in_word = true;
    } else if (c == ' ') {
      if (in_word) words.push_back(std::move(word));
      word.clear();
      in_word = false;
    } else {
      word += c;
      in_word = true;
    }
  }
  if (in_word) words.push_back(std::move(word));
  return words;
}

// Whether `written` (a task.txt) holds the commands of `task`, however its folder and the plan's
// were spelled when it was written (out, ./out, /home/me/out): the task's commands made again with
// the folder and the start file that the written ones name are the same text. The written start
// file is taken only where it names the plan's: a plan edited to start from another file holds
// other tasks, whose commands differ only there. One no longer there is judged by its name.
bool holds_task(const std::string& written, const SweepPlan& plan, const SweepTask& task) {
  std::string last_line = written.substr(0, written.empty() ? 0 : written.size() - 1);
  last_line = last_line.substr(last_line.rfind('\n') + 1);
  const std::vector<std::string> words = shell_words(last_line);
  // Every task's last command names its folder's summary, FOLDER/summary.json, after --summary; a
  // start file's task reads it as its first command's first argument: carom run FILE ... or carom
  // compress FILE ....
  const auto summary = std::find(words.begin(), words.end(), "--summary");
  if (summary == words.end() || summary + 1 == words.end()) return false;
  const fs::path folder = fs::path(*(summary + 1)).parent_path();
  const std::vector<std::string> first_words = shell_words(written.substr(0, written.find('\n')));
  if (first_words.size() < 3) return false;
  const bool from_file = std::any_of(task.start.begin(), task.start.end(),
                                     [](const PlanSetting& s) { return s.key == "file"; });
  try {
    std::optional<std::string> start_file;
    if (from_file) {
      const std::string planned = *sweep::task_spec(plan, task, folder.string()).start_file;
      const std::string& stored = first_words[2];
      const bool same = fs::exists(stored)
                            ? same_file(stored, planned)
                            : fs::path(stored).filename() == fs::path(planned).filename();
      if (!same) return false;
      start_file = stored;
    }
    return written == commands_text(sweep::task_spec(plan, task, folder.string(), start_file));
  } catch (const PlanError&) {
    return false;  // a folder spelled as no task's could be
  }
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

// What a compression's summary says of how it ended: its status, target, dimension, packing
// fraction and Z.
CompressionSummary compression_outcome(const nlohmann::json& summary) {
  CompressionSummary outcome;
  outcome.status = summary.value("status", "");
  if (const auto target = summary.find("target"); target != summary.end() && target->is_number()) {
    outcome.target = target->get<double>();
  }
  outcome.dimension = summary.value("dimension", 2);
  outcome.packing_fraction = number(summary, "packing_fraction");
  outcome.compressibility_factor = number(summary, "compressibility_factor");
  return outcome;
}

// A compression's failure, as carom compress reports it (exit 1): jammed before its target.
std::optional<std::string> compression_shortfall(const nlohmann::json& summary,
                                                 const fs::path& folder) {
  return shortfall(compression_outcome(summary), (folder / task_files::kPacking).string());
}

// What a finished task measured, from its summary (and a run's time series for the errors):
// done, or failed for a compression that jammed short of its target.
TaskResult finished_result(const SweepPlan& plan, const fs::path& folder) {
  const std::vector<std::string> names = measure_names(plan);
  const nlohmann::json summary = parse_json(read_text(folder / task_files::kSummary));
  TaskResult result;
  result.status = TaskStatus::done;
  if (plan.kind() == TaskKind::compress) {
    if (std::optional<std::string> why = compression_shortfall(summary, folder)) {
      result.status = TaskStatus::failed;
      result.error = std::move(*why);
    }
  }
  result.dimension = summary.value("dimension", 0);
  result.wall_seconds = number(summary, "wall_seconds");
  const auto drift = summary.find("compressibility_factor_drift");
  const bool verdict = drift != summary.end() && drift->is_object();
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
    // A summary written before carom reported block_correlation has none: NaN, a blank field.
    if (verdict && name == kDriftMeasure) value = number(*drift, "sigmas");
    if (verdict && name == kCorrelationMeasure) {
      value = DriftVerdict::correlation_spreads_of(number(*drift, "block_correlation"),
                                                   number(*drift, "intervals"));
    }
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
    write_initial<3>(spec.initial, spec.start_path);
  } else {
    write_initial<2>(spec.initial, spec.start_path);
  }
}

// The task's start compressed into packing.txt (carom init's made first): its result, or nullopt
// when stopped before the end (nothing written; the next attempt compresses again).
std::optional<CompressionResult> compress_start(const sweep::TaskSpec& spec,
                                                const TaskHooks& hooks) {
  make_start(spec);
  CompressionHooks compression_hooks;
  compression_hooks.stop = hooks.stop;
  if (hooks.progress && spec.compress.settings.target) {
    compression_hooks.progress = [&](const CompressionProgress& p) {
      hooks.progress(p.packing_fraction / *spec.compress.settings.target);
    };
  }
  CompressionResult result =
      carom::compress(read_start_system(spec.compress.input, spec.compress_boundary), spec.compress,
                      compression_hooks);
  if (result.summary.status == "interrupted") return std::nullopt;
  return result;
}

void write_packing(const CompressionResult& result, const std::string& path) {
  AtomicFile packing(path);
  write_start(packing.stream(), result.packing, Rule::elastic);
  packing.commit();
}

void write_compression_summary(const CompressionSummary& summary, const fs::path& path) {
  AtomicFile file(path.string());
  write_json(file.stream(), summary);
  file.commit();
}

// How the compression that made a run's packing ended, if it ended at the task's target or
// jammed before it: its summary (compression.json, written after packing.txt) says so. Nothing
// otherwise: no packing, no summary (killed between the two), an unreadable one, or a compression
// stopped part way (a hand-run carom compress interrupted): that packing is compressed again.
std::optional<CompressionSummary> finished_compression(const sweep::TaskSpec& spec,
                                                       const fs::path& folder) {
  const fs::path record = folder / task_files::kCompression;
  if (!fs::exists(spec.start.path) || !fs::exists(record)) return std::nullopt;
  CompressionSummary outcome;
  try {
    outcome = compression_outcome(parse_json(read_text(record)));
  } catch (const std::exception&) {
    return std::nullopt;
  }
  const bool ended = outcome.status == "reached_target" || outcome.status == "jammed";
  if (!ended || outcome.target != spec.compress.settings.target) return std::nullopt;
  return outcome;
}

TaskStatus run(const sweep::TaskSpec& spec, const fs::path& folder, const TaskHooks& hooks) {
  const fs::path checkpoint = folder / task_files::kCheckpoint;
  const bool resumed = fs::exists(checkpoint);
  if (!resumed && spec.compresses_start) {
    std::optional<CompressionSummary> compressed = finished_compression(spec, folder);
    if (!compressed) {
      // The task's progress is its run's: the compression before it reports none.
      const std::optional<CompressionResult> result = compress_start(spec, {hooks.stop, {}});
      if (!result) return TaskStatus::stopped;
      write_packing(*result, spec.start.path);
      write_compression_summary(result->summary, folder / task_files::kCompression);
      compressed = result->summary;
    }
    // Jammed short of its packing, the run would be at another state point: the task fails, as
    // carom compress does, its packing kept, and is not compressed again (it would jam again).
    if (const std::optional<std::string> jammed = shortfall(*compressed, spec.start.path)) {
      throw RequestError(*jammed + ": no run starts from it");
    }
  }
  const auto begin = [&] {
    if (resumed) return resume_start(checkpoint.string());
    if (!spec.compresses_start) make_start(spec);
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
  const std::optional<CompressionResult> result = compress_start(spec, hooks);
  if (!result) return TaskStatus::stopped;
  const std::string packing_path = (folder / task_files::kPacking).string();
  write_packing(*result, packing_path);
  // Jammed short of its target, the task failed as its carom compress does, its packing and
  // summary kept: the summary, written last, is what says so; error.txt, before it, tells why.
  if (const std::optional<std::string> why = shortfall(result->summary, packing_path)) {
    write_text(folder / task_files::kError, *why + '\n');
  }
  write_compression_summary(result->summary, folder / task_files::kSummary);
  return TaskStatus::done;
}

fs::path task_folder(const SweepPlan& plan, std::size_t index, const std::string& out_dir) {
  if (index >= plan.tasks().size()) {
    throw RequestError(fmt::format("{} has {} tasks, numbered from 0: there is no task {}",
                                   plan.name(), plan.tasks().size(), index));
  }
  return fs::path(out_dir) / plan.tasks()[index].name;
}

// The temporary files of an attempt killed while it wrote one of the files a task writes whole
// (AtomicFile's FILE.tmp.XXXXXX): those and nothing else, so that a dump the plan names
// "run.tmp.xyz" is the user's and stays.
void remove_leftovers(const fs::path& folder) {
  const auto& written_whole = task_files::kWrittenWhole;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (std::any_of(written_whole.begin(), written_whole.end(), [&](const char* target) {
          return AtomicFile::is_temporary_of(name, target);
        })) {
      fs::remove(entry.path());
    }
  }
}

// Refuses an out_dir that cannot be a writable folder: a file, under a file, or in a folder
// that cannot be written.
void check_folder_can_be_written(const std::string& out_dir) {
  std::error_code error;
  fs::path existing = fs::absolute(out_dir, error);
  while (!fs::exists(existing, error) && existing.has_relative_path()) {
    existing = existing.parent_path();
  }
  if (!fs::is_directory(existing, error)) {
    throw RequestError(
        fmt::format("cannot make the sweep's folder {} (-o): {} is a file, not a folder", out_dir,
                    existing.string()));
  }
  if (::access(existing.c_str(), W_OK) != 0) {
    throw RequestError(fmt::format("cannot write the sweep's folder {} (-o): {}: {}", out_dir,
                                   existing.string(), std::strerror(errno)));
  }
}

// A file a sweep reads or writes, and what it is in messages.
struct SweepFile {
  std::string what;
  std::string path;
};

// The start a task reads with `file` (a .gsd's ":K" frame left out), if it reads one.
std::optional<std::string> start_file(const SweepPlan& plan, const SweepTask& task) {
  for (const PlanSetting& s : task.start) {
    if (s.key != "file" || !std::holds_alternative<std::string>(s.value)) continue;
    return start_file_path((fs::path(plan.folder()) / std::get<std::string>(s.value)).string());
  }
  return std::nullopt;
}

// The names of the files a task of `plan` may write in its folder: the sweep's own, and the dump,
// event log and end state the plan names.
std::vector<std::string> task_file_names(const SweepPlan& plan, const SweepTask& task,
                                         bool reads_a_start_file) {
  std::vector<std::string> names = {task_files::kCommands, task_files::kSummary, task_files::kError,
                                    task_files::kLock};
  if (!reads_a_start_file) names.emplace_back(task_files::kStart);
  if (plan.kind() == TaskKind::compress || plan.compresses_start()) {
    names.emplace_back(task_files::kPacking);
  }
  if (plan.compresses_start()) names.emplace_back(task_files::kCompression);
  if (plan.kind() == TaskKind::compress) return names;
  names.emplace_back(task_files::kLog);
  names.emplace_back(task_files::kCheckpoint);
  for (const PlanSetting& s : task.action) {
    if (sweep::names_a_task_file(s.key) && std::holds_alternative<std::string>(s.value)) {
      names.push_back(std::get<std::string>(s.value));
    }
  }
  return names;
}

// Refuses a sweep one of whose outputs is one of its inputs or another of its own files, however
// the paths are spelled (./, .., symbolic or hard links: same_file, as carom run checks its
// files): the report page must not be the plan, a start file, a table, a lock or any task's file
// or folder, and no file the sweep writes (the tables, the locks, the tasks' files) may be the
// plan or a start file. The page's folder must be writable; the tables and the page must not be
// folders. `named_page`: the page is --html's, not the sweep folder's own.
void check_apart(const SweepPlan& plan, const std::string& out_dir, const std::string& page,
                 bool named_page) {
  const fs::path dir(out_dir);
  std::vector<SweepFile> inputs = {{"the plan", plan.name()}};
  for (const SweepTask& task : plan.tasks()) {
    if (std::optional<std::string> start = start_file(plan, task);
        start && std::none_of(inputs.begin(), inputs.end(),
                              [&](const SweepFile& f) { return f.path == *start; })) {
      inputs.push_back({"the start file", *start});
    }
  }
  const std::vector<SweepFile> tables = {{"results.csv", (dir / "results.csv").string()},
                                         {"summary.csv", (dir / "summary.csv").string()},
                                         {"the sweep's lock", (dir / kSweepLock).string()}};
  // Named as carom run names its clashing files; the page given by --html is moved by it, any
  // other file by another folder.
  const SweepFile report{named_page ? "--html" : "the report page", page};
  const auto refuse = [&](const SweepFile& output, const SweepFile& other) {
    throw RequestError(fmt::format(
        "{} and {} name the same file ({} and {}): the sweep would overwrite {}; give another {}",
        output.what, other.what, output.path, other.path, other.what,
        named_page && &output == &report ? "--html" : "-o"));
  };
  for (const std::string& path : {tables[0].path, tables[1].path, page}) {
    if (fs::is_directory(path)) {
      throw RequestError(fmt::format("cannot write {}: it is a folder", path));
    }
  }
  // A page elsewhere than the sweep's folder (which is made if missing) must have a folder.
  if (const fs::path page_folder = fs::path(page).parent_path();
      !same_file(page_folder.empty() ? "." : page_folder.string(), out_dir)) {
    check_writable(page);
  }
  // The few named files, pairwise.
  for (const SweepFile& input : inputs) {
    if (same_file(page, input.path)) refuse(report, input);
    for (const SweepFile& table : tables) {
      if (same_file(table.path, input.path)) refuse(table, input);
    }
  }
  for (const SweepFile& table : tables) {
    if (same_file(page, table.path)) refuse(report, table);
  }
  // The tasks' folders and files, up to 100,000 folders of them: one stat each, against the
  // named files that exist (a hard link is the same device and inode whatever its name); against
  // those that do not, only a path of the same name can be the same.
  std::vector<SweepFile> named = inputs;
  named.push_back(report);
  const auto clash = [&](const SweepFile& own, const SweepFile& file) {
    &file == &named.back() ? refuse(report, own) : refuse(own, file);
  };
  std::vector<std::pair<struct stat, const SweepFile*>> existing;
  for (const SweepFile& file : named) {
    struct stat info {};
    if (::stat(file.path.c_str(), &info) == 0) existing.emplace_back(info, &file);
  }
  for (const SweepTask& task : plan.tasks()) {
    const SweepFile folder{fmt::format("task {}'s folder", task.name), (dir / task.name).string()};
    std::error_code error;
    if (fs::exists(folder.path, error) && !fs::is_directory(folder.path, error)) {
      throw RequestError(fmt::format("{} ({}) is a file", folder.what, folder.path));
    }
    if (fs::path(page).filename() == task.name && same_file(folder.path, page)) {
      refuse(report, folder);
    }
    for (const std::string& name :
         task_file_names(plan, task, start_file(plan, task).has_value())) {
      const SweepFile own{fmt::format("task {}'s {}", task.name, name),
                          (fs::path(folder.path) / name).string()};
      struct stat info {};
      if (::stat(own.path.c_str(), &info) == 0) {
        for (const auto& [other, file] : existing) {
          if (other.st_dev == info.st_dev && other.st_ino == info.st_ino) clash(own, *file);
        }
        continue;
      }
      for (const SweepFile& file : named) {
        if (fs::path(file.path).filename() == fs::path(name).filename() &&
            same_file(own.path, file.path)) {
          clash(own, file);
        }
      }
    }
  }
}

// How often a task whose lock another holds looks again.
constexpr auto kLockPoll = std::chrono::milliseconds(100);

// The task's lock, once whoever holds it (a Dask worker of an earlier sweep, still running the
// task) lets go: then the task goes on from what that one left, as after any attempt. Nothing
// if `stop` is raised meanwhile.
std::optional<HeldLock> wait_for_lock(const fs::path& path, const std::atomic<int>* stop) {
  while (true) {
    if (std::optional<HeldLock> lock = HeldLock::try_take(path.string())) return lock;
    if (stop != nullptr && stop->load() != 0) return std::nullopt;
    std::this_thread::sleep_for(kLockPoll);
  }
}

}  // namespace

const std::vector<std::string>& measure_names(const SweepPlan& plan) {
  return plan.measures();
}

std::vector<std::string> sweep::measures_of(const SweepPlan& plan) {
  if (plan.kind() == TaskKind::compress) return {"packing_fraction", "Z", "time", "events"};
  std::vector<std::string> names = {
      "Z",           "Z_error",        "pressure",         "pressure_error",
      "temperature", "collision_rate", "packing_fraction", std::string(kDriftMeasure),
      std::string(kCorrelationMeasure)};
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

void check_sweep_folder(const SweepPlan& plan, const std::string& out_dir,
                        const std::string& report) {
  check_folder_can_be_written(out_dir);
  const std::string page = report.empty() ? (fs::path(out_dir) / kReportPage).string() : report;
  check_apart(plan, out_dir, page, !report.empty());
  for (std::size_t i = 0; i < plan.tasks().size(); ++i) {
    const fs::path folder = task_folder(plan, i, out_dir);
    const fs::path commands = folder / task_files::kCommands;
    if (!fs::exists(commands)) continue;
    if (!holds_task(read_text(commands), plan, plan.tasks()[i])) {
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
  const std::optional<HeldLock> lock = wait_for_lock(folder / task_files::kLock, hooks.stop);
  if (!lock) return TaskResult::with(TaskStatus::stopped);
  const fs::path commands = folder / task_files::kCommands;
  if (!fs::exists(commands)) {
    write_text(commands, commands_text(spec));
  } else if (!holds_task(read_text(commands), plan, plan.tasks()[index])) {
    check_sweep_folder(plan, out_dir);  // throws, saying what differs
  }
  const fs::path error = folder / task_files::kError;
  if (fs::exists(folder / task_files::kSummary)) return finished_result(plan, folder);
  fs::remove(error);
  remove_leftovers(folder);
  try {
    const TaskStatus status =
        plan.kind() == TaskKind::run ? run(spec, folder, hooks) : compress(spec, folder, hooks);
    if (status == TaskStatus::stopped) return TaskResult::with(TaskStatus::stopped);
    return finished_result(plan, folder);
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
      results.push_back(finished_result(plan, folder));
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
