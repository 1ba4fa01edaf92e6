// The simulation engines: a fast one for real work and a simple reference one to check it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "carom/core/event.hpp"
#include "carom/core/physics.hpp"
#include "carom/core/system.hpp"

namespace carom {

// The particles cannot move apart: collisions keep coming at one instant without end (a disk
// wedged exactly between two walls, an inelastic collapse). Thrown instead of spinning forever.
class JamError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class EngineKind {
  fast,       // neighbour lists for a dense system they suit, else a cell grid (make_engine
              // picks); one pending event per particle in a calendar, O(1) per event
  reference,  // the classic assignment's algorithm done right: every pair predicted again after
              // every event
};

template <>
struct EnumNames<EngineKind> {
  static constexpr std::array<std::pair<std::string_view, EngineKind>, 2> table{
      {{"fast", EngineKind::fast}, {"reference", EngineKind::reference}}};
};

// Every radius growing during a run (Lubachevsky-Stillinger compression, see grown_radius): at
// stored time t a particle's radius is radius x (1 + rate x t). An engine with growth runs only up
// to stored time `until`: its cell grid and image horizon are sized for the radii then. Rate 0:
// no growth.
struct Growth {
  double rate = 0.0;
  double until = 0.0;
};

// Runs a system event by event. Events are processed in the order of EventKey, only the
// particles involved are moved, and the particles' stored states follow the classic assignment's
// lazy convention (see Particle). Engines know nothing of end times, frames or measurements: the
// Simulation (simulation.hpp) drives them.
//
// Inside, every time is a stored time (counted from System::epoch); step() takes and returns
// absolute times. The physics never sees an absolute time, so rebase() now and then keeps its
// resolution independent of how long the run has gone on.
template <std::size_t D>
class Engine {
 public:
  virtual ~Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Processes the earliest pending collision if it happens no later than the absolute time
  // `end_time` and returns it (at its absolute time); otherwise changes nothing and returns
  // nullopt. Stopping and going on is invisible: any sequence of end times gives the same events,
  // bit for bit.
  virtual std::optional<Event> step(double end_time) = 0;

  // Moves the epoch to the last processed event: every stored time becomes relative to it (the
  // particles do not move) and pending predictions are made again from the shifted states. Both
  // engines do it identically, so they still agree bit for bit when rebased at the same events.
  // The Simulation does it every so many events (Simulation::rebase_period).
  void rebase();

  // Brings every particle to the stored time t (not before the last event), lets `change` set
  // their velocities (and nothing else of the System), then moves the epoch to t and predicts
  // everything again, as rebase() does: what a thermostat does between collisions, in every
  // engine alike. Not for a growing engine.
  template <class F>
  void intervene(double t, F&& change) {
    move_all_to(t);
    change(system_);
    velocities_changed();
    restart_at(t);
  }

  // Gives particle i, brought to the stored time t (not before the last event), a new velocity:
  // what Andersen's thermostat does to one particle between collisions, in every engine alike.
  // Its events are predicted again; predictions others made against it are stale (its version
  // changes). Not for a growing engine.
  void reset_velocity(std::uint32_t i, double t, const Vec<D>& velocity);

  const System<D>& system() const { return system_; }
  const CollisionRule& rule() const { return rule_; }
  // A stretch of simulated time in which the particles make at most about 10^5 cell crossings in
  // all (the work between events, a few milliseconds), for the system as it is now: the
  // Simulation looks at its stop flag at least this often, events or not.
  virtual double slice_length() const;
  // RunLengthError if the engine cannot run on to the absolute time t (the Simulation's own
  // checks aside): nothing in dynamics.
  virtual void check_target(double /*t*/) const {}
  // The absolute time of the last processed event (the latest stored time before any).
  double time() const { return system_.absolute(now_); }
  // The same as a stored time: exact, where time() may be rounded.
  double stored_time() const { return now_; }

  // A velocity the engine changed other than in an event step() returned (event chains turning
  // at a chain's end): particle's, at stored time `at`, from `before` to `after`.
  struct VelocityChange {
    std::uint32_t particle = 0;
    double at = 0.0;
    Vec<D> before, after;
  };
  // Calls `take(change)` for each such change since the last call, in order, and forgets them:
  // the Simulation keeps the fluxes' kinetic rates right with them.
  template <class F>
  void take_velocity_changes(F&& take) {
    for (const VelocityChange& change : velocity_changes_) take(change);
    velocity_changes_.clear();
  }

