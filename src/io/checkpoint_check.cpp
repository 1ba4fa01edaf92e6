#include "checkpoint_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>

#include "carom/engine/engine.hpp"
#include "carom/engine/overlap.hpp"
#include "carom/engine/validation.hpp"

namespace carom {

namespace {

// The resumed engine is replayed from the latest stored time to the checkpoint's to find
// collisions that should have happened before it; beyond this many box crossings in that span
// (a run with no event for a very long time) the replay is skipped as too long.
constexpr double kMostReplayedCrossings = 1e5;

// The first problem found: validate stops there.
struct Problem {
  std::string what;
};

// What a run can have reached, checked: the settings, the counts, the times, every particle as
// the classic reader checks it (at its stored time, and moved to the checkpoint's time), and no
// collision missed before the checkpoint's time.
template <std::size_t D>
void validate(const Checkpoint<D>& c, int format) {
  const auto fail = [](const std::string& problem) { throw Problem{problem}; };
  try {
    check_settings(c.settings);
  } catch (const std::invalid_argument& e) {
    fail(e.what());
  }
  for (const auto& [what, t] : {std::pair{"time", c.time}, std::pair{"epoch", c.system.epoch}}) {
    if (std::abs(t) > Simulation<D>::kLatestTime) {
      fail(fmt::format("the {} {} is beyond {}, which no run reaches", what, t,
                       Simulation<D>::kLatestTime));
    }
  }
  if (!(c.system.epoch <= c.time)) {
    fail(fmt::format("the epoch {} is after the checkpoint's time {}", c.system.epoch, c.time));
  }
  const Measurement& m = c.measurement;
  if (!(m.start_time <= c.time)) {
    fail(fmt::format("the measurement starts at {}, after the checkpoint's time {}", m.start_time,
                     c.time));
  }
  if (!(m.kinetic_energy_initial >= 0.0)) {
    fail(fmt::format("the measurement's initial kinetic energy {} is negative",
                     m.kinetic_energy_initial));
  }
  // The window counts a part of the run (format 1 stored nothing else).
  if (format != 1 &&
      (m.counts.events > c.counts.events || m.counts.wall_collisions > c.counts.wall_collisions ||
       m.counts.pair_collisions > c.counts.pair_collisions ||
       m.counts.elastic_by_tc > c.counts.elastic_by_tc)) {
    fail(fmt::format("the measurement counts {} events, more than the {} of the whole run",
                     m.counts.events, c.counts.events));
  }

  const System<D>& s = c.system;
  const Box<D>& box = s.box;
  if ((c.settings.sampler.kind == SamplerKind::ecmc) != c.chain.has_value()) {
    fail("an event-chain run needs its chain, and dynamics has none");
  }
  if (c.chain) {
    // Chains move one particle, the active one, along the chain's axis; the rest are at rest.
    const ChainState& chain = *c.chain;
    if (chain.active >= s.size()) {
      fail(fmt::format("the active particle {} is not one of the {}", chain.active, s.size()));
    }
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Vec<D>& v = s.particles[i].velocity;
      for (std::size_t k = 0; k < D; ++k) {
        const bool moves = i == chain.active && k == chain.axis;
        if (moves ? !(v[k] > 0.0) : v[k] != 0.0) {
          fail(fmt::format("particle {} has velocity component {} = {}: event chains move only "
                           "the active particle {}, along axis {}",
                           i, k, v[k], chain.active, chain.axis));
        }
      }
    }
    const double since = s.particles[chain.active].time;
    if (!(chain.chain_end >= since)) {
      fail(fmt::format("the chain ends at {}, before the active particle's stored time {}",
                       chain.chain_end, since));
    }
    // A chain lasts its length over N (one chain of a turn): one that ends later never turns.
    const double lasts = chain_turn_duration(c.settings.sampler, s.size(), D) / D;
    if (!(chain.chain_end - since <= lasts * (1.0 + 1e-6) + 1e-9 * std::abs(chain.chain_end))) {
      fail(
          fmt::format("the chain ends at {}, more than a chain ({} time units) after the active "
                      "particle's stored time {}",
                      chain.chain_end, lasts, since));
    }
    try {
      check_chain_start(s);  // masses, box
    } catch (const std::invalid_argument& e) {
      fail(e.what());
    }
  }
  constexpr std::uint64_t kMost = std::numeric_limits<std::uint64_t>::max();
  const auto sum = [&](std::uint64_t a, std::uint64_t b) { return a > kMost - b ? kMost : a + b; };
  std::uint64_t walls = 0, pairs = 0;  // saturating
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Particle<D>& p = s.particles[i];
    const ParticleRecord& r = s.records[i];
    if (!(s.absolute(p.time) <= c.time)) {
      fail(fmt::format("particle {} is stored at t = {}, after the checkpoint's time {}", i,
                       s.absolute(p.time), c.time));
    }
    if (s.absolute(r.last_collision) > c.time) {
      fail(fmt::format("particle {} last collided at t = {}, after the checkpoint's time {}", i,
                       s.absolute(r.last_collision), c.time));
    }
    walls = sum(walls, r.wall_collisions);
    pairs = sum(pairs, r.pair_collisions);
    // Its stored state, as the classic reader checks a start: a periodic run wraps positions by
    // floor, which may leave one an ulp outside.
    Particle<D> stored = p;
    if (box.periodic()) {
      for (std::size_t k = 0; k < D; ++k) {
        const double slack = 1e-9 * box.size[k];
        if (stored.position[k] >= -slack && stored.position[k] <= box.size[k] + slack) {
          stored.position[k] = std::clamp(stored.position[k], 0.0, box.size[k]);
        }
      }
    }
    if (const auto problem = particle_problem(i, stored, r.mass, box)) {
      fail(fmt::format("at its stored time t = {}, {}", s.absolute(p.time), *problem));
    }
    // Moved to the checkpoint's time: in a box with walls, still inside it.
    if (!box.periodic()) {
      Particle<D> now = p;
      advance(now, s.stored(c.time));
      if (const auto problem = particle_problem(i, now, r.mass, box)) {
        fail(fmt::format("at the checkpoint's time t = {}, {}", c.time, *problem));
      }
    }
  }
  // Every collision counted once in the run's counts and once per particle involved (the
  // particles' counters may hold more: a system built by a program may carry earlier history).
  if (walls < c.counts.wall_collisions ||
      pairs < sum(c.counts.pair_collisions, c.counts.pair_collisions)) {
    fail(fmt::format(
        "the particles' collision counts (wall {}, pair {}) are fewer than the run's ({} wall, {} "
        "pair collisions, each counted by both its particles)",
        walls, pairs, c.counts.wall_collisions, c.counts.pair_collisions));
  }
  if (const auto overlap = find_pair_overlap(s, s.stored(c.time))) {
    System<D> now = s;
    now.particles = synchronised(s, s.stored(c.time));
    fail(fmt::format("at the checkpoint's time t = {}, {}", c.time,
                     describe_overlap(now, overlap->first, overlap->second,
                                      s.particles[overlap->first].radius)));
  }
  // No collision due before the checkpoint's time may be left unprocessed (two particles whose
  // stored states have them pass through each other, say): the resumed run would go back in
  // time. The engine, started from the stored states as a resumed run starts, must find none.
  if (most_crossings(s, c.time - s.absolute(s.latest_stored())) <= kMostReplayedCrossings) {
    std::optional<Event> missed;
    try {
      auto engine = make_engine(EngineKind::fast, s, c.settings.rule);
      missed = engine->step(std::nextafter(c.time, -kNever));
    } catch (const std::exception& e) {
      fail(fmt::format("its particles cannot be run: {}", e.what()));
    }
    if (missed) {
      fail(
          fmt::format("the stored states are not ones a run can reach: {} at t = {}, before the "
                      "checkpoint's time {}, was never processed",
                      describe(*missed), missed->time, c.time));
    }
  }
}

}  // namespace

template <std::size_t D>
std::optional<std::string> checkpoint_problem(const Checkpoint<D>& checkpoint, int format) {
  try {
    validate(checkpoint, format);
  } catch (const Problem& problem) {
    return problem.what;
  }
  return std::nullopt;
}

template std::optional<std::string> checkpoint_problem(const Checkpoint<2>&, int);
template std::optional<std::string> checkpoint_problem(const Checkpoint<3>&, int);

}  // namespace carom
