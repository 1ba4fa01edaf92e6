// The fuzzed code path: any bytes as a classic input file (disks or spheres); a valid file is
// then simulated for a few events in both engines (which must agree). Shared by the libFuzzer
// target and the replay test, so every corpus and regression input also runs under plain `make
// test`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <variant>

#include "carom/engine/compression.hpp"
#include "carom/engine/engine.hpp"
#include "carom/engine/overlap.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/run_report.hpp"

namespace carom::fuzz {

// What became of one input, read for walls and for a periodic box (so each counts up to twice).
struct Outcome {
  int refused = 0;     // InputError: refused with a message, as bad input should be
  int simulated = 0;   // read, and run in both engines
  int events = 0;      // events both engines processed, identically
  int jammed = 0;      // JamError: a configuration that cannot move apart, reported
  int mismatches = 0;  // the engines disagreed, or a packing was broken: a bug
  int compressed = 0;  // small systems compressed (to a jam or a bound on the work)
};

// Runs both engines on a system read from fuzzed bytes, for a few events, and compares them.
template <std::size_t D>
void simulate_both(const System<D>& system, Outcome& outcome) {
  if (system.size() > 200) return;  // keep the reference engine cheap
  // Cell crossings are work inside one step: a particle crossing the box 10^10 times between two
  // collisions is a long run, not a bug. The CLI refuses beyond Simulation::kMostCrossings; the
  // fuzzer keeps each input quick.
  constexpr double kEnd = 1e3;
  if (most_crossings(system, kEnd) > 1e5) return;
  ++outcome.simulated;
  for (const Rule rule : {Rule::swap, Rule::elastic}) {
    try {
      auto fast = make_engine(EngineKind::fast, system, {rule});
      auto reference = make_engine(EngineKind::reference, system, {rule});
      for (int e = 0; e < 50; ++e) {
        const auto a = fast->step(kEnd), b = reference->step(kEnd);
        if (a.has_value() != b.has_value() || (a && !(*a == *b && a->impulse == b->impulse))) {
          ++outcome.mismatches;
          break;
        }
        if (!a) break;
        ++outcome.events;
      }
    } catch (const JamError&) {
      ++outcome.jammed;
    } catch (const std::invalid_argument&) {
      ++outcome.refused;  // a periodic box too small for the particles
    }
  }
}

// Compresses a small system (tiny and degenerate ones are where compressions once spun forever
// or wrote files the reader refused): it must end (jammed, or within a bound on the work), and
// whatever it reached must overlap nothing and be a start file the reader reads back.
template <std::size_t D>
void compress_small(const System<D>& system, Outcome& outcome) {
  if (system.size() > 20) return;
  CompressionSettings settings;
  settings.rate = 1.0;
  std::optional<Compression<D>> compression;
  try {
    compression.emplace(system, settings);
  } catch (const std::invalid_argument&) {
    return;  // refused with a reason: overlaps, no motion, a box too small
  }
  try {
    compression->run(20000);
  } catch (const JamError&) {
    return;
  }
  ++outcome.compressed;
  std::stringstream file;
  write_start(file, compression->system(), Rule::elastic);
  try {
    read_classic<D>(file, "packing");
  } catch (const InputError&) {
    ++outcome.mismatches;
  }
  if (find_violation(compression->system(), 0.0)) ++outcome.mismatches;
}

inline Outcome classic_input(const std::uint8_t* data, std::size_t size) {
  Outcome outcome;
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const Boundary boundary : {Boundary::walls, Boundary::periodic}) {
    std::istringstream in(text);
    AnyClassicInput input;
    try {
      input = read_any_classic(in, "fuzz", boundary);
    } catch (const InputError&) {
      ++outcome.refused;
      continue;
    }
    std::visit(
        [&](const auto& read) {
          simulate_both(read.system, outcome);
          compress_small(read.system, outcome);
        },
        input);
  }
  return outcome;
}

}  // namespace carom::fuzz