 protected:
  // Throws std::invalid_argument for a periodic box with a side not above two diameters (grown
  // to growth.until), or records that do not match the particles (none at all means mass 1 and
  // no history each).
  Engine(System<D> system, const CollisionRule& rule, const Growth& growth);
  // Carries out a collision that is due (at a stored time): moves the particles involved to its
  // time, applies the rule or the wall bounce, updates their records and fills in what it did.
  // Returns the event at its absolute time.
  Event apply(Event event);
  // Whether an event at stored time t happens no later than the absolute time end_time.
  bool due_by(double t, double end_time) const { return system_.absolute(t) <= end_time; }
  // After rebase() shifted every stored time by `shift`: predictions are made again.
  virtual void rebased(double shift) = 0;
  // After intervene() changed velocities, before predictions are made again: for what an engine
  // keeps that depends on the particles' speeds.
  virtual void velocities_changed() {}
  // After reset_velocity() gave particle i a new velocity at now_: its events predicted again.
  virtual void velocity_reset(std::uint32_t i) = 0;
  // How many particles move at once, for slice_length(): every one in dynamics.
  virtual double moving_particles() const { return static_cast<double>(system_.size()); }

  // The image of particle j that particle i sees at time t (zero in a box with walls).
  Vec<D> image(std::uint32_t i, std::uint32_t j, double t) const;

  // How long pair predictions made with the images seen at one moment stay right: within this
  // time no pair can travel far enough to touch through another image. Infinite for walls. With
  // growth, collisions speed particles up, and it shrinks as they do (see fastest_).
  double image_horizon() const;
  // The same for particles (inside the box) never faster than `speed`.
  double image_horizon(double speed) const;
  // The fastest particle's speed at stored time t (not before the last event), its state brought
  // inside the box (in a sheared box a state outside has the velocity of an image).
  double fastest_in_box(double t) const;
  bool growing() const { return growth_.rate != 0.0; }
  // The largest radius the run can reach (grown to growth.until).
  double largest_reach() const { return largest_; }
  // For a horizon too short for a double to advance the time at `t`: the run cannot progress.
  [[noreturn]] void throw_too_fast(double t) const;
  // For collisions that keep coming at one instant (`event` the last): a JamError naming what
  // can cause it in this run (an inelastic collapse, a particle wedged between walls).
  [[noreturn]] void throw_stuck(const Event& event) const;
  // What such a jam's error says first: "N `events` at t = ... without time advancing (particle
  // i and ...)", `event` the last of them.
  std::string describe_stall(const Event& event, std::string_view events) const;

  System<D> system_;
  CollisionRule rule_;
  Growth growth_;
  double largest_ = 0.0;  // see largest_reach()
  // With growth or shear: a bound on every particle's speed so far (collisions between growing
  // particles, or through the sheared boundary, add energy, so speed_bound() does not hold);
  // raised after each collision (and, in a sheared box, when an engine sees a particle cross the
  // sheared boundary), made afresh when every state is renewed (rebase, intervene).
  double fastest_ = 0.0;
  // Raises fastest_ to cover a particle whose velocity has this square.
  void raise_speed_bound(double speed2) {
    fastest_ = std::max(fastest_, std::sqrt(speed2) * (1.0 + 1e-9));
  }
  double now_ = 0.0;                 // the stored time of the last processed event
  std::vector<VelocityChange> velocity_changes_;  // see take_velocity_changes
  std::uint64_t events_at_now_ = 0;  // consecutive events at exactly now_, to detect a jam

