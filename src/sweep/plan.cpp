// Reading a plan: TOML (toml++) into settings, the axes' Cartesian product into tasks, and every
// task checked by what will run it, so that a bad plan is refused before anything runs.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "carom/atomic_file.hpp"
#include "carom/names.hpp"
#include "carom/simulation.hpp"
#include "sweep/plan_keys.hpp"
#include "sweep/task_spec.hpp"

namespace carom {

namespace {

using sweep::find_key;
using sweep::KeyInfo;
using sweep::Section;
using sweep::ValueType;

int line_of(const toml::node& node) {
  return static_cast<int>(node.source().begin.line);
}

bool is_choice(std::string_view key, std::string_view name) {
  if (key == "rule") return from_name<Rule>(name).has_value();
  if (key == "boundary") return from_name<Boundary>(name).has_value();
  if (key == "thermostat") return from_name<ThermostatKind>(name).has_value();
  return from_name<EngineKind>(name).has_value();
}

std::string choices(std::string_view key) {
  if (key == "rule") return names_list<Rule>();
  if (key == "boundary") return names_list<Boundary>();
  if (key == "thermostat") return names_list<ThermostatKind>();
  return names_list<EngineKind>();
}

class Reader {
 public:
  explicit Reader(const std::string& name) : name_(name) {}

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw PlanError(fmt::format("{}:{}: {}", name_, line, what));
  }

  [[noreturn]] void refuse_value(const toml::node& node, std::string_view where,
                                 const KeyInfo& info, std::string_view takes) const {
    fail(line_of(node), fmt::format("[{}] {}: {}", where, info.key, takes));
  }

  // The value of `node` for `info`, or a PlanError saying what the key takes.
  PlanValue value(const KeyInfo& info, const toml::node& node, std::string_view where) const {
    switch (info.type) {
      case ValueType::integer:
        if (const auto* i = node.as_integer(); i != nullptr && i->get() >= 0) return i->get();
        refuse_value(node, where, info, "takes a whole number >= 0");
      case ValueType::number:
        if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
        if (const auto* x = node.as_floating_point(); x != nullptr && std::isfinite(x->get())) {
          return x->get();
        }
        refuse_value(node, where, info, "takes a finite number");
      case ValueType::flag:
        if (const auto* b = node.as_boolean()) return b->get();
        refuse_value(node, where, info, "takes true or false");
      case ValueType::numbers: {
        const auto* list = node.as_array();
        std::vector<double> numbers;
        if (list != nullptr) {
          for (const toml::node& element : *list) {
            if (element.is_integer())
              numbers.push_back(static_cast<double>(*element.value<std::int64_t>()));
            else if (element.is_floating_point())
              numbers.push_back(*element.value<double>());
            else
              refuse_value(node, where, info, "takes a list of numbers");
          }
          return numbers;
        }
        refuse_value(node, where, info, "takes a list of numbers");
      }
      case ValueType::cadence:
        if (const auto* i = node.as_integer(); i != nullptr && i->get() > 0) return i->get();
        if (const auto* s = node.as_string()) {
          try {
            checkpoint_cadence(s->get());
          } catch (const RequestError& e) {
            refuse_value(node, where, info, e.what());
          }
          return s->get();
        }
        refuse_value(node, where, info,
                     "takes a number of events (1000000) or of seconds (\"600s\")");
      case ValueType::choice:
        if (const auto* s = node.as_string(); s != nullptr && is_choice(info.key, s->get())) {
          return s->get();
        }
        refuse_value(node, where, info, "takes " + choices(info.key));
      case ValueType::text:
        if (const auto* s = node.as_string(); s != nullptr && !s->get().empty()) return s->get();
        refuse_value(node, where, info, "takes a file name");
      case ValueType::file_name:
        if (const auto* s = node.as_string()) {
          const std::string& file = s->get();
          if (file.empty() || file.find('/') != std::string::npos || file == "." || file == "..") {
            refuse_value(
                node, where, info,
                "takes a file name, without a folder: the file is written in each task's folder");
          }
          for (const char* own : task_files::kOwn) {
            if (file == own)
              refuse_value(node, where, info,
                           fmt::format("{} is a file the sweep writes itself", own));
            if (AtomicFile::is_temporary_of(file, own)) {
              refuse_value(node, where, info,
                           fmt::format("{} is the name of a temporary file of the sweep's {}, "
                                       "which a resumed task removes",
                                       file, own));
            }
          }
          return file;
        }
        refuse_value(node, where, info, "takes a file name");
    }
    refuse_value(node, where, info, "?");
    return false;
  }

