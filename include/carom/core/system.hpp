// The simulated system: a box, the particles in it and the labels that name walls.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "carom/core/names.hpp"
#include "carom/core/vec.hpp"

namespace carom {

// One hard disk (D = 2) or sphere (D = 3): the hot data every prediction reads, kept together
// (48 bytes for a disk, one 64-byte line for a sphere). The stored state is the one the classic
// assignment prints: the position at `time`, the moment the particle last collided (or the start).
// Other particles are never touched by an event; their current position is derived on demand (see
// position_at).
template <std::size_t D>
struct Particle {
  Vec<D> position;
  Vec<D> velocity;
  double time = 0.0;
  double radius = 0.0;

  friend bool operator==(const Particle&, const Particle&) = default;
};

// Adds `sides` (a whole number) to an image flag (see ParticleRecord::image), saturating at the
// int32 range rather than overflow (and leaving it alone for a count that is not a number, which
// no run has but a reader may be handed).
inline void add_sides(std::int32_t& flag, double sides) {
  const double sum = flag + sides;
  if (std::isnan(sum)) return;
  constexpr double kLow = std::numeric_limits<std::int32_t>::min();
  constexpr double kHigh = std::numeric_limits<std::int32_t>::max();
  flag = static_cast<std::int32_t>(std::clamp(sum, kLow, kHigh));
}

// The cold data of a particle, read only when it collides: its mass and what has happened to it.
struct ParticleRecord {
  double mass = 1.0;
  std::uint64_t wall_collisions = 0;
  std::uint64_t pair_collisions = 0;
  // The time of its last collision (wall or pair), for the TC model; before any, -infinity.
  // Kept apart from Particle::time, which also moves when states are brought to a common time.
  double last_collision = -std::numeric_limits<double>::infinity();
  // In a periodic box, how many box sides the particle's stored position has been moved by
  // wrapping, per axis (z unused for disks): the unwrapped position is position + image x side,
  // as in HOOMD's and LAMMPS' image flags. Int32, as theirs. In a sheared box the image one box
  // up lies at (shift, Ly) (Box::sheared_shift), as in a tilted box of HOOMD's: the unwrapped x
  // adds image_y x shift, and when the stored shift drops by whole sides (shift_epoch) they move
  // into image_x, so that the unwrapped position never jumps. Only real crossings count: a
  // collision through a sliding image moves no flag.
  std::array<std::int32_t, 3> image{};
  // Grows whenever the particle's velocity changes (its collisions, and a thermostat's resets:
  // Engine::reset_velocity): events predicted against an older value are stale. Bookkeeping of
  // one run, not kept by checkpoints (a resumed run predicts everything afresh) and not compared;
  // 32 bits, as no prediction waits for 2^32 changes of its partner.
  std::uint32_t changes = 0;
  // The particle's species: an index into System::type_names (0, "A", unless a start names
  // more). Set by the start and never changed by a run.
  std::uint32_t type = 0;

  std::uint64_t version() const { return changes; }
  // A pair collision (or lift) at stored time t changed its velocity: counted, and the TC model's
  // time and the version moved on.
  void count_pair_collision(double t) {
    add_pair_collisions(1);
    last_collision = t;
  }
  // n pair collisions (or lifts) counted at once, where the time is written elsewhere: an event
  // chain's lifts, added to the mover's record after its stop.
  void add_pair_collisions(std::uint32_t n) {
    pair_collisions += n;
    changes += n;
  }
  friend bool operator==(const ParticleRecord& a, const ParticleRecord& b) {
    return a.mass == b.mass && a.wall_collisions == b.wall_collisions &&
           a.pair_collisions == b.pair_collisions && a.last_collision == b.last_collision &&
           a.image == b.image && a.type == b.type;
  }
};

enum class Boundary {
  walls,     // a hard wall on every face (the classic assignment's box)
  periodic,  // the box repeats in every direction: minimum image convention, no walls
};

template <>
struct EnumNames<Boundary> {
  static constexpr std::array<std::pair<std::string_view, Boundary>, 2> table{
      {{"walls", Boundary::walls}, {"periodic", Boundary::periodic}}};
};

// How messages name the particles of a dimension.
template <std::size_t D>
inline constexpr std::string_view kParticlesName = D == 2 ? "disks" : "spheres";
template <std::size_t D>
inline constexpr std::string_view kParticleName = D == 2 ? "disk" : "sphere";

// A rectangular box [0, size[0]] x ... x [0, size[D-1]].
//
// A periodic box may be sheared (Lees-Edwards): the images above it in y slide along x with
// velocity shear_rate x Ly, those below with the opposite, so that the fluid streams with the
// profile u_x = shear_rate (y - Ly / 2). At stored time t (System::epoch) the images one box up
// sit shear_offset + shear_rate Ly t further along x (sheared_shift): a linear function of the
// stored time, so that a particle's image moves in a straight line and contact times stay the
// roots of a quadratic.
template <std::size_t D>
struct Box {
  Vec<D> size;
  Boundary boundary = Boundary::walls;
  double shear_rate = 0.0;    // du_x / dy; 0: not sheared
  double shear_offset = 0.0;  // the x shift of the images one box up, at stored time 0

