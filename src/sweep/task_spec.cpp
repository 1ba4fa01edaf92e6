#include "task_spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include "carom/core/names.hpp"
#include "carom/engine/simulation.hpp"
#include "plan_keys.hpp"

namespace carom::sweep {

namespace {

namespace fs = std::filesystem;

double as_number(const PlanValue& v) {
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  return std::get<double>(v);
}
std::uint64_t as_integer(const PlanValue& v) {
  return static_cast<std::uint64_t>(std::get<std::int64_t>(v));
}
const std::string& as_text(const PlanValue& v) {
  return std::get<std::string>(v);
}
bool as_flag(const PlanValue& v) {
  return std::get<bool>(v);
}

template <class E>
E as_choice(const PlanValue& v) {
  return *from_name<E>(as_text(v));  // the parser checked the name
}

// A word for a shell: quoted unless it is made of characters no shell treats specially.
std::string shell_word(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789-_./=,:+@%") == std::string::npos) {
    return word;
  }
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// "--key value" as carom's parser takes it ("--flag" alone when true, nothing when false).
void append_option(std::string& command, const PlanSetting& s) {
  std::string option = "--" + s.key;
  for (char& c : option) c = c == '_' ? '-' : c;
  if (const bool* flag = std::get_if<bool>(&s.value)) {
    if (*flag) command += " " + option;
    return;
  }
  command += " " + option + " " + shell_word(value_text(s.value));
}

std::string in_folder(const std::string& folder, const std::string& file) {
  return (fs::path(folder) / file).string();
}

// Whether `word` is in `text` with no letter or '_' on either side.
bool has_word(const std::string& text, const std::string& word) {
  const auto part_of_word = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  };
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) {
    const std::size_t end = at + word.size();
    if ((at == 0 || !part_of_word(text[at - 1])) &&
        (end == text.size() || !part_of_word(text[end]))) {
      return true;
    }
  }
  return false;
}

// The setting a library message is about: the one whose option it names first ("--shear needs
// --rule elastic" is about --shear), else whose key it names, as written or in words ("the
// restitution must be ...", "a longer chain length"), else the first.
const PlanSetting& named_in(const std::vector<PlanSetting>& settings, const std::string& message) {
  const PlanSetting* first_named = nullptr;
  std::size_t first_at = std::string::npos;
  for (const PlanSetting& s : settings) {
    std::string option = "--" + s.key;
    for (char& c : option) c = c == '_' ? '-' : c;
    // "--every" is not named by "--every-thing": the option ends where a word does.
    for (std::size_t at = message.find(option); at != std::string::npos;
         at = message.find(option, at + 1)) {
      const std::size_t end = at + option.size();
      const bool whole =
          end == message.size() ||
          !(std::isalnum(static_cast<unsigned char>(message[end])) || message[end] == '-');
      if (whole && at < first_at) {
        first_named = &s;
        first_at = at;
      }
    }
  }
  if (first_named != nullptr) return *first_named;
  for (const PlanSetting& s : settings) {
    std::string words = s.key;
    std::replace(words.begin(), words.end(), '_', ' ');
    if (has_word(message, s.key) || has_word(message, words)) return s;
  }
  return settings.front();
}

const PlanSetting* find_setting(const std::vector<PlanSetting>& settings, std::string_view key) {
  const auto found = std::find_if(settings.begin(), settings.end(),
                                  [&](const PlanSetting& s) { return s.key == key; });
  return found == settings.end() ? nullptr : &*found;
}

// RequestError "--KEY excludes --OTHER" when both are given (a flag: given as true), as carom's
// command line refuses them.
void refuse_together(const std::vector<PlanSetting>& settings, std::string_view key,
                     std::string_view other) {
  const auto given = [&](std::string_view name) {
    const PlanSetting* s = find_setting(settings, name);
    return s != nullptr && !(std::holds_alternative<bool>(s->value) && !as_flag(s->value));
  };
  if (given(key) && given(other)) {
    std::string message = fmt::format("--{} excludes --{}", key, other);
    for (char& c : message) c = c == '_' ? '-' : c;
    throw RequestError(message);
  }
}

