// The keys a plan may hold, in which section, of what type: the options of carom init, run and
// compress with their dashes dropped and '-' written '_'. One table, read by the plan's parser
// (types, sections, the axes' keys) and by task_spec (what each key sets).
#pragma once

#include <optional>
#include <string_view>

#include "carom/sweep/sweep.hpp"

namespace carom::sweep {

enum class Section { init, start_file, run, compress };

enum class ValueType {
  integer,    // a whole number >= 0
  number,     // any number (an integer is taken as one)
  text,       // a string
  choice,     // a string naming a rule, boundary or engine
  flag,       // true or false (an option without a value)
  numbers,    // a list of numbers (--box)
  cadence,    // a whole number of events or a string "600s" (--checkpoint-every)
  file_name,  // a file name inside the task's folder (no '/')
};

struct KeyInfo {
  std::string_view key;
  Section section;
  ValueType type;
};

// The key `key` of `section`, or nullopt.
std::optional<KeyInfo> find_key(Section section, std::string_view key);

// Whether a [run] key names a file the task writes in its folder (dump, events, final).
inline bool names_a_task_file(std::string_view key) {
  const std::optional<KeyInfo> info = find_key(Section::run, key);
  return info && info->type == ValueType::file_name;
}

// Why a key of carom run's is not a plan's (the sweep writes that file itself, or it is about a
// terminal), or nullopt.
std::optional<std::string_view> refused_run_key(std::string_view key);

// The section's name in the plan: "start", "run", "compress".
std::string_view section_name(Section section);

}  // namespace carom::sweep
