// The simulation engines: a fast one for real work and a simple reference one to check it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string_view>

#include "carom/event.hpp"
#include "carom/physics.hpp"
#include "carom/system.hpp"

namespace carom {

// What a run has counted and accumulated since it started.
struct RunCounts {
  std::uint64_t events = 0;  // processed collisions: wall_collisions + pair_collisions
  std::uint64_t wall_collisions = 0;
  std::uint64_t pair_collisions = 0;
  std::uint64_t elastic_by_tc = 0;  // inelastic collisions made elastic by the TC model
  double virial = 0.0;              // sum over pair collisions of r_ij . (momentum given to i)
  double wall_momentum = 0.0;       // total momentum given to the walls
};

// The particles cannot move apart: collisions keep coming at one instant without end (a disk
// wedged exactly between two walls, say). Thrown instead of spinning forever.
class JamError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class EngineKind {
  fast,       // cell grid, one pending event per particle in a calendar, O(1) per event
  reference,  // the seed's algorithm done right: every pair predicted again after every event
};

// Runs a system event by event. Events are processed in the order of EventKey, only the
// particles involved are moved, and the particles' stored states follow the seed's lazy
// convention (see Particle).
template <std::size_t D>
class Engine {
 public:
  virtual ~Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Processes the earliest pending collision if it happens no later than `end_time` and
  // returns it; otherwise changes nothing and returns nullopt.
  virtual std::optional<Event> step(double end_time) = 0;

  // Brings every particle to `end_time`, which must not precede the last processed event. The run
  // may go on afterwards.
  void finish(double end_time);

  const System<D>& system() const { return system_; }
  const RunCounts& counts() const { return counts_; }
  const CollisionRule& rule() const { return rule_; }
  // The time of the last processed event (the start time before any).
  double time() const { return now_; }

  // Starts counting afresh (after equilibration, say); the dynamics are not affected.
  void reset_counts() { counts_ = {}; }
  // Carries counts over from a checkpoint.
  void restore_counts(const RunCounts& counts) { counts_ = counts; }

 protected:
  // Throws std::invalid_argument for a periodic box with a side not above two diameters.
  Engine(System<D> system, const CollisionRule& rule);
  // Called when every stored state has changed at once (finish): pending predictions are stale.
  virtual void resync() {}
  // Carries out a collision that is due: moves the particles involved to its time, applies the
  // rule or the wall bounce, and counts it.
  void apply(const Event& event);

  // The image of particle j that particle i sees at time t (zero in a box with walls).
  Vec<D> image(std::uint32_t i, std::uint32_t j, double t) const;

  // How long pair predictions made with the images seen at one moment stay right: within this
  // time no pair can travel far enough to touch through another image. Infinite for walls.
  double image_horizon() const;
  // For a horizon too short for a double to advance the time at `t`: the run cannot progress.
  [[noreturn]] void throw_too_fast(double t) const;

  System<D> system_;
  CollisionRule rule_;
  RunCounts counts_;
  double now_ = 0.0;
  std::uint64_t events_at_now_ = 0;  // consecutive events at exactly now_, to detect a jam
};

template <std::size_t D>
std::unique_ptr<Engine<D>> make_engine(EngineKind kind, System<D> system,
                                       const CollisionRule& rule);

// Runs `engine` until `end_time`, calling on_event(event) after every processed collision, then
// brings every particle to `end_time`.
template <std::size_t D, class OnEvent>
void run(Engine<D>& engine, double end_time, OnEvent&& on_event) {
  while (const std::optional<Event> event = engine.step(end_time)) on_event(*event);
  engine.finish(end_time);
}

template <std::size_t D>
void run(Engine<D>& engine, double end_time) {
  run(engine, end_time, [](const Event&) {});
}

// A speed no particle can exceed during the run: no rule makes a particle faster than the fastest
// at the start (swap) or than one holding all the kinetic energy (elastic, inelastic).
template <std::size_t D>
double speed_bound(const System<D>& system) {
  double fastest = 0.0, energy = 0.0, lightest = kNever;
  for (const Particle<D>& p : system.particles) {
    fastest = std::max(fastest, std::sqrt(norm2(p.velocity)));
    energy += 0.5 * p.mass * norm2(p.velocity);
    lightest = std::min(lightest, p.mass);
  }
  return std::max(fastest, std::sqrt(2.0 * energy / lightest)) * (1.0 + 1e-9);
}

// How many times a particle at speed_bound() would cross the box's shortest side in `duration`:
// a bound on the work a run can need (wall hits, cell crossings, renewals of predictions in a
// small periodic box). Used to refuse runs that could never finish (a typo such as 1e84 for 1.84,
// or a mass of 1e75 that could hand a light disk astronomical speeds).
template <std::size_t D>
double most_crossings(const System<D>& system, double duration) {
  return speed_bound(system) * duration / shortest_side(system.box);
}

// Runs needing more box crossings than this are refused as impossible to finish.
inline constexpr double kMostCrossings = 1e13;

std::string_view rule_name(Rule rule);
std::string_view boundary_name(Boundary boundary);
std::string_view engine_name(EngineKind kind);

}  // namespace carom
