// Where a run begins, in no particular dimension: a start file (classic, or a frame of a GSD file)
// read with carom run's options, a checkpoint continued, carom init's options, or arrays. The
// dimension is chosen here, once, from what is read; every front end then holds an AnySimulation.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "carom/engine/initial.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/run/any_simulation.hpp"

namespace carom {

// A start named on a command line: `FILE.gsd` or `FILE.gsd:K` (frame K) is read by
// read_gsd_start, anything else as a classic file (read_any_classic_file) in `boundary`. A GSD
// frame's box is its own: a `boundary` that differs from it is an InputError.
AnyClassicInput read_any_start_file(const std::string& spec,
                                    std::optional<Boundary> boundary = std::nullopt);

// The file a start spec names: FILE.gsd for FILE.gsd:K, else the spec itself.
std::string start_file_path(const std::string& spec);

// The particles and box of a start file (read_any_start_file), in either dimension.
AnySystem read_start_system(const std::string& spec,
                            std::optional<Boundary> boundary = std::nullopt);

// Lees-Edwards shear asked of a start (`carom run --shear RATE [--velocity-profile]`): the box's
// shear rate (Box::shear_rate), and whether the particles start streaming with the profile
// u_x = RATE (y - Ly / 2) added to their velocities, so that the run begins without a shock.
struct ShearRequest {
  double rate = 0.0;  // 0: none
  bool profile = false;
};

// Checks a shear request: RequestError, naming the option, for a rate that is not a finite number
// or a profile without a rate.
ShearRequest shear_request(std::optional<double> rate, bool profile);

// RequestError, naming the options, for a shear (a rate other than 0) of a box with walls or under
// a rule other than elastic: what a start made with `shear` refuses, checked before it is made.
void check_shear_box(const ShearRequest& shear, bool periodic, Rule rule);

// RequestError unless `dimension` is 2 (disks) or 3 (spheres).
void require_dimension(std::int64_t dimension);

// How to read a start file: carom run's FILE and options (carom.read's arguments).
struct StartSpec {
  std::string path;                  // see read_any_start_file; "-" reads standard input
  std::optional<Boundary> boundary;  // nullopt: what the file records, else walls
  std::optional<Rule> rule;          // nullopt: default_rule (the file's record, the box, ...)
  double restitution = 1.0;
  double tc = kDefaultTc;
  EngineKind engine = EngineKind::fast;
  std::optional<double> temperature;  // new Maxwell-Boltzmann velocities at this kT
  std::uint64_t seed = 1;             // of those velocities
  Thermostat thermostat;              // none (thermostat_request makes one)
  ShearRequest shear;                 // none
  SamplerKind sampler = SamplerKind::md;
  double chain_length = 0.0;  // event chains': in mean diameters (0: default_chain_length)
};

// The thermostat `carom run --thermostat KIND --kT T [--thermostat-every DT] [--thermostat-rate
// NU] [--seed S]` asks for (Python's the same by keyword); Andersen's without an interval resets
// particles one at a time, as events. Throws RequestError, naming the options, for a thermostat
// without its temperature, rescaling without its interval, a rate without Andersen's, an
// Andersen's without a rate, or values check_thermostat refuses; first of all for a thermostat of
// event chains (`sampler`).
Thermostat thermostat_request(ThermostatKind kind, std::optional<double> kT,
                              std::optional<double> every, std::optional<double> rate,
                              std::uint64_t seed, SamplerKind sampler);

// Throws RequestError, naming the options, when `settings` ask for event chains and the run asks
// for what only dynamics has: a box with walls (`periodic` false), a shear, a thermostat, a
// restitution below 1, a collision rule or engine named (`rule_named`), or velocities drawn
// (`draws_velocities`); or a chain length without event chains.
void check_sampler_request(const Settings& settings, bool periodic, const ShearRequest& shear,
                           bool rule_named, bool draws_velocities);

// A run made ready to go.
struct Start {
  AnySimulation simulation;
  std::string input;     // what was read: the start file or the checkpoint
  std::string source;    // the file the run began from (a checkpoint records it)
  bool resumed = false;  // continues a checkpoint: its outputs continue their files
  std::string note;      // what reading decided without being asked, and why ("" if nothing)
  std::optional<std::uint64_t> seed;  // of the velocities drawn, if any were
  WindowRecords records;              // a checkpoint's: its run's window records so far
};

// Reads a start file. Throws InputError for a broken file, RequestError for options it cannot
// take (a temperature no velocities can have), std::invalid_argument for settings check_settings
// refuses or a system no engine can run.
Start load_start(const StartSpec& spec);
// Continues the checkpoint at `path` exactly (its rule, boundary and engine apply).
Start resume_start(const std::string& path);

// What `carom init` makes: `options`'s particles in `dimension` (2: disks; 3: spheres), for a
// run under `rule` (the rule its file records).
struct InitSpec {
  int dimension = 2;
  InitialOptions options;
  Rule rule = Rule::elastic;  // the physical rule, which the classic assignment's swap is not
};

// carom init's start of `dimension` (2 or 3), run with `settings`. Throws InitialError when the
// options cannot be met, RequestError for another dimension.
Start init_start(int dimension, const InitialOptions& options, const Settings& settings,
                 const ShearRequest& shear = {});

// Particles held as arrays by a caller (numpy's, say): row-major (N, D) positions and
// velocities, the D box sides, N radii and N masses, and their types: the names, and N indices
// into them (null: every particle of the first).
struct ParticleArrays {
  int dimension = 2;
  std::size_t n = 0;
  const double* positions = nullptr;
  const double* velocities = nullptr;
  const double* box = nullptr;
  const double* radii = nullptr;
  const double* masses = nullptr;
  std::vector<std::string> type_names{"A"};
  const std::uint32_t* types = nullptr;
  Boundary boundary = Boundary::periodic;  // as carom init's: walls on request
};
// A start from arrays, checked as a start file is (check_start: InputError naming the particle).
Start arrays_start(const ParticleArrays& arrays, const Settings& settings,
                   const ShearRequest& shear = {});

}  // namespace carom
