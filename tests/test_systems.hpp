// Reproducible random systems for the tests (pcg32: the same sequence on every machine).
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <pcg_random.hpp>
#include <string>
#include <vector>

#include "carom/core/measurement.hpp"
#include "carom/core/system.hpp"
#include "carom/engine/engine.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/classic_input.hpp"

namespace carom::testing {

// One of the classic assignment's reference cases (tests/data/cases).
inline System<2> case_system(const std::string& name) {
  return read_classic_file<2>(std::string(CAROM_TEST_DATA) + "/cases/" + name).system;
}

// A uniform double in [0, 1) with 53 random bits.
inline double uniform(pcg32& rng) {
  const std::uint64_t hi = rng() >> 5, lo = rng() >> 6;
  return (static_cast<double>(hi) * 67108864.0 + static_cast<double>(lo)) / 9007199254740992.0;
}

inline double uniform(pcg32& rng, double lo, double hi) {
  return lo + (hi - lo) * uniform(rng);
}

// A disk of radius r at `position` moving with `velocity`, stored at t = 0.
inline Particle<2> disk(Vec2 position, Vec2 velocity, double r) {
  Particle<2> p;
  p.position = position;
  p.velocity = velocity;
  p.radius = r;
  return p;
}

// A box of the given size holding the given disks.
inline System<2> boxed(Vec2 size, std::vector<Particle<2>> particles,
                       Boundary boundary = Boundary::walls) {
  System<2> system;
  system.box = {size, boundary};
  for (const Particle<2>& p : particles) system.add(p);
  return system;
}

// Up to `n` disks placed at random without overlap (attempts are bounded, so a crowded box gets
// fewer), radii in [r_min, r_max], velocity components uniform in [-1, 1].
inline System<2> random_gas(pcg32& rng, std::size_t n, double r_min, double r_max, double lx,
                            double ly) {
  System<2> system;
  system.box.size = {lx, ly};
  for (std::size_t attempt = 0; attempt < 200 * n && system.particles.size() < n; ++attempt) {
    Particle<2> p;
    p.radius = uniform(rng, r_min, r_max);
    if (2 * p.radius >= lx || 2 * p.radius >= ly) continue;
    p.position = {uniform(rng, p.radius, lx - p.radius), uniform(rng, p.radius, ly - p.radius)};
    p.velocity = {uniform(rng, -1, 1), uniform(rng, -1, 1)};
    const double mass = uniform(rng, 0.5, 2.0);
    bool free = true;
    for (const Particle<2>& q : system.particles) {
      const double sigma = p.radius + q.radius;
      if (norm2(p.position - q.position) < sigma * sigma) free = false;
    }
    if (free) system.add(p, mass);
  }
  return system;
}

// Up to `n` spheres placed at random without overlap in a box of the given size (walls), radii
// in [r_min, r_max], velocity components uniform in [-1, 1], masses in [0.5, 2].
inline System<3> random_spheres(pcg32& rng, std::size_t n, double r_min, double r_max,
                                const Vec<3>& size) {
  System<3> system;
  system.box.size = size;
  for (std::size_t attempt = 0; attempt < 200 * n && system.size() < n; ++attempt) {
    Particle<3> p;
    p.radius = uniform(rng, r_min, r_max);
    bool fits = true;
    for (std::size_t k = 0; k < 3; ++k) {
      fits = fits && 2 * p.radius < size[k];
      p.position[k] = uniform(rng, p.radius, size[k] - p.radius);
      p.velocity[k] = uniform(rng, -1, 1);
    }
    const double mass = uniform(rng, 0.5, 2.0);
    for (const Particle<3>& q : system.particles) {
      const double sigma = p.radius + q.radius;
      if (norm2(p.position - q.position) < sigma * sigma) fits = false;
    }
    if (fits) system.add(p, mass);
  }
  return system;
}

// A square (D = 2) or simple cubic (D = 3) lattice of particles of radius r, `gap` apart at the
// closest, filling a box of side `cells` * (2r + gap); velocities random, or along one axis only
// (alternating between axes, speeds -0.5, 0 or 0.5) so that events tie.
template <std::size_t D>
System<D> cubic_lattice(pcg32& rng, std::size_t cells, double r, double gap,
                        bool aligned_velocities) {
  System<D> system;
  const double spacing = 2 * r + gap;
  for (std::size_t k = 0; k < D; ++k) system.box.size[k] = cells * spacing;
  std::size_t sites = 1;
  for (std::size_t k = 0; k < D; ++k) sites *= cells;
  for (std::size_t site = 0; site < sites; ++site) {
    Particle<D> p;
    p.radius = r;
    std::size_t index_sum = 0;
    for (std::size_t k = 0, rest = site; k < D; ++k) {
      // The first axis varies slowest.
      std::size_t stride = 1;
      for (std::size_t later = k + 1; later < D; ++later) stride *= cells;
      const std::size_t index = rest / stride;
      rest %= stride;
      index_sum += index;
      p.position[k] = (index + 0.5) * spacing;
    }
    if (aligned_velocities) {
      const double speed = (rng() % 3) * 0.5 - 0.5;
      p.velocity[(index_sum + 1) % D] = speed;
    } else {
      for (std::size_t k = 0; k < D; ++k) p.velocity[k] = uniform(rng, -1, 1);
    }
    system.add(p);
  }
  return system;
}

inline System<2> square_lattice(pcg32& rng, std::size_t cells, double r, double gap,
                                bool aligned_velocities) {
  return cubic_lattice<2>(rng, cells, r, gap, aligned_velocities);
}

// Every event up to `end_time` that `engine` processes.
template <std::size_t D>
std::vector<Event> events_until(Engine<D>& engine, double end_time) {
  std::vector<Event> events;
  while (const auto event = engine.step(end_time)) events.push_back(*event);
  return events;
}

// Keeps every event of a simulation it observes.
template <std::size_t D>
struct EventRecorder final : Observer<D> {
  EventRecorder() : Observer<D>(Trigger::each_event()) {}
  void observe(const Simulation<D>& simulation) override {
    events.push_back(simulation.last_event());
  }
  std::vector<Event> events;
};

// Runs `system` to `end_time` in a Simulation and returns its events.
template <std::size_t D>
std::vector<Event> simulate(Simulation<D>& simulation, double end_time) {
  auto recorder = std::make_shared<EventRecorder<D>>();
  simulation.add_observer(recorder);
  simulation.run_until(end_time);
  return recorder->events;
}

// What a list of events adds up to.
inline Counts count(const std::vector<Event>& events) {
  Counts counts;
  for (const Event& event : events) counts.add(event);
  return counts;
}

}  // namespace carom::testing
