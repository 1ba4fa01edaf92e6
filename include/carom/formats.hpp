// Output formats for a 2D run: the seed's table and trace, the classic csv, and json.
#pragma once

#include <cstddef>
#include <ostream>
#include <span>
#include <string>

#include "carom/engine.hpp"
#include "carom/event.hpp"
#include "carom/system.hpp"

namespace carom {

enum class Format { table, csv, json };

// `particle %d: (%.6f, %.6f) (%.6f, %.6f): %.6f : (%d, %d)`, without a newline.
std::string particle_line(std::size_t index, const Particle<2>& p);

// The header `particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)`, then one
// particle_line a disk.
void write_table(std::ostream& out, std::span<const Particle<2>> particles);

// One line a disk: `%.6f, %.6f, %d, %d` (x, y, wall collisions, disk collisions).
void write_csv(std::ostream& out, std::span<const Particle<2>> particles);

// What a json result says about how it was made and how long it took.
struct RunSettings {
  std::string input;
  double end_time = 0.0;
  double equilibrate = 0.0;  // observables are measured from this time on
  CollisionRule rule;
  EngineKind engine = EngineKind::fast;
  double kinetic_energy_initial = 0.0;  // at the start of the measurement
  double wall_seconds = 0.0;            // wall-clock time of the simulation
};

// The settings, the run's counts and observables (see measure()) and, with `particles`, every
// disk's final state; numbers in full precision.
void write_json(std::ostream& out, const RunSettings& settings, const Engine<2>& engine,
                bool particles = true);

// The step-by-step trace users compare their own programs against.
class TraceWriter {
 public:
  explicit TraceWriter(std::ostream& out) : out_(out) {}
  // `Input File:`, `Target Time:` and the initial particles.
  void start(const std::string& input, double end_time, std::span<const Particle<2>> particles);
  // `TIME = t`, the event, and every disk's stored state.
  void event(const Event& event, std::span<const Particle<2>> particles);
  // The particles brought to the end time.
  void finish(std::span<const Particle<2>> particles);

 private:
  std::ostream& out_;
};

// A system in the classic input format, every number in its shortest form that reads back as the
// same double. Disks whose radius differs from `radius`, or whose mass is not
// 1, carry the optional columns `r [m]`.
void write_classic(std::ostream& out, const System<2>& system, double radius);

// One line naming an event: `Collision: particle 1 with particle 2` or
// `Collision: particle 3 with wall -2 (right)`.
std::string describe(const Event& event);

}  // namespace carom