void init_options(TaskSpec& spec, const std::vector<PlanSetting>& settings) {
  InitialOptions& o = spec.initial;
  for (const PlanSetting& s : settings) {
    const PlanValue& v = s.value;
    if (s.key == "dim") {
      require_dimension(std::get<std::int64_t>(v));  // before it is narrowed to an int
      spec.dimension = static_cast<int>(as_integer(v));
    }
    if (s.key == "n") o.n = as_integer(v);
    if (s.key == "phi") o.packing_fraction = as_number(v);
    if (s.key == "box") o.box = std::get<std::vector<double>>(v);
    if (s.key == "aspect") o.aspect = as_number(v);
    if (s.key == "radius") o.radius = as_number(v);
    if (s.key == "polydispersity") o.polydispersity = as_number(v);
    if (s.key == "species") {
      try {
        o.species = parse_species(as_text(v));
      } catch (const InitialError& e) {
        throw RequestError(e.what());
      }
    }
    if (s.key == "kT") o.temperature = as_number(v);
    if (s.key == "seed") o.seed = as_integer(v);
    if (s.key == "boundary") o.boundary = as_choice<Boundary>(v);
    if (s.key == "lattice" && as_flag(v)) o.placement = Placement::lattice;
    if (s.key == "random" && as_flag(v)) o.placement = Placement::random;
  }
  // What carom init's command line refuses as options that exclude each other (CLI11's words).
  refuse_together(settings, "random", "lattice");
  refuse_together(settings, "aspect", "box");
  refuse_together(settings, "radius", "box");
  refuse_together(settings, "species", "polydispersity");
  refuse_together(settings, "species", "radius");
}

void run_options(TaskSpec& spec, const std::vector<PlanSetting>& settings,
                 const std::string& folder) {
  StartSpec& start = spec.start;
  RunSpec& run = spec.run;
  std::optional<std::string> cadence;
  std::optional<double> log_every, thermostat_every, thermostat_rate, shear;
  bool velocity_profile = false;
  ThermostatKind thermostat = ThermostatKind::none;
  for (const PlanSetting& s : settings) {
    const PlanValue& v = s.value;
    if (s.key == "thermostat") thermostat = as_choice<ThermostatKind>(v);
    if (s.key == "thermostat_every") thermostat_every = as_number(v);
    if (s.key == "thermostat_rate") thermostat_rate = as_number(v);
    if (s.key == "end_time") run.end_time = as_number(v) + 0.0;  // -0 as 0, as carom run
    if (s.key == "equilibrate") run.measure_from = as_number(v);
    if (s.key == "rule") start.rule = as_choice<Rule>(v);
    if (s.key == "restitution") start.restitution = as_number(v);
    if (s.key == "tc") start.tc = as_number(v);
    if (s.key == "boundary") start.boundary = as_choice<Boundary>(v);
    if (s.key == "engine") start.engine = as_choice<EngineKind>(v);
    if (s.key == "kT") start.temperature = as_number(v);
    if (s.key == "seed") start.seed = as_integer(v);
    if (s.key == "dump") run.dump = in_folder(folder, as_text(v));
    if (s.key == "every") run.dump_every = as_number(v);
    if (s.key == "events") run.events = in_folder(folder, as_text(v));
    if (s.key == "final") run.final_state = in_folder(folder, as_text(v));
    if (s.key == "log_every") log_every = as_number(v);
    if (s.key == "checkpoint_every") cadence = value_text(v);
    if (s.key == "check") run.check = as_flag(v);
    if (s.key == "check_every") run.check_every = as_integer(v);
    if (s.key == "transport") run.transport = as_flag(v);
    if (s.key == "shear") shear = as_number(v);
    if (s.key == "velocity_profile") velocity_profile = as_flag(v);
    if (s.key == "sampler") start.sampler = as_choice<SamplerKind>(v);
    if (s.key == "chain_length") start.chain_length = as_number(v);
  }
  if (find_setting(settings, "seed") != nullptr && !start.temperature &&
      start.sampler == SamplerKind::md) {
    throw RequestError(
        "--seed needs --kT T (it seeds the velocities --kT draws, and Andersen's resets) or "
        "--sampler ecmc (the chains' particles): without them it would seed nothing");
  }
  start.shear = shear_request(shear, velocity_profile);
  start.thermostat = thermostat_request(thermostat, start.temperature, thermostat_every,
                                        thermostat_rate, start.seed, start.sampler);
  // Every task keeps a time series (the error bars of results.csv), its summary and its state.
  const double measured = run.end_time - run.measure_from.value_or(0.0);
  run.log = in_folder(folder, task_files::kLog);
  run.log_every = log_every.value_or((measured > 0.0 ? measured : run.end_time) / 200.0);
  run.summary = in_folder(folder, task_files::kSummary);
  run.checkpoint = in_folder(folder, task_files::kCheckpoint);
  spec.checkpoint_every = cadence.value_or(spec.checkpoint_every);
  run.checkpoint_every = checkpoint_cadence(spec.checkpoint_every);
}