 private:
  std::string name_;
};

// The keys of a table in the order the plan writes them.
std::vector<std::pair<std::string, const toml::node*>> in_order(const toml::table& table) {
  std::vector<std::pair<std::string, const toml::node*>> keys;
  for (const auto& [key, node] : table) keys.emplace_back(std::string(key.str()), &node);
  std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) {
    return line_of(*a.second) < line_of(*b.second);
  });
  return keys;
}

constexpr std::size_t kMostTasks = 100'000;

struct Axis {
  std::string key;
  bool in_start = false;  // else the run's or the compression's
  int line = 0;
  std::vector<PlanValue> values;
};

}  // namespace

SweepPlan SweepPlan::read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PlanError(fmt::format("cannot read the plan {}", path));
  std::ostringstream text;
  text << in.rdbuf();
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  return parse(text.str(), path, folder.empty() ? std::string(".") : folder.string());
}

SweepPlan SweepPlan::parse(std::string_view text, const std::string& name,
                           const std::string& folder) {
  const Reader reader(name);
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    reader.fail(static_cast<int>(e.source().begin.line), std::string(e.description()));
  }
  SweepPlan plan;
  plan.name_ = name;
  plan.text_ = std::string(text);
  plan.folder_ = folder;

  for (const auto& [key, node] : in_order(root)) {
    if (key != "start" && key != "run" && key != "compress" && key != "sweep") {
      reader.fail(line_of(*node), fmt::format("unknown section [{}]: a plan has [start], [run] or "
                                              "[compress], and [sweep]",
                                              key));
    }
    if (!node->is_table()) {
      reader.fail(line_of(*node), fmt::format("{} must be a section, [{}]", key, key));
    }
  }
  const toml::table* start = root["start"].as_table();
  const toml::table* run = root["run"].as_table();
  const toml::table* compress = root["compress"].as_table();
  if (start == nullptr) reader.fail(1, "no [start]: carom init's options, or file = \"START\"");
  if ((run == nullptr) == (compress == nullptr)) {
    reader.fail(1,
                "a plan has one of [run] (carom run's options) and [compress] (carom "
                "compress's)");
  }
  plan.kind_ = run != nullptr ? TaskKind::run : TaskKind::compress;
  const toml::table& action = run != nullptr ? *run : *compress;
  const Section action_section = run != nullptr ? Section::run : Section::compress;
  const std::string_view action_name = sweep::section_name(action_section);
  const Section start_section = start->contains("file") ? Section::start_file : Section::init;

  // The settings every task shares.
  std::vector<PlanSetting> fixed_start, fixed_action;
  for (const auto& [key, node] : in_order(*start)) {
    const std::optional<KeyInfo> info = find_key(start_section, key);
    if (!info) {
      reader.fail(line_of(*node),
                  start_section == Section::start_file && find_key(Section::init, key)
                      ? fmt::format("[start] {}: a start read from a file takes no carom init "
                                    "options (put carom run's in [run])",
                                    key)
                      : fmt::format("[start] {}: not an option of carom init", key));
    }
    fixed_start.push_back({key, reader.value(*info, *node, "start"), line_of(*node)});
  }
  for (const auto& [key, node] : in_order(action)) {
    const std::optional<KeyInfo> info = find_key(action_section, key);
    if (!info) {
      const auto why = action_section == Section::run ? sweep::refused_run_key(key) : std::nullopt;
      reader.fail(line_of(*node), why ? fmt::format("[run] {}: {}", key, *why)
                                      : fmt::format("[{}] {}: not an option of carom {}",
                                                    action_name, key, action_name));
    }
    fixed_action.push_back({key, reader.value(*info, *node, action_name), line_of(*node)});
  }

  std::vector<Axis> axes;
  if (const toml::table* swept = root["sweep"].as_table()) {
    for (const auto& [key, node] : in_order(*swept)) {
      Axis axis{key, false, line_of(*node), {}};
      std::optional<KeyInfo> info;
      if (start_section == Section::init) info = find_key(Section::init, key);
      axis.in_start = info.has_value();
      if (!info) info = find_key(action_section, key);
      if (!info) {
        reader.fail(axis.line,
                    fmt::format("[sweep] {}: not an option of [start] or [{}]", key, action_name));
      }
      const std::vector<PlanSetting>& fixed = axis.in_start ? fixed_start : fixed_action;
      for (const PlanSetting& s : fixed) {
        if (s.key == key) {
          reader.fail(axis.line, fmt::format("[sweep] {}: also set on line {}; a key is set or "
                                             "swept, not both",
                                             key, s.line));
        }
      }
      const toml::array* values = node->as_array();
      if (values == nullptr || values->empty()) {
        reader.fail(
            axis.line,
            fmt::format("[sweep] {}: an axis is a non-empty list of values, {} = [...]", key, key));
      }
      std::set<std::string> seen;
      for (const toml::node& element : *values) {
        axis.values.push_back(reader.value(*info, element, "sweep"));
        if (!seen.insert(sweep::value_text(axis.values.back())).second) {
          reader.fail(line_of(element), fmt::format("[sweep] {}: {} is listed twice", key,
                                                    sweep::value_text(axis.values.back())));
        }
      }
      plan.axes_.push_back(key);
      axes.push_back(std::move(axis));
    }
  }

  const auto has = [&](const std::vector<PlanSetting>& fixed, bool in_start, std::string_view key) {
    return std::any_of(fixed.begin(), fixed.end(), [&](const auto& s) { return s.key == key; }) ||
           std::any_of(axes.begin(), axes.end(),
                       [&](const Axis& a) { return a.in_start == in_start && a.key == key; });
  };
  if (start_section == Section::init) {
    for (const char* needed : {"n", "phi"}) {
      if (!has(fixed_start, true, needed)) {
        reader.fail(line_of(*start), fmt::format("[start] needs {} (carom init --{}), set or swept",
                                                 needed, needed));
      }
    }
  }
  if (plan.kind_ == TaskKind::run && !has(fixed_action, false, "end_time")) {
    reader.fail(line_of(action), "[run] needs end_time, set or swept");
  }
  if (plan.kind_ == TaskKind::compress && !has(fixed_action, false, "phi") &&
      !has(fixed_action, false, "jam")) {
    reader.fail(line_of(action),
                "[compress] needs phi (the packing fraction to stop at) or "
                "jam = true");
  }

  // A product too large to list is refused before it is made (a plan that asks for it is a
  // mistake; a study that large is several plans).
  double count = 1.0;
  for (const Axis& axis : axes) count *= static_cast<double>(axis.values.size());
  if (count > static_cast<double>(kMostTasks)) {
    reader.fail(axes.front().line,
                fmt::format("[sweep] makes {:.0f} tasks, more than a plan may have ({}): split it "
                            "into several plans",
                            count, kMostTasks));
  }

  // The Cartesian product, the first axis outermost.
  std::vector<std::size_t> at(axes.size(), 0);
  while (true) {
    SweepTask task{"", {}, fixed_start, fixed_action};
    for (std::size_t a = 0; a < axes.size(); ++a) {
      const PlanValue& value = axes[a].values[at[a]];
      const PlanSetting setting{axes[a].key, value, axes[a].line, true};
      (axes[a].in_start ? task.start : task.action).push_back(setting);
      task.point.emplace_back(axes[a].key, sweep::value_text(value));
      task.name += fmt::format("{}{}={}", a == 0 ? "" : ",", axes[a].key, sweep::value_text(value));
    }
    if (task.name.empty()) task.name = "task";
    for (char& c : task.name) c = c == '/' || c == ' ' ? '_' : c;
    sweep::task_spec(plan, task, "DIR");  // refuses what the task's run would refuse
    plan.tasks_.push_back(std::move(task));
    std::size_t a = axes.size();
    while (a > 0 && ++at[a - 1] == axes[a - 1].values.size()) at[--a] = 0;
    if (a == 0) break;
  }
  return plan;
}

}  // namespace carom
