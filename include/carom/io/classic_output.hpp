// The classic assignment's outputs and start files: the particle table and csv of a run's result,
// the step-by-step trace, and the classic input format written back (carom init's and carom
// compress's starts). Disks print (x, y), spheres (x, y, z).
#pragma once

#include <cstddef>
#include <ostream>
#include <span>
#include <string>

#include "carom/core/system.hpp"
#include "carom/engine/simulation.hpp"

namespace carom {

// `particle %d: (%.6f, %.6f) (%.6f, %.6f): %.6f : (%d, %d)`, without a newline.
template <std::size_t D>
std::string particle_line(std::size_t index, const Particle<D>& p, const ParticleRecord& record);

// The header `particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)`, then one
// particle_line a particle: the stored (lazy) states, each at its absolute stored time (the
// classic assignment's trace).
template <std::size_t D>
void write_table(std::ostream& out, const System<D>& system);

// One line a particle: `%.6f, %.6f, %d, %d` (x, y, wall collisions, particle collisions).
template <std::size_t D>
void write_csv(std::ostream& out, std::span<const Particle<D>> particles,
               std::span<const ParticleRecord> records);

// The table and the csv of every particle at the simulation's time, brought there one at a
// time: a result of 10^6 particles costs no copy of the state.
template <std::size_t D>
void write_table(std::ostream& out, const Simulation<D>& simulation);
template <std::size_t D>
void write_csv(std::ostream& out, const Simulation<D>& simulation);

// The step-by-step trace users compare their own programs against: `Input File:`, `Target
// Time:` and the initial particles; after every event its time, what collided and every
// particle's stored state; at the end every particle brought to the end time.
template <std::size_t D>
class TraceWriter final : public Observer<D> {
 public:
  explicit TraceWriter(std::ostream& out) : Observer<D>(Trigger::each_event()), out_(out) {}
  void start(const std::string& input, double end_time, const Simulation<D>& simulation);
  void observe(const Simulation<D>& simulation) override;
  void finish(const Simulation<D>& simulation);

 private:
  std::ostream& out_;
};

// A system in the classic input format, every number in its shortest form that reads back as the
// same double. Particles whose radius differs from `radius`, or whose mass is not 1, carry the
// optional columns `r [m]`. Spheres have three box sides and `x y z vx vy vz` lines.
template <std::size_t D>
void write_classic(std::ostream& out, const System<D>& system, double radius);
// A start as carom init and carom compress write it: the line recording its boundary and `rule`
// (start_record_line), then the classic lines with R the particles' common radius, or their mean
// when they differ (those particles then carry their own).
template <std::size_t D>
void write_start(std::ostream& out, const System<D>& system, Rule rule);

}  // namespace carom