void compress_options(TaskSpec& spec, const std::vector<PlanSetting>& settings) {
  CompressionSpec& c = spec.compress;
  bool jam = false;
  for (const PlanSetting& s : settings) {
    const PlanValue& v = s.value;
    if (s.key == "phi") c.settings.target = as_number(v);
    if (s.key == "jam") jam = as_flag(v);
    if (s.key == "rate") c.settings.rate = as_number(v);
    if (s.key == "boundary") spec.compress_boundary = as_choice<Boundary>(v);
    if (s.key == "kT") c.settings.temperature = as_number(v);
    if (s.key == "jam_pressure") c.settings.jammed_pressure = as_number(v);
    if (s.key == "engine") c.settings.engine = as_choice<EngineKind>(v);
    if (s.key == "unit_diameter") c.unit_diameter = as_flag(v);
  }
  refuse_together(settings, "jam", "phi");
  if (jam) c.settings.target.reset();
}

// What carom compress would refuse of a task's compression before it starts, named by the setting
// that sets it: its rate, kT and jamming pressure, and, where carom init makes the start (whose
// packing fraction is [start]'s phi), its target.
void check_compression(const SweepPlan& plan, const SweepTask& task, const TaskSpec& spec,
                       const std::vector<PlanSetting>& settings, std::string_view section) {
  const CompressionSettings& c = spec.compress.settings;
  const auto check = [&](std::string_view key, const auto& checked) {
    try {
      checked();
    } catch (const std::invalid_argument& e) {
      const PlanSetting* s = find_setting(settings, key);
      throw setting_error(plan, &task, s != nullptr ? *s : settings.front(), section, e.what());
    }
  };
  check("rate", [&] { check_growth_rate(c.rate); });
  check("kT", [&] { check_compression_temperature(c.temperature); });
  check("jam_pressure", [&] { check_jammed_pressure(c.jammed_pressure); });
  const InitialOptions& o = spec.initial;
  if (c.target && !spec.start_file && o.packing_fraction > 0.0) {
    const bool equal = o.polydispersity == 0.0 && o.species.empty();
    check("phi", [&] {
      check_target_packing(*c.target, o.packing_fraction, equal,
                           static_cast<std::size_t>(spec.dimension));
    });
  }
}

// The run's settings, and the task's seed when the run draws random numbers (new velocities at
// kT, Andersen's resets, event chains) without a seed of its own and carom init's start has one: a
// seed, set or swept, then seeds every draw of its task, not only carom init's.
std::vector<PlanSetting> action_settings(const SweepPlan& plan, const SweepTask& task) {
  std::vector<PlanSetting> settings = task.action;
  const PlanSetting* seed = find_setting(task.start, "seed");
  const PlanSetting* sampler = find_setting(settings, "sampler");
  const bool draws = find_setting(settings, "kT") != nullptr ||
                     (sampler != nullptr && value_text(sampler->value) == "ecmc");
  if (plan.kind() == TaskKind::run && seed != nullptr && draws &&
      find_setting(settings, "seed") == nullptr) {
    settings.push_back(*seed);
  }
  return settings;
}

