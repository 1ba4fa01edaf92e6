// Compression by growing particles (Lubachevsky and Stillinger 1990; the protocol of Skoge,
// Donev, Stillinger and Torquato 2006): every radius grows in time as r_i(t) = r_i(0) (1 + rate t),
// so that size ratios are kept, while the particles move and collide as in any run (collisions and
// wall bounces elastic in the frame of the moving surfaces: see growing_contact_time). Growing
// collisions add energy; the velocities are rescaled to the temperature after every N events.
// Used to make dense fluids, glasses and jammed packings (carom compress, carom.compress).
//
// The run goes in stretches: each starts an engine at the current radii (grown by the growth from
// the start, not by accumulated rounding) and lasts N events, or until the radii have grown by
// 2 %, or until the target; then every particle is brought to its end, the radii are set, the
// velocities rescaled and the compressibility factor of the stretch measured. Everything the class
// reports is at the end of a stretch.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <vector>

#include "carom/core/system.hpp"
#include "carom/engine/engine.hpp"

namespace carom {

// Fast enough that equal spheres jam amorphous (near random close packing, 0.64) rather than
// crystallise; see docs/validation.md for what slower rates give.
inline constexpr double kDefaultGrowthRate = 0.01;
// The compressibility factor Z = PV / NkT at which a packing counts as jammed (Skoge et al.'s
// 10^12), and the most that may be asked for: near 1e15 the gaps are below what doubles resolve.
inline constexpr double kJammedPressure = 1e12;
inline constexpr double kMostJammedPressure = 1e14;
// A packing whose radii have not changed (to the last bit) over this many stretches can grow no
// more: jammed.
inline constexpr int kStalledStretches = 10;

struct CompressionSettings {
  // How fast every diameter grows, per unit time, over its diameter at the start; the thermal
  // speed is sqrt(kT / m) = 1 by default.
  double rate = kDefaultGrowthRate;
  std::optional<double> target;  // the packing fraction to stop at; nullopt: until jammed
  double jammed_pressure = kJammedPressure;
  double temperature = 1.0;  // kT the velocities are rescaled to (masses as in the system)
  EngineKind engine = EngineKind::fast;
};

// The checks Compression's constructor makes of its settings, one at a time, so that a caller can
// make them before it has a start (a sweep plan, at each task's setting): each throws
// std::invalid_argument saying what is wrong. A growth rate, temperature or jamming pressure must
// be a positive number, the last at most kMostJammedPressure.
void check_growth_rate(double rate);
void check_compression_temperature(double temperature);
void check_jammed_pressure(double pressure);
// A target packing fraction must lie above the start's and below what the particles can fill:
// close packing of equal particles in `dimension` dimensions, else a full box.
void check_target_packing(double target, double start_packing, bool equal_particles,
                          std::size_t dimension);

enum class CompressionStatus {
  running,
  reached_target,  // the packing fraction is the target (to rounding)
  jammed,          // Z passed settings.jammed_pressure, or the radii stopped growing
};

template <std::size_t D>
class Compression {
 public:
  // Throws std::invalid_argument for what cannot be compressed: overlapping particles, a target
  // not above the start's packing fraction or beyond what the particles can fill (close packing
  // of equal particles; 1 for unequal ones), a rate or temperature that is not a positive number,
  // a periodic box whose sides will not stay above two diameters, or a start with no motion.
  Compression(System<D> start, const CompressionSettings& settings);

  // Runs whole stretches until at least `events` more events are done, the target is reached,
  // the packing jams or the stop flag is set (looked at between stretches of N events). Returns
  // status().
  CompressionStatus run(std::uint64_t events);
  // A flag the caller owns (as Simulation::set_stop_flag): nonzero stops run() after the stretch
  // under way, the packing whole. nullptr: none.
  void set_stop_flag(const std::atomic<int>* flag) { stop_ = flag; }
  CompressionStatus status() const { return status_; }

  // The packing at the end of the last stretch: every particle at that time (stored time 0), the
  // radii grown, the velocities rescaled to the temperature.
  const System<D>& system() const { return system_; }
  const CompressionSettings& settings() const { return settings_; }
  double time() const { return time_; }
  double packing_fraction() const;
  // Z = PV / NkT over the last stretch, from the collision virial; 0 before any.
  double compressibility_factor() const { return compressibility_factor_; }
  std::uint64_t events() const { return events_; }

 private:
  // Runs one stretch from the current state.
  void stretch();
  // The growth factor of every radius at time t.
  double scale_at(double t) const { return 1.0 + settings_.rate * t; }

  CompressionSettings settings_;
  System<D> system_;
  std::vector<double> initial_radius_;
  double initial_packing_ = 0.0;
  double target_time_ = 0.0;  // when the target is reached (infinite when jamming)
  double time_ = 0.0;
  double compressibility_factor_ = 0.0;
  std::uint64_t events_ = 0;
  double last_scale_ = 0.0;      // the radii's growth factor at the end of the last stretch
  int unchanged_stretches_ = 0;  // stretches since it last changed
  CompressionStatus status_ = CompressionStatus::running;
  const std::atomic<int>* stop_ = nullptr;
};

}  // namespace carom
