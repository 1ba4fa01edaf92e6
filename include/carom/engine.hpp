// The simulation engines: a fast one for real work and a simple reference one to check it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "carom/event.hpp"
#include "carom/physics.hpp"
#include "carom/system.hpp"

namespace carom {

struct RunCounts {
  std::uint64_t events = 0;  // processed collisions: wall_collisions + pair_collisions
  std::uint64_t wall_collisions = 0;
  std::uint64_t pair_collisions = 0;
};

enum class EngineKind {
  fast,       // cell grid, one pending event per particle, O(log N) per event
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

  // Brings every particle to `end_time`, which must not precede the last processed event.
  void finish(double end_time);

  const System<D>& system() const { return system_; }
  const RunCounts& counts() const { return counts_; }
  Rule rule() const { return rule_; }
  // The time of the last processed event (the start time before any).
  double time() const { return now_; }

 protected:
  Engine(System<D> system, Rule rule);
  // Carries out a collision that is due: moves the particles involved to its time, applies the
  // rule or the wall bounce, and counts it.
  void apply(const Event& event);

  System<D> system_;
  Rule rule_;
  RunCounts counts_;
  double now_ = 0.0;
};

template <std::size_t D>
std::unique_ptr<Engine<D>> make_engine(EngineKind kind, System<D> system, Rule rule);

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

std::string_view rule_name(Rule rule);
std::string_view engine_name(EngineKind kind);

}  // namespace carom