// Why a swept seed of carom init's would leave the tasks of a state point one run, or nullopt:
// when it draws neither the placement (a lattice) nor the radii (equal), and the run draws every
// velocity again with a seed of its own.
std::optional<std::string> why_seed_is_idle(const TaskSpec& spec, const SweepTask& task) {
  const PlanSetting* seed = find_setting(task.start, "seed");
  const bool chains = spec.start.sampler == SamplerKind::ecmc;
  // A compressed start is not: the velocities carom init draws shape the packing.
  if (seed == nullptr || !seed->swept || spec.kind != TaskKind::run || spec.compresses_start ||
      !(spec.start.temperature || chains)) {
    return std::nullopt;
  }
  const PlanSetting* own_run_seed = find_setting(task.action, "seed");
  const InitialOptions& o = spec.initial;
  const bool random_placement =
      o.placement == Placement::random ||
      (o.placement == Placement::automatic &&
       o.packing_fraction <= random_placement_limit(static_cast<std::size_t>(spec.dimension)));
  if (own_run_seed == nullptr || random_placement || o.polydispersity > 0.0 || !o.species.empty()) {
    return std::nullopt;
  }
  return fmt::format(
      "carom init places every particle on a lattice ({}) with one radius, and [run] {} with "
      "[run] seed = {}: the tasks of a state point would be the same run. Remove [run] seed (the "
      "swept seed then draws them), or make the start random (random = true, or polydispersity)",
      o.placement == Placement::lattice
          ? std::string("lattice = true")
          : fmt::format("phi above {}",
                        random_placement_limit(static_cast<std::size_t>(spec.dimension))),
      chains ? "sampler = \"ecmc\" draws every chain's particle" : "kT draws every velocity again",
      value_text(own_run_seed->value));
}

// The commands, with the sweep's own files added as carom run's options.
void write_commands(TaskSpec& spec, const SweepTask& task, const std::vector<PlanSetting>& action,
                    const std::string& folder) {
  const std::string& start_path = spec.start_path;
  if (!spec.start_file) {
    std::string init = "carom init";
    for (const PlanSetting& s : task.start) append_option(init, s);
    spec.commands.push_back(init + " -o " + shell_word(start_path));
  }
  if (spec.kind == TaskKind::compress || spec.compresses_start) {
    std::string compress = "carom compress " + shell_word(start_path);
    for (const PlanSetting& s : spec.kind == TaskKind::compress ? action : task.compression) {
      append_option(compress, s);
    }
    compress += " -o " + shell_word(in_folder(folder, task_files::kPacking));
    // A compression's own summary is the task's; before a run, the run's is, and the
    // compression's says whether the packing is whole.
    compress += " --summary " + shell_word(in_folder(folder, spec.kind == TaskKind::compress
                                                                 ? task_files::kSummary
                                                                 : task_files::kCompression));
    spec.commands.push_back(compress + " -q");
    if (spec.kind == TaskKind::compress) return;
  }
  const RunSpec& run = spec.run;
  std::string command = "carom run " + shell_word(spec.start.path) + " " + value_text(run.end_time);
  for (const PlanSetting& s : action) {
    if (names_a_task_file(s.key)) {
      // Named as the task's commands reach it from where they run, as its own files are.
      append_option(command, {s.key, in_folder(folder, as_text(s.value)), s.line, s.swept});
    } else if (s.key != "end_time" && s.key != "log_every" && s.key != "checkpoint_every") {
      append_option(command, s);
    }
  }
  command += " --log " + shell_word(run.log) + " --log-every " + value_text(run.log_every) +
             " --summary " + shell_word(run.summary) + " --checkpoint " +
             shell_word(run.checkpoint) + " --checkpoint-every " + spec.checkpoint_every +
             " -q -o /dev/null";
  spec.commands.push_back(command);
}

}  // namespace

std::string value_text(const PlanValue& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, bool>) {
          return v ? "true" : "false";
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          return fmt::format("{}", fmt::join(v, " "));
        } else {
          return fmt::format("{}", v);
        }
      },
      value);
}

PlanError setting_error(const SweepPlan& plan, const SweepTask* task, const PlanSetting& setting,
                        std::string_view section, const std::string& why) {
  const std::string where = setting.swept ? "sweep" : std::string(section);
  const std::string which =
      task != nullptr && setting.swept ? fmt::format(" (task {})", task->name) : std::string();
  return PlanError(fmt::format("{}:{}: [{}] {} = {}{}: {}", plan.name(), setting.line, where,
                               setting.key, value_text(setting.value), which, why));
}