 private:
  // A pair collision in a sheared box: b moved into the image a touches at t (the image's cells
  // returned), and after the collision both wrapped back into the box, b's image flags left
  // counting its real crossings only, and the speed bound raised.
  [[gnu::noinline]] Vec<D> to_touching_image(const Particle<D>& a, Particle<D>& b, double t) const;
  [[gnu::noinline]] void back_into_sheared_box(Particle<D>& a, Particle<D>& b, const Vec<D>& cells);
  // intervene()'s steps: every particle stored at t (wrapped into a periodic box); the epoch at
  // t, the last event's place, and every prediction made again.
  void move_all_to(double t);
  void restart_at(double t);
};

// The engine of `kind` for `system`. For EngineKind::fast: neighbour lists (ListEngine) when they
// suit the system (dense, not growing, not sheared; ListEngine::suits), else the cell grid.
template <std::size_t D>
std::unique_ptr<Engine<D>> make_engine(EngineKind kind, System<D> system, const CollisionRule& rule,
                                       const Growth& growth = {});

// A particle brought to the stored time t (not before its own), wrapped into a periodic box.
template <std::size_t D>
Particle<D> synchronised(Particle<D> p, const Box<D>& box, double t) {
  advance(p, t);
  std::array<std::int32_t, 3> image{};
  wrap(p, box, image);
  return p;
}

// In a sheared box, the whole box sides by which the images' shift at stored time t lies from
// the one frames, summaries and Python show (shown_shift).
template <std::size_t D>
double sides_beyond_shown_shift(const Box<D>& box, double t) {
  return box.sheared() ? std::nearbyint(box.sheared_shift(t) / box.size[0]) : 0.0;
}

// The x shift of the images one box up at stored time t as frames, summaries and Python show it:
// within half a side of 0 (any multiple of Lx names the same lattice of images, and readers of
// a tilted box, freud's and OVITO's, want the smallest tilt). 0 in a box that is not sheared.
template <std::size_t D>
double shown_shift(const Box<D>& box, double t) {
  if (!box.sheared()) return 0.0;
  return box.sheared_shift(t) - sides_beyond_shown_shift(box, t) * box.size[0];
}

// The same, adding the box sides wrapping moves it by to `image`, its image flags as a
// trajectory has them: in a sheared box such that position + image x sides + image_y x
// shown_shift along x is where the particle would be had the box not wrapped it (see
// ParticleRecord::image).
template <std::size_t D>
Particle<D> synchronised(Particle<D> p, const Box<D>& box, double t,
                         std::array<std::int32_t, 3>& image) {
  advance(p, t);
  wrap(p, box, image);
  if (box.sheared()) [[unlikely]]
    add_sides(image[0], sides_beyond_shown_shift(box, t) * image[1]);
  return p;
}

// Every particle brought to the stored time t (System::stored gives the one of an absolute time);
// the stored states are not touched.
template <std::size_t D>
std::vector<Particle<D>> synchronised(const System<D>& system, double t) {
  std::vector<Particle<D>> at;
  at.reserve(system.size());
  for (const Particle<D>& p : system.particles) at.push_back(synchronised(p, system.box, t));
  return at;
}

// A speed no particle can exceed during the run: no rule makes a particle faster than the fastest
// at the start (swap) or than one holding all the kinetic energy (elastic, inelastic).
template <std::size_t D>
double speed_bound(const System<D>& system) {
  double fastest = 0.0, energy = 0.0, lightest = kNever;
  for (std::size_t i = 0; i < system.size(); ++i) {
    const double mass = system.records[i].mass, v2 = norm2(system.particles[i].velocity);
    fastest = std::max(fastest, std::sqrt(v2));
    energy += 0.5 * mass * v2;
    lightest = std::min(lightest, mass);
  }
  return std::max(fastest, std::sqrt(2.0 * energy / lightest)) * (1.0 + 1e-9);
}

// How many times a particle at speed_bound() would cross the box's shortest side in `duration`,
// or the images across a sheared boundary slide by a box side: a bound on the work a run can need
// (wall hits, cell crossings, renewals of predictions in a small periodic box or at the sheared
// boundary). Used to refuse runs that could never finish (a typo such as 1e84 for 1.84, a mass of
// 1e75 that could hand a light disk astronomical speeds, or a shear rate of 1e99).
template <std::size_t D>
double most_crossings(const System<D>& system, double duration) {
  const double speed = speed_bound(system) + std::abs(system.box.image_speed());
  return speed * duration / shortest_side(system.box);
}

// Runs needing more box crossings than this are refused as impossible to finish.
inline constexpr double kMostCrossings = 1e13;

}  // namespace carom
