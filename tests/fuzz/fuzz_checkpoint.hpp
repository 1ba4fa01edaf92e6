// Fuzzed code paths of the other readers: any bytes as a checkpoint (what is accepted is resumed
// for a few events under the invariant check: it must be a state a run can go on from), and any
// bytes as an extended-XYZ trajectory for `carom view` (what is read is made into the page).
// Shared by the libFuzzer targets and the replay test, so every corpus and regression input also
// runs under plain `make test`.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <variant>

#include "carom/analysis/analysis.hpp"
#include "carom/analysis/viewer.hpp"
#include "carom/engine/invariant_check.hpp"
#include "carom/io/checkpoint.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/gsd.hpp"

namespace carom::fuzz {

struct CheckpointOutcome {
  int refused = 0;  // InputError: refused with a message
  int resumed = 0;  // accepted, and run on for a few events
  int events = 0;
  int jammed = 0;      // JamError, reported
  int violations = 0;  // an accepted checkpoint went back in time or broke an invariant: a bug
};

// Fails (counts a violation) if an event comes before the time the run was resumed at.
template <std::size_t D>
class NotBefore final : public Observer<D> {
 public:
  NotBefore(double time, CheckpointOutcome& outcome)
      : Observer<D>(Trigger::each_event()), time_(time), outcome_(outcome) {}
  void observe(const Simulation<D>& simulation) override {
    ++outcome_.events;
    if (simulation.last_event().time < time_) ++outcome_.violations;
  }

 private:
  double time_;
  CheckpointOutcome& outcome_;
};

template <std::size_t D>
void resume(const Checkpoint<D>& checkpoint, CheckpointOutcome& outcome) {
  if (checkpoint.system.size() > 200) return;  // keep it quick
  double earliest = checkpoint.time;
  for (const Particle<D>& p : checkpoint.system.particles) earliest = std::min(earliest, p.time);
  const double end = std::min(checkpoint.time + 10.0, Simulation<D>::kLatestTime);
  if (most_crossings(checkpoint.system, end - earliest) > 1e5) return;
  ++outcome.resumed;
  try {
    Simulation<D> simulation(checkpoint);
    simulation.add_observer(std::make_shared<NotBefore<D>>(checkpoint.time, outcome));
    simulation.add_observer(std::make_shared<InvariantCheck<D>>(1));
    simulation.run_until(end, 100);
  } catch (const JamError&) {
    ++outcome.jammed;
  } catch (const RunLengthError&) {
    // A run the length guard refuses: not a fault of the checkpoint.
  } catch (const std::exception&) {
    ++outcome.violations;  // InvariantError, or a Simulation refusing what the reader accepted
  }
}

inline CheckpointOutcome checkpoint(const std::uint8_t* data, std::size_t size) {
  CheckpointOutcome outcome;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  AnyCheckpoint read;
  try {
    read = read_checkpoint(in, "fuzz");
  } catch (const InputError&) {
    ++outcome.refused;
    return outcome;
  }
  std::visit([&](const auto& c) { resume(c, outcome); }, read);
  return outcome;
}

struct XyzOutcome {
  int refused = 0;  // InputError
  int frames = 0;   // frames read and made into a page
};

inline XyzOutcome xyz(const std::uint8_t* data, std::size_t size) {
  XyzOutcome outcome;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const std::vector<Frame> frames = read_xyz_frames(in, "fuzz");
    std::ostringstream page;
    write_viewer_html(page, frames);
    outcome.frames = static_cast<int>(frames.size());
  } catch (const InputError&) {
    ++outcome.refused;
  }
  return outcome;
}

struct GsdOutcome {
  int refused = 0;  // InputError
  int started = 0;  // read as a start and run for a few events
  int events = 0;
  int violations = 0;  // an accepted start broke an invariant: a bug
  int analysed = 0;    // read as a trajectory and analysed (carom analyze)
};

// Any bytes as a GSD file (the reader takes a path: they are written to a scratch file first).
// What is accepted as a start runs 50 events under the invariant check; what is accepted as a
// trajectory is analysed as carom analyze does (refusing options it cannot have is fine, any
// other failure is a bug).
inline GsdOutcome gsd(const std::uint8_t* data, std::size_t size) {
  GsdOutcome outcome;
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("carom-fuzz-" + std::to_string(::getpid()) + ".gsd");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const AnyClassicInput start = read_gsd_start(path.string(), std::nullopt);
    std::visit(
        [&](const auto& input) {
          using System = std::remove_cvref_t<decltype(input.system)>;
          if (input.system.size() > 200) return;  // keep it quick
          ++outcome.started;
          try {
            Simulation<System::dimension> simulation(input.system, {{Rule::elastic}});
            simulation.add_observer(std::make_shared<InvariantCheck<System::dimension>>(1));
            // A fast particle in a box too small for five cells renews every prediction each
            // time it could cross half the box: a long run, not a bug (the fuzzer found one).
            if (most_crossings(input.system, 1.0) < 1e3) simulation.run_until(1.0, 50);
            outcome.events = static_cast<int>(simulation.counts().events);
          } catch (const JamError&) {
          } catch (const std::exception&) {
            ++outcome.violations;
          }
        },
        start);
  } catch (const InputError&) {
    ++outcome.refused;
  }
  try {
    const std::vector<Frame> frames = read_gsd_frames(path.string());
    if (frames.front().radius.size() <= 200 && frames.size() <= 20) {
      try {
        analyze(frames, "fuzz.gsd");
        ++outcome.analysed;
      } catch (const std::invalid_argument&) {
      }
    }
  } catch (const InputError&) {
  } catch (const std::exception&) {
    ++outcome.violations;
  }
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
  return outcome;
}

}  // namespace carom::fuzz
