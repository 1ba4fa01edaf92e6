// A compression as a whole, in no particular dimension: from a start to a packing and its
// summary, what `carom compress` and carom.compress both do, here once.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "carom/engine/compression.hpp"
#include "carom/run/any_simulation.hpp"

namespace carom {

// What a compression asks for: carom compress's options.
struct CompressionSpec {
  CompressionSettings settings;  // settings.target nullopt: until jammed (--jam)
  bool unit_diameter = false;    // rescale the packing to a mean diameter of 1
  std::string input;             // the start's name, for the summary and messages
};

// What `carom compress --summary` writes and carom.compress returns.
struct CompressionSummary {
  std::string input;
  int dimension = 2;
  std::size_t n = 0;
  Boundary boundary = Boundary::walls;
  std::string status;  // reached_target, jammed, or interrupted (stopped by the flag)
  std::optional<double> target;
  double packing_fraction = 0.0;
  double compressibility_factor = 0.0;
  double rate = 0.0, temperature = 0.0, jammed_pressure = 0.0;
  double time = 0.0;
  std::uint64_t events = 0;
  double grown_diameter = 0.0;  // the packing's mean diameter in the start's unit of length
  double mean_diameter = 0.0;   // in the packing's (1 with unit_diameter)
  bool unit_diameter = false;
  std::vector<double> box;
  double wall_seconds = 0.0;
};

// The json of `carom compress --summary` (and of carom.compress's summary).
void write_json(std::ostream& out, const CompressionSummary& summary);

// Why a compression that jammed before its target failed ("the disks jammed at packing fraction
// 0.84 (Z = 1e+09) before reaching 0.9; the jammed packing is in OUT"), `packing` naming where
// its packing is; nothing when it did not fall short. `carom compress` exits 1 with it, and a
// sweep's compression fails with it.
std::optional<std::string> shortfall(const CompressionSummary& summary, const std::string& packing);
// The same without the packing's file: "the disks jammed at packing fraction 0.84 (Z = 1e+09)
// before reaching 0.9" (a sweep's run from a compressed start keeps no jammed packing).
std::optional<std::string> jammed_short(const CompressionSummary& summary);

struct CompressionProgress {
  double packing_fraction = 0.0, compressibility_factor = 0.0, time = 0.0;
  std::uint64_t events = 0;
};

struct CompressionHooks {
  const std::atomic<int>* stop = nullptr;  // nonzero stops after the stretch under way
  // Called after every N events.
  std::function<void(const CompressionProgress&)> progress;
};

struct CompressionResult {
  AnySystem packing;  // every particle at the end (t = 0), velocities at the temperature
  CompressionSummary summary;
};

// Grows `start`'s particles as spec says until the target, a jam or a stop. The packing is a
// valid start whatever ended the compression. Throws RequestError ("cannot compress INPUT: ...")
// for what Compression refuses.
CompressionResult compress(AnySystem start, const CompressionSpec& spec,
                           const CompressionHooks& hooks = {});

}  // namespace carom