  bool periodic() const { return boundary == Boundary::periodic; }
  bool sheared() const { return shear_rate != 0.0; }
  // The x shift of the images one box up at stored time t (unreduced: any multiple of Lx is the
  // same lattice).
  double sheared_shift(double t) const { return shear_offset + shear_rate * size[1] * t; }
  // The x velocity of the images one box up relative to the box.
  double image_speed() const { return shear_rate * size[1]; }
  // The streaming velocity at height y.
  double stream_velocity(double y) const { return shear_rate * (y - 0.5 * size[1]); }
};

template <std::size_t D>
double shortest_side(const Box<D>& box) {
  double side = box.size[0];
  for (std::size_t k = 1; k < D; ++k) side = side < box.size[k] ? side : box.size[k];
  return side;
}

// The box's area (disks) or volume (spheres).
template <std::size_t D>
double box_volume(const Box<D>& box) {
  double volume = 1.0;
  for (std::size_t k = 0; k < D; ++k) volume *= box.size[k];
  return volume;
}

// The state of a run: the box, every particle's hot data and, index for index, its record.
template <std::size_t D>
struct System {
  static constexpr std::size_t dimension = D;

  Box<D> box;
  std::vector<Particle<D>> particles;
  std::vector<ParticleRecord> records;
  // The names of the particles' species (ParticleRecord::type indexes them): one, "A", unless the
  // start names more (carom init --species, a file's types). Never empty.
  std::vector<std::string> type_names{"A"};
  // The absolute time that stored times (Particle::time, ParticleRecord::last_collision) count
  // from. A run moves it forward now and then (Engine::rebase) so that stored times stay small: a
  // double then resolves the moments of contact as finely at t = 1e11 as at t = 1.
  double epoch = 0.0;

  std::size_t size() const { return particles.size(); }
  // A stored time as an absolute one.
  double absolute(double stored) const { return epoch + stored; }
  // Moves the epoch `shift` later: every stored time becomes relative to it (particles do not
  // move; -infinity stays). The new epoch is exactly absolute(shift).
  void shift_epoch(double shift) {
    epoch = absolute(shift);
    if (box.sheared()) {  // the images' shift at the new epoch, reduced to [0, Lx)
      const double unreduced = box.sheared_shift(shift);
      box.shear_offset = std::fmod(unreduced, box.size[0]);
      if (box.shear_offset < 0.0) box.shear_offset += box.size[0];
      // The sides the shift dropped by move into the x image flags (see ParticleRecord::image).
      const double sides = std::nearbyint((unreduced - box.shear_offset) / box.size[0]);
      if (sides != 0.0) {
        for (ParticleRecord& r : records) add_sides(r.image[0], sides * r.image[1]);
      }
    }
    for (Particle<D>& p : particles) p.time -= shift;
    for (ParticleRecord& r : records) r.last_collision -= shift;
  }
  // The latest stored time: every particle's state is at or before it.
  double latest_stored() const {
    double latest = -std::numeric_limits<double>::infinity();
    for (const Particle<D>& p : particles) latest = latest < p.time ? p.time : latest;
    return latest;
  }
  // The stored time of an absolute time t: the latest s with absolute(s) <= t. A run has processed
  // exactly the events whose absolute time is not after t (absolute() is monotone), so bringing
  // particles to stored(t) passes no event left for later, however coarsely a double resolves t.
  // With the epoch at zero, t itself.
  double stored(double t) const {
    double low = t - epoch;
    if (!std::isfinite(low) || epoch == 0.0) return low;
    // Bracket the answer within a few units in the last place of t, then halve the bracket.
    double step = std::max(std::abs(t), std::abs(low)) * 0x1p-52 + 0x1p-1074;
    double high = low;
    while (absolute(low) > t) low -= step, step *= 2.0;
    while (!(absolute(high) > t)) high += step, step *= 2.0;
    for (double middle = low + (high - low) / 2.0; middle != low && middle != high;
         middle = low + (high - low) / 2.0) {
      (absolute(middle) <= t ? low : high) = middle;
    }
    return low;
  }
  void add(const Particle<D>& particle, double mass = 1.0) {
    particles.push_back(particle);
    records.push_back({mass});
  }
};

// Whether the system holds more than the single default species "A" (files then carry types).
template <std::size_t D>
bool has_types(const System<D>& system) {
  return system.type_names.size() != 1 || system.type_names[0] != "A";
}

template <std::size_t D>
double largest_radius(const System<D>& system) {
  double largest = 0.0;
  for (const Particle<D>& p : system.particles) largest = largest < p.radius ? p.radius : largest;
  return largest;
}

// Walls are labelled by negative numbers, two per axis, the classic assignment's order:
// -1 left (x = 0), -2 right (x = Lx), -3 bottom (y = 0), -4 top (y = Ly), then -5, -6 for z.
constexpr int wall_label(std::size_t axis, bool upper) {
  return -static_cast<int>(2 * axis + (upper ? 2 : 1));
}
constexpr std::size_t wall_axis(int label) {
  return static_cast<std::size_t>(-label - 1) / 2;
}
constexpr bool wall_is_upper(int label) {
  return (-label - 1) % 2 == 1;
}

constexpr std::string_view wall_name(int label) {
  constexpr std::string_view names[] = {"left", "right", "bottom", "top", "back", "front"};
  const int index = -label - 1;
  return index >= 0 && index < 6 ? names[index] : std::string_view("unknown");
}

}  // namespace carom