TaskSpec task_spec(const SweepPlan& plan, const SweepTask& task, const std::string& folder,
                   const std::optional<std::string>& start_file) {
  TaskSpec spec;
  spec.kind = plan.kind();
  for (const PlanSetting& s : task.start) {
    if (s.key == "file") {
      spec.start_file = start_file.value_or((fs::path(plan.folder()) / as_text(s.value)).string());
    }
  }
  const std::string_view section = spec.kind == TaskKind::run ? "run" : "compress";
  if (!spec.start_file) {
    try {
      init_options(spec, task.start);
      check_initial_options(static_cast<std::size_t>(spec.dimension), spec.initial);
    } catch (const std::exception& e) {  // InitialError, or RequestError for the dimension
      throw setting_error(plan, &task, named_in(task.start, e.what()), "start", e.what());
    }
  }
  spec.compresses_start = plan.compresses_start();
  if (spec.compresses_start) {
    try {
      compress_options(spec, task.compression);
    } catch (const std::invalid_argument& e) {
      throw setting_error(plan, &task, named_in(task.compression, e.what()), "compress", e.what());
    }
    check_compression(plan, task, spec, task.compression, "compress");
  }
  const std::vector<PlanSetting> action = action_settings(plan, task);
  if (spec.kind == TaskKind::compress) {
    try {
      compress_options(spec, action);
    } catch (const std::invalid_argument& e) {
      throw setting_error(plan, &task, named_in(action, e.what()), section, e.what());
    }
    check_compression(plan, task, spec, action, section);
  }
  try {
    if (spec.kind == TaskKind::run) {
      run_options(spec, action, folder);
      const StartSpec& s = spec.start;
      check_settings(
          {{s.rule.value_or(s.restitution < 1.0 ? Rule::elastic : Rule::swap), s.restitution, s.tc},
           s.engine});
      check_run_spec(spec.run);
      // What the run checks of its start's box, before any particle is made: the boundary and
      // rule are the run's, else what the start records (carom init's: its boundary, elastic; a
      // compression's: the boundary it compressed in, elastic).
      StartRecord record = spec.start_file ? plan.start_file_record()
                                           : StartRecord{spec.initial.boundary, Rule::elastic, {}};
      if (spec.compresses_start) {
        record = {
            spec.compress_boundary ? spec.compress_boundary : record.boundary, Rule::elastic, {}};
      }
      const Boundary boundary = s.boundary.value_or(record.boundary.value_or(Boundary::walls));
      const Rule rule = s.rule.value_or(default_rule(record, boundary, s.restitution));
      const bool periodic = boundary == Boundary::periodic;
      check_shear_box(s.shear, periodic, rule);
      check_run_in_box(spec.run, 0.0, periodic, s.shear.rate != 0.0, s.sampler);
      check_sampler_request({{rule, s.restitution, s.tc},
                             s.engine,
                             s.thermostat,
                             {s.sampler, s.chain_length, s.seed}},
                            periodic, s.shear, s.rule.has_value(), s.temperature.has_value());
      // Chains of a length given, over carom init's particles: whether they reach the end.
      if (s.sampler == SamplerKind::ecmc && s.chain_length != 0.0 && !spec.start_file &&
          spec.initial.n > 0) {
        check_chain_clock(spec.run.end_time, s.chain_length,
                          s.chain_length / static_cast<double>(spec.initial.n));
      }
    }
  } catch (const std::invalid_argument& e) {
    throw setting_error(plan, &task, named_in(action, e.what()), section, e.what());
  }
  spec.idle_seed = why_seed_is_idle(spec, task);
  spec.start_path = spec.start_file.value_or(in_folder(folder, task_files::kStart));
  spec.compress.input = spec.start_path;
  spec.start.path =
      spec.compresses_start ? in_folder(folder, task_files::kPacking) : spec.start_path;
  write_commands(spec, task, action, folder);
  return spec;
}

}  // namespace carom::sweep
