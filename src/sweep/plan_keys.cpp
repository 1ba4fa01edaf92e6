#include "plan_keys.hpp"

#include <array>

namespace carom::sweep {

namespace {

using enum Section;
using enum ValueType;

// The order is carom's help's: task_commands() writes options in the plan's order anyway.
constexpr std::array kKeys = {
    KeyInfo{"dim", init, integer},
    KeyInfo{"n", init, integer},
    KeyInfo{"phi", init, number},
    KeyInfo{"box", init, numbers},
    KeyInfo{"aspect", init, number},
    KeyInfo{"radius", init, number},
    KeyInfo{"polydispersity", init, number},
    KeyInfo{"species", init, text},
    KeyInfo{"kT", init, number},
    KeyInfo{"seed", init, integer},
    KeyInfo{"boundary", init, choice},
    KeyInfo{"lattice", init, flag},
    KeyInfo{"random", init, flag},
    KeyInfo{"file", start_file, text},
    KeyInfo{"end_time", run, number},
    KeyInfo{"equilibrate", run, number},
    KeyInfo{"rule", run, choice},
    KeyInfo{"restitution", run, number},
    KeyInfo{"tc", run, number},
    KeyInfo{"boundary", run, choice},
    KeyInfo{"engine", run, choice},
    KeyInfo{"kT", run, number},
    KeyInfo{"seed", run, integer},
    KeyInfo{"dump", run, file_name},
    KeyInfo{"every", run, number},
    KeyInfo{"events", run, file_name},
    KeyInfo{"final", run, file_name},
    KeyInfo{"log_every", run, number},
    KeyInfo{"checkpoint_every", run, cadence},
    KeyInfo{"check", run, flag},
    KeyInfo{"check_every", run, integer},
    KeyInfo{"transport", run, flag},
    KeyInfo{"thermostat", run, choice},
    KeyInfo{"thermostat_every", run, number},
    KeyInfo{"thermostat_rate", run, number},
    KeyInfo{"shear", run, number},
    KeyInfo{"velocity_profile", run, flag},
    KeyInfo{"sampler", run, choice},
    KeyInfo{"chain_length", run, number},
    KeyInfo{"phi", compress, number},
    KeyInfo{"jam", compress, flag},
    KeyInfo{"rate", compress, number},
    KeyInfo{"boundary", compress, choice},
    KeyInfo{"kT", compress, number},
    KeyInfo{"jam_pressure", compress, number},
    KeyInfo{"engine", compress, choice},
    KeyInfo{"unit_diameter", compress, flag},
};

struct Refusal {
  std::string_view key, why;
};
constexpr std::array kRefusedRunKeys = {
    Refusal{"summary", "the sweep writes each task's summary to DIR/<task>/summary.json"},
    Refusal{"log", "the sweep writes each task's time series to DIR/<task>/log.csv"},
    Refusal{"checkpoint", "the sweep saves each task's state to DIR/<task>/checkpoint.ckpt"},
    Refusal{"output", "a task's results are its summary.json and a row of DIR/results.csv"},
    Refusal{"format", "a task's results are its summary.json and a row of DIR/results.csv"},
    Refusal{"resume", "the sweep continues every interrupted task from its checkpoint itself"},
    Refusal{"trace", "a task's step-by-step trace is what carom run --trace prints: run it alone"},
    Refusal{"quiet", "give it to carom sweep (-q)"},
    Refusal{"progress", "give it to carom sweep (--progress)"},
};

}  // namespace

std::optional<KeyInfo> find_key(Section section, std::string_view key) {
  for (const KeyInfo& info : kKeys) {
    if (info.section == section && info.key == key) return info;
  }
  return std::nullopt;
}

std::optional<std::string_view> refused_run_key(std::string_view key) {
  for (const Refusal& refusal : kRefusedRunKeys) {
    if (refusal.key == key) return refusal.why;
  }
  return std::nullopt;
}

std::string_view section_name(Section section) {
  switch (section) {
    case init:
    case start_file:
      return "start";
    case run:
      return "run";
    case compress:
      return "compress";
  }
  return "?";
}

}  // namespace carom::sweep
