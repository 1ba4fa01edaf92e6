// Reading a plan: TOML (toml++) into settings, the axes' Cartesian product into tasks, and every
// task checked by what will run it, so that a bad plan is refused before anything runs.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

#include "carom/core/names.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/atomic_file.hpp"
#include "carom/run/start.hpp"
#include "plan_keys.hpp"
#include "task_spec.hpp"

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
  if (key == "sampler") return from_name<SamplerKind>(name).has_value();
  return from_name<EngineKind>(name).has_value();
}

std::string choices(std::string_view key) {
  if (key == "rule") return names_list<Rule>();
  if (key == "boundary") return names_list<Boundary>();
  if (key == "thermostat") return names_list<ThermostatKind>();
  if (key == "sampler") return names_list<SamplerKind>();
  return names_list<EngineKind>();
}

// The longest file name (of one folder's entry) that file systems take.
constexpr std::size_t kLongestFileName = 255;

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

  // A file name is written into task.txt (a command a line) and results.csv (a row a line): a
  // line break or another control character in it would break their lines.
  void refuse_control_characters(const toml::node& node, std::string_view where,
                                 const KeyInfo& info, const std::string& file) const {
    if (std::any_of(file.begin(), file.end(),
                    [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; })) {
      refuse_value(node, where, info,
                   "takes a file name without line breaks, tabs or other control characters");
    }
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
          if (!numbers.empty()) return numbers;
        }
        refuse_value(node, where, info, "takes a list of numbers, one a side of the box");
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
        if (const auto* s = node.as_string(); s != nullptr && !s->get().empty()) {
          refuse_control_characters(node, where, info, s->get());
          return s->get();
        }
        refuse_value(node, where, info, "takes a file name");
      case ValueType::file_name:
        if (const auto* s = node.as_string()) {
          const std::string& file = s->get();
          refuse_control_characters(node, where, info, file);
          if (file.empty() || file.find('/') != std::string::npos || file == "." || file == "..") {
            refuse_value(
                node, where, info,
                "takes a file name, without a folder: the file is written in each task's folder");
          }
          if (file.size() > kLongestFileName) {
            refuse_value(node, where, info,
                         fmt::format("takes a file name of at most {} bytes (what file systems "
                                     "take), not {}",
                                     kLongestFileName, file.size()));
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

// The deepest a plan may nest. A plan's keys are a section's (two parts) and its values lists of
// numbers (one more level): anything much deeper is a mistake or an attack, and toml++ recurses
// once for each part of a dotted key or table header, which 100,000 parts overflow the stack with.
constexpr int kDeepestNesting = 32;

// Refuses (PlanError, at its line) a text that nests deeper than kDeepestNesting anywhere: the
// parts of the table header and of the key a value is under, plus the lists and inline tables
// open around it. A lexical scan before toml++ sees the text, strings and comments skipped; it
// counts a dot of any key as a level, so it errs towards counting too deep, never too shallow.
void check_nesting(std::string_view text, const Reader& reader) {
  struct Open {
    char bracket;     // '[' a list, '{' an inline table
    int outer_depth;  // the key depth where it opened
  };
  std::vector<Open> open;
  int header_depth = 0;  // the parts of the last table header, less one
  int key_depth = 0;     // the parts of the key being read (or read), less one, and the header's
  bool in_key = true;    // at a key (or a header): its dots nest
  bool in_header = false;
  int line = 1;
  const auto skip_string = [&](std::size_t& at) {
    const char quote = text[at];
    const bool multi_line = text.substr(at, 3) == std::string(3, quote);
    const std::string_view end = multi_line ? text.substr(at, 3) : text.substr(at, 1);
    for (at += end.size(); at < text.size(); ++at) {
      if (text[at] == '\n') ++line;
      if (quote == '"' && text[at] == '\\') {
        ++at;
      } else if (text.substr(at, end.size()) == end) {
        at += end.size() - 1;
        return;
      }
    }
  };
  for (std::size_t at = 0; at < text.size(); ++at) {
    const char c = text[at];
    if (c == '\n') {
      ++line;
      if (open.empty()) {
        in_key = true;
        in_header = false;
        key_depth = header_depth;
      }
    } else if (c == '#') {
      while (at + 1 < text.size() && text[at + 1] != '\n') ++at;
    } else if (c == '"' || c == '\'') {
      skip_string(at);
    } else if (c == '[' && open.empty() && in_key) {
      // A table header, [a.b] or [[a.b]]: its parts nest the keys under it.
      if (!in_header) header_depth = key_depth = 0;
      in_header = true;
    } else if (c == ']' && in_header) {
      header_depth = key_depth;
    } else if (c == '.' && in_key) {
      ++key_depth;
    } else if (c == '=' && in_key) {
      in_key = false;
    } else if (c == '[' || c == '{') {
      open.push_back({c, key_depth});
      in_key = c == '{';
    } else if ((c == ']' || c == '}') && !open.empty()) {
      key_depth = open.back().outer_depth;
      open.pop_back();
      in_key = false;
    } else if (c == ',' && !open.empty() && open.back().bracket == '{') {
      key_depth = open.back().outer_depth;
      in_key = true;
    }
    if (static_cast<int>(open.size()) + key_depth + 1 > kDeepestNesting) {
      reader.fail(line, fmt::format("nesting deeper than {} (a dotted key, table header or list "
                                    "this deep): a plan's keys and lists nest 3 deep at most",
                                    kDeepestNesting));
    }
  }
}

constexpr std::size_t kMostTasks = 100'000;

// A task folder's name is at most this long, well inside kLongestFileName.
constexpr std::size_t kLongestFolderName = 200;

// FNV-1a, 64 bits: the same on every machine, so that a task's folder is found again.
std::uint64_t fnv1a(std::string_view bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

// Whether a character is kept as it is in a folder's name: ',' and '=' part the point's keys and
// values, and '~' marks a hashed name, so a value holding them (a file name) is not kept as is.
bool kept_in_folder_name(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '+' ||
         c == '-';
}

// The folder of a task at `point` ("phi=0.3,seed=1"; a list's numbers joined by '_'; "task" when
// nothing is swept). Distinct points have distinct folders: a name that would lose a character
// (a file name's space, slash or non-ASCII byte becomes '_') or be longer than
// kLongestFolderName keeps a readable start and ends in '~' and a hash of the whole point.
std::string folder_name(const std::vector<std::pair<std::string, std::string>>& point,
                        const std::vector<const PlanValue*>& values) {
  if (point.empty()) return "task";
  std::string name, whole;
  bool lossless = true;
  for (std::size_t a = 0; a < point.size(); ++a) {
    const auto& [key, text] = point[a];
    name += fmt::format("{}{}=", a == 0 ? "" : ",", key);
    whole += fmt::format("{}={}{}", key, text, '\0');
    const bool numbers = std::holds_alternative<std::vector<double>>(*values[a]);
    for (const char c : text) {
      const bool kept = kept_in_folder_name(c) || (numbers && c == ' ');
      lossless = lossless && kept;
      name += kept_in_folder_name(c) ? c : '_';
    }
  }
  if (lossless && name.size() <= kLongestFolderName) return name;
  const std::string hash = fmt::format("~{:016x}", fnv1a(whole));
  return name.substr(0, kLongestFolderName - hash.size()) + hash;
}

// Where a swept key goes: carom init's start, the run or compression, or the compression of a
// run's start.
enum class Goes { start, action, compression };

struct Axis {
  std::string key;
  Goes goes = Goes::action;
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
  check_nesting(text, reader);
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
  if (run == nullptr && compress == nullptr) {
    reader.fail(1,
                "a plan has [run] (carom run's options), [compress] (carom compress's), or both "
                "(each run from its start compressed)");
  }
  plan.kind_ = run != nullptr ? TaskKind::run : TaskKind::compress;
  plan.compresses_start_ = run != nullptr && compress != nullptr;
  const toml::table& action = run != nullptr ? *run : *compress;
  const Section action_section = run != nullptr ? Section::run : Section::compress;
  const std::string_view action_name = sweep::section_name(action_section);
  const Section start_section = start->contains("file") ? Section::start_file : Section::init;

  // The settings every task shares.
  std::vector<PlanSetting> fixed_start, fixed_action, fixed_compression;
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
  if (const toml::node* file = start->get("file"); file != nullptr && file->is_string()) {
    // Read now, once: a start no task could read is refused before any runs, and its boundary
    // and rule are what the tasks' checks take.
    const std::string path = (std::filesystem::path(folder) / *file->value<std::string>()).string();
    try {
      std::visit(
          [&](const auto& input) {
            plan.start_file_record_ = {input.system.box.boundary, input.record.rule, {}};
          },
          read_any_start_file(path));
    } catch (const std::exception& e) {  // InputError, or a file that cannot be opened
      reader.fail(line_of(*file), fmt::format("[start] file: {}", e.what()));
    }
  }
  const auto read_section = [&](const toml::table& table, Section section,
                                std::vector<PlanSetting>& fixed) {
    const std::string_view name = sweep::section_name(section);
    for (const auto& [key, node] : in_order(table)) {
      const std::optional<KeyInfo> info = find_key(section, key);
      if (!info) {
        const auto why = section == Section::run ? sweep::refused_run_key(key) : std::nullopt;
        reader.fail(line_of(*node),
                    why ? fmt::format("[run] {}: {}", key, *why)
                        : fmt::format("[{}] {}: not an option of carom {}", name, key, name));
      }
      fixed.push_back({key, reader.value(*info, *node, name), line_of(*node)});
    }
  };
  read_section(action, action_section, fixed_action);
  if (plan.compresses_start_) read_section(*compress, Section::compress, fixed_compression);
  const auto fixed_of = [&](Goes goes) -> std::vector<PlanSetting>& {
    return goes == Goes::start    ? fixed_start
           : goes == Goes::action ? fixed_action
                                  : fixed_compression;
  };

  // carom compress gives the particles new velocities at its own kT: after carom init, init's kT
  // would be erased, so there kT is the compression's.
  const bool compresses_init = start_section == Section::init &&
                               (plan.kind_ == TaskKind::compress || plan.compresses_start_);
  if (compresses_init) {
    for (const PlanSetting& s : fixed_start) {
      if (s.key == "kT") {
        reader.fail(s.line,
                    "[start] kT: the compression gives the particles new velocities at "
                    "[compress] kT (default 1), so carom init's would be lost: set it there");
      }
    }
  }
  std::vector<Axis> axes;
  if (const toml::table* swept = root["sweep"].as_table()) {
    for (const auto& [key, node] : in_order(*swept)) {
      Axis axis{key, Goes::action, line_of(*node), {}};
      // A key of carom init's goes to the start, but kT after carom init goes to the compression
      // (above); of a run from a compressed start, `phi` and kT are the compression's (the
      // packing the run is at; [start]'s phi is the gas's), and a key of carom compress's alone
      // (rate, jam_pressure, unit_diameter) is too.
      std::optional<KeyInfo> info;
      const bool compression_key = plan.compresses_start_ && (key == "phi" || key == "kT");
      if (start_section == Section::init && !compression_key && !(compresses_init && key == "kT")) {
        info = find_key(Section::init, key);
        if (info) axis.goes = Goes::start;
      }
      if (!info && !compression_key) info = find_key(action_section, key);
      if (!info && plan.compresses_start_) {
        info = find_key(Section::compress, key);
        axis.goes = Goes::compression;
      }
      if (!info) {
        reader.fail(
            axis.line,
            plan.compresses_start_
                ? fmt::format("[sweep] {}: not an option of [start], [compress] or [run]", key)
                : fmt::format("[sweep] {}: not an option of [start] or [{}]", key, action_name));
      }
      for (const PlanSetting& s : fixed_of(axis.goes)) {
        if (s.key == key) {
          reader.fail(axis.line, fmt::format("[sweep] {}: also set on line {}; a key is set or "
                                             "swept, not both",
                                             key, s.line));
        }
      }
      // The box's boundary and the velocities' kT are the particles' as a command leaves them:
      // a later command that sets its own replaces the swept one, and the tasks would not differ.
      if (key == "boundary" || key == "kT") {
        const auto later = [&](Goes goes) {
          return axis.goes == Goes::start ? goes != Goes::start
                                          : axis.goes == Goes::compression && goes == Goes::action;
        };
        for (const Goes goes : {Goes::compression, Goes::action}) {
          if (!later(goes)) continue;
          for (const PlanSetting& s : fixed_of(goes)) {
            if (s.key != key) continue;
            const Section section = goes == Goes::compression ? Section::compress : action_section;
            reader.fail(axis.line,
                        fmt::format("[sweep] {}: [{}] {} on line {} replaces it in every task, "
                                    "which would not differ: sweep it there, or drop that line",
                                    key, sweep::section_name(section), key, s.line));
          }
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

  // The plan line that sets or sweeps `key` for `goes`, or 0.
  const auto line_setting = [&](Goes goes, std::string_view key) {
    for (const PlanSetting& s : fixed_of(goes)) {
      if (s.key == key) return s.line;
    }
    for (const Axis& a : axes) {
      if (a.goes == goes && a.key == key) return a.line;
    }
    return 0;
  };
  const auto has = [&](Goes goes, std::string_view key) { return line_setting(goes, key) != 0; };
  // The line that sets jam to true for `goes`, or sweeps it with true among its values, or 0 (jam =
  // false is no jam).
  const auto line_jammed = [&](Goes goes) {
    for (const PlanSetting& s : fixed_of(goes)) {
      if (s.key == "jam" && std::get<bool>(s.value)) return s.line;
    }
    for (const Axis& a : axes) {
      const auto jams = [](const PlanValue& v) { return std::get<bool>(v); };
      if (a.goes == goes && a.key == "jam" &&
          std::any_of(a.values.begin(), a.values.end(), jams)) {
        return a.line;
      }
    }
    return 0;
  };
  if (start_section == Section::init) {
    for (const char* needed : {"n", "phi"}) {
      if (!has(Goes::start, needed)) {
        reader.fail(
            line_of(*start),
            plan.compresses_start_ && std::string_view(needed) == "phi"
                ? "[start] needs phi (carom init --phi: the gas each run's start is "
                  "compressed from), set; a swept phi is the compression's"
                : fmt::format("[start] needs {} (carom init --{}), set or swept", needed, needed));
      }
    }
  }
  if (plan.kind_ == TaskKind::run && !has(Goes::action, "end_time")) {
    reader.fail(line_of(action), "[run] needs end_time, set or swept");
  }
  if (plan.kind_ == TaskKind::compress && !has(Goes::action, "phi") &&
      line_jammed(Goes::action) == 0) {
    reader.fail(line_of(action),
                "[compress] needs phi (the packing fraction to stop at) or "
                "jam = true");
  }
  if (plan.compresses_start_) {
    if (const int jam = line_jammed(Goes::compression); jam != 0) {
      reader.fail(jam,
                  "[compress] jam: a run starts from its compression's packing, which must be a "
                  "packing fraction to stop at (phi), not a jammed packing");
    }
    if (!has(Goes::compression, "phi")) {
      reader.fail(line_of(*compress),
                  "[compress] needs phi (the packing fraction each run starts at), set or swept");
    }
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

  const auto seed_axis =
      std::find_if(axes.begin(), axes.end(), [](const Axis& a) { return a.key == "seed"; });
  const int seed_line = seed_axis == axes.end() ? 0 : seed_axis->line;

  // The Cartesian product, the first axis outermost.
  std::vector<std::size_t> at(axes.size(), 0);
  std::unordered_map<std::string, std::size_t> task_of_folder;
  while (true) {
    SweepTask task{"", {}, fixed_start, fixed_action, fixed_compression};
    std::vector<const PlanValue*> values;
    for (std::size_t a = 0; a < axes.size(); ++a) {
      const PlanValue& value = axes[a].values[at[a]];
      const PlanSetting setting{axes[a].key, value, axes[a].line, true};
      (axes[a].goes == Goes::start    ? task.start
       : axes[a].goes == Goes::action ? task.action
                                      : task.compression)
          .push_back(setting);
      task.point.emplace_back(axes[a].key, sweep::value_text(value));
      values.push_back(&value);
    }
    task.name = folder_name(task.point, values);
    if (const auto [named, added] = task_of_folder.emplace(task.name, plan.tasks_.size()); !added) {
      // Two points whose hashes agree (about one chance in 10^9 for 100,000 tasks): refused rather
      // than run in one folder.
      const auto described = [](const SweepTask& t) {
        std::string text;
        for (const auto& [key, value] : t.point) text += fmt::format(" {} = {}", key, value);
        return text;
      };
      reader.fail(axes.front().line,
                  fmt::format("[sweep] the tasks{} and{} would share the folder {}: change a value",
                              described(plan.tasks_[named->second]), described(task), task.name));
    }
    // Refuses what the task's commands would refuse, and a swept seed they would not use.
    if (const auto idle = sweep::task_spec(plan, task, "DIR").idle_seed) {
      reader.fail(seed_line, fmt::format("[sweep] seed (task {}): {}", task.name, *idle));
    }
    plan.tasks_.push_back(std::move(task));
    std::size_t a = axes.size();
    while (a > 0 && ++at[a - 1] == axes[a - 1].values.size()) at[--a] = 0;
    if (a == 0) break;
  }
  plan.measures_ = sweep::measures_of(plan);
  return plan;
}

}  // namespace carom
