// The physics of hard particles as small pure functions: free flight, the time a particle
// reaches a wall or touches another particle, and the collision rules. Both engines call exactly
// these functions, so their results agree bit for bit.
//
// Every prediction is a function of the two particles' stored states only, never of the time
// at which it is asked. That makes it reproducible: the fast engine, which predicts once, and
// the reference engine, which predicts again after every event, compute identical times.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>

#include "carom/core/names.hpp"
#include "carom/core/system.hpp"

namespace carom {

inline constexpr double kNever = std::numeric_limits<double>::infinity();

template <std::size_t D>
constexpr Vec<D> position_at(const Particle<D>& p, double t) {
  return p.position + p.velocity * (t - p.time);
}

// Moves a particle along its straight line so that its stored state is at time t.
template <std::size_t D>
constexpr void advance(Particle<D>& p, double t) {
  p.position = position_at(p, t);
  p.time = t;
}

struct WallHit {
  double time = kNever;
  int label = 0;
};

// The first wall a particle reaches, from its stored state. A zero velocity component means no
// wall on that axis; a particle that touches a wall (or overlaps it by round-off) while moving
// into it hits it at once; one moving away never does. Ties between walls go to the lower
// |label|, so a corner hit is two events at the same time, -1/-2 before -3/-4.
template <std::size_t D>
constexpr WallHit next_wall_hit(const Particle<D>& p, const Box<D>& box) {
  WallHit hit;
  if (box.periodic()) return hit;
  for (std::size_t k = 0; k < D; ++k) {
    const double v = p.velocity[k];
    if (v == 0.0) continue;
    const bool upper = v > 0.0;
    const double gap = upper ? (box.size[k] - p.radius) - p.position[k] : p.position[k] - p.radius;
    const double dt = std::max(gap, 0.0) / std::abs(v);
    const double t = p.time + dt;
    if (t < hit.time) hit = {t, wall_label(k, upper)};
  }
  return hit;
}

// The periodic image of particle b that particle a sees: the multiple of the box size to subtract
// from a separation so that it is the shortest. Zero for a box with walls. Separations within half
// a box, nearly all of them, need no division.
template <std::size_t D>
constexpr Vec<D> image_offset(const Vec<D>& separation, const Box<D>& box) {
  Vec<D> offset;
  if (box.periodic()) {
    for (std::size_t k = 0; k < D; ++k) {
      const double side = box.size[k];
      if (!(std::abs(separation[k]) <= 0.5 * side)) {
        offset[k] = side * std::nearbyint(separation[k] / side);
      }
    }
  }
  return offset;
}

// The separation a - b of two stored positions, through the nearest image in a periodic box.

// separation() for a box that is not sheared: the minimum image of a rectangular lattice.
template <std::size_t D>
constexpr Vec<D> image_separation(const Particle<D>& a, const Particle<D>& b, const Box<D>& box) {
  const Vec<D> r = a.position - b.position;
  return r - image_offset(r, box);
}

// Brings one coordinate into [0, side) and returns by how many sides it moved it: floor(x / side).
// Strictly inside, floor() is 0 and the subtraction changes nothing (at -0 it would make +0,
// hence the strict test): no libm call then.
inline double wrap_coordinate(double& x, double side) {
  if (x > 0.0 && x < side) return 0.0;
  const double sides = std::floor(x / side);
  x -= side * sides;
  return sides;
}

// Wraps a position into the periodic box; positions in a box with walls are left alone.
template <std::size_t D>
void wrap(Vec<D>& position, const Box<D>& box) {
  if (!box.periodic()) return;
  for (std::size_t k = 0; k < D; ++k) wrap_coordinate(position[k], box.size[k]);
}

// The same, adding the sides each axis moved by to `image`.
template <std::size_t D>
void wrap(Vec<D>& position, const Box<D>& box, std::array<std::int32_t, 3>& image) {
  if (!box.periodic()) return;
  for (std::size_t k = 0; k < D; ++k) {
    const double moved = wrap_coordinate(position[k], box.size[k]);
    if (moved != 0.0) add_sides(image[k], moved);  // inside already, most of the time
  }
}

// The earliest time after t0 at which a pair at separation r, moving apart at v, is sigma apart
// (see contact_time), or kNever.
template <std::size_t D>
constexpr double earliest_contact(double t0, const Vec<D>& r, const Vec<D>& v, double sigma,
                                  double limit) {
  const double rv = dot(r, v);
  if (!(rv < 0.0)) return kNever;
  const double c = norm2(r) - sigma * sigma;
  if (c <= 0.0) return t0;
  if (t0 + c / (-2.0 * rv) * (1.0 - 1e-9) > limit) return kNever;
  const double discriminant = rv * rv - norm2(v) * c;
  if (discriminant < 0.0) return kNever;
  return t0 + c / (-rv + std::sqrt(discriminant));
}

// Event-chain Monte Carlo's lift: how far a particle moving along +`axis` goes before it touches
// one at separation r = (mover - other) with contact distance sigma, or kNever when the other is
// not ahead of it within sigma across the axis. The contact is earliest_contact's root for a unit
// velocity, in the same cancellation-free form and bit for bit the same (the dot product with a
// unit vector is the component, |e|^2 c is c): (|r|^2 - sigma^2) / (-r_axis + sqrt(sigma^2 -
// |r_perp|^2)). A pair touching or overlapping by round-off lifts at once (0). `limit` works as
// in contact_time: a lift beyond it may be reported as kNever, one at or before it never is.
template <std::size_t D>
constexpr double lift_distance(const Vec<D>& r, std::size_t axis, double sigma,
                               double limit = kNever) {
  const double along = r[axis];
  if (!(along < 0.0)) return kNever;
  const double c = norm2(r) - sigma * sigma;
  if (c <= 0.0) return 0.0;
  if (c / (-2.0 * along) * (1.0 - 1e-9) > limit) return kNever;
  const double discriminant = along * along - c;
  if (discriminant < 0.0) return kNever;
  return c / (-along + std::sqrt(discriminant));
}

// Wraps a particle's stored state into a periodic box, adding the sides it moved by to `image`;
// in a sheared box a move across y also moves it along x by the images' shift and changes its
// x velocity by their speed (it becomes the image of itself inside the box).
template <std::size_t D>
[[gnu::noinline]] void wrap_across_shear(Particle<D>& p, const Box<D>& box,
                                         std::array<std::int32_t, 3>& image) {
  const double layers = std::floor(p.position[1] / box.size[1]);
  if (layers == 0.0) return;
  p.position[1] -= layers * box.size[1];
  p.position[0] -= layers * box.sheared_shift(p.time);
  p.velocity[0] -= layers * box.image_speed();
  add_sides(image[1], layers);
  // The round-off of the subtraction may leave y a hair outside [0, Ly): a hair's move in.
  p.position[1] = std::clamp(p.position[1], 0.0, std::nextafter(box.size[1], 0.0));
}

template <std::size_t D>
[[gnu::always_inline]] inline void wrap(Particle<D>& p, const Box<D>& box,
                                        std::array<std::int32_t, 3>& image) {
  if (box.sheared()) [[unlikely]]
    wrap_across_shear(p, box, image);
  wrap(p.position, box, image);
}

// When two particles first touch, from their stored states, or kNever; `offset` selects the image
// of b (see image_offset). Both are brought to the later of their two stored times; only an
// approaching pair can collide, so a pair that has just collided (and so separates) never
// collides again by round-off. The earlier root of |r + v dt|^2 = sigma^2 is taken in the form
// c / (-b + sqrt(b^2 - v^2 c)), which has no cancellation. A pair that touches or overlaps by
// round-off while approaching collides at once. The result is symmetric in a and b bit for bit
// (swapping them negates r, v and the offset exactly).
//
// A caller that only wants contacts no later than `limit` (the earliest event found so far) may
// get kNever for a later one: the root is at least c / (2 |rv|) away, since the square root is at
// most |rv|, and that bound, shrunk by far more than the arithmetic's rounding, settles most
// candidates without a square root. A contact at or before `limit` is never lost: rounding is
// monotone, so the computed time is at least the computed bound.
template <std::size_t D>
constexpr double contact_time(const Particle<D>& a, const Particle<D>& b, const Vec<D>& offset,
                              double limit = kNever) {
  // The later particle's own position is position_at(p, p.time) exactly (x + v 0 = x, but for
  // the sign of a zero, which no result below depends on): only the earlier one is moved.
  const double t0 = std::max(a.time, b.time);
  const Vec<D> r =
      (a.time < b.time ? position_at(a, t0) - b.position : a.position - position_at(b, t0)) -
      offset;
  return earliest_contact(t0, r, a.velocity - b.velocity, a.radius + b.radius, limit);
}

template <std::size_t D>
constexpr double contact_time(const Particle<D>& a, const Particle<D>& b) {
  return contact_time(a, b, Vec<D>{});
}

// Lees-Edwards images (Box::sheared). An image of particle b is named by its cells n, whole
// numbers held as doubles: at stored time t it sits at b's position plus
// (n_x Lx + n_y shift(t), n_y Ly, n_z Lz), shift(t) = Box::sheared_shift(t), and moves with b's
// velocity plus (n_y image_speed, 0, 0). Whatever box a stored state lies in, these are the same
// lattice of images, so engines may leave states outside the box between collisions.

// The cells of the image of b that a sees nearest, from their separation a - b at stored time t:
// each component of the image's separation within half a side. Negating the separation negates
// the cells, bit for bit.
template <std::size_t D>
Vec<D> sheared_cells(const Vec<D>& separation, const Box<D>& box, double t) {
  // Within half a side (nearly always) the cell is 0: no division, as nearbyint would give.
  const auto nearest = [](double x, double side) {
    return std::abs(x) <= 0.5 * side ? 0.0 : std::nearbyint(x / side);
  };
  Vec<D> cells;
  cells[1] = nearest(separation[1], box.size[1]);
  const double x =
      cells[1] == 0.0 ? separation[0] : separation[0] - cells[1] * box.sheared_shift(t);
  cells[0] = nearest(x, box.size[0]);
  if constexpr (D == 3) cells[2] = nearest(separation[2], box.size[2]);
  return cells;
}

// Where the image in `cells` is, relative to the particle, at stored time t.
template <std::size_t D>
Vec<D> sheared_offset(const Vec<D>& cells, const Box<D>& box, double t) {
  Vec<D> offset;
  offset[0] = cells[0] * box.size[0] + cells[1] * box.sheared_shift(t);
  offset[1] = cells[1] * box.size[1];
  if constexpr (D == 3) offset[2] = cells[2] * box.size[2];
  return offset;
}

// The separation a - b of two stored positions, through the nearest image in a periodic box (in
// a sheared one, that of the lattice at a's stored time).
template <std::size_t D>
Vec<D> separation(const Particle<D>& a, const Particle<D>& b, const Box<D>& box) {
  const Vec<D> r = a.position - b.position;
  if (box.sheared()) [[unlikely]] {
    return r - sheared_offset(sheared_cells(r, box, a.time), box, a.time);
  }
  return image_separation(a, b, box);
}

// contact_time through the image of b in `cells` of a sheared box: the image moves in a straight
// line, so the contact is the root of the same quadratic. Symmetric in a and b bit for bit, as
// contact_time is.
template <std::size_t D>
double sheared_contact_time(const Particle<D>& a, const Particle<D>& b, const Vec<D>& cells,
                            const Box<D>& box, double limit = kNever) {
  const double t0 = std::max(a.time, b.time);
  const Vec<D> r =
      (a.time < b.time ? position_at(a, t0) - b.position : a.position - position_at(b, t0)) -
      sheared_offset(cells, box, t0);
  Vec<D> v = a.velocity - b.velocity;
  v[0] -= cells[1] * box.image_speed();
  return earliest_contact(t0, r, v, a.radius + b.radius, limit);
}

// A particle's velocity relative to the streaming profile of a sheared box, from its stored
// state: the same for every image of it (its velocity otherwise).
template <std::size_t D>
Vec<D> peculiar_velocity(const Particle<D>& p, const Box<D>& box) {
  Vec<D> c = p.velocity;
  if (box.sheared()) c[0] -= box.stream_velocity(p.position[1]);
  return c;
}

// The converse: the velocity of particle p (of its stored state, whichever image) when it moves
// at `peculiar` relative to the streaming profile.
template <std::size_t D>
Vec<D> streaming_velocity(Vec<D> peculiar, const Particle<D>& p, const Box<D>& box) {
  if (box.sheared()) peculiar[0] += box.stream_velocity(p.position[1]);
  return peculiar;
}

// Growing particles (Lubachevsky-Stillinger compression, carom compress): every radius grows
// linearly in stored time, radius(t) = radius x (1 + rate x t), `radius` being a particle's radius
// at stored time 0, so that the size ratios are kept. The functions below are the growing twins
// of next_wall_hit, contact_time, collide and bounce; with rate 0 they give the same times and
// velocities (the tests check it), but the engines call the plain ones then, which are cheaper.
inline constexpr double grown_radius(double radius, double rate, double t) {
  return radius * (1.0 + rate * t);
}

// The first wall a growing particle reaches. The gap to a wall closes at |v| + its growth speed
// moving towards the wall, and at its growth speed less |v| moving away, so a particle slower than
// it grows reaches both walls of an axis; the earlier is taken (ties: the lower |label|, then the
// lower wall).
template <std::size_t D>
constexpr WallHit growing_wall_hit(const Particle<D>& p, const Box<D>& box, double rate) {
  WallHit hit;
  if (box.periodic()) return hit;
  const double radius = grown_radius(p.radius, rate, p.time), growth = p.radius * rate;
  for (std::size_t k = 0; k < D; ++k) {
    for (const bool upper : {false, true}) {
      const double closing = (upper ? p.velocity[k] : -p.velocity[k]) + growth;
      if (!(closing > 0.0)) continue;
      const double gap = upper ? (box.size[k] - radius) - p.position[k] : p.position[k] - radius;
      const double t = p.time + std::max(gap, 0.0) / closing;
      if (t < hit.time) hit = {t, wall_label(k, upper)};
    }
  }
  return hit;
}

// When two growing particles first touch: the earliest tau >= 0 with |r + v tau|^2 =
// (sigma + sigma' tau)^2, sigma the contact distance at t0 and sigma' its growth speed, that is
// A tau^2 + 2 B tau + C = 0 with A = v^2 - sigma'^2, B = r.v - sigma sigma' (the gap closes while
// B < 0) and C = |r|^2 - sigma^2. A closing pair that touches or overlaps by round-off collides at
// once; an opening pair meets again only if the growth outruns it (A < 0), at the positive root.
// Both roots are taken in their cancellation-free forms.
template <std::size_t D>
constexpr double growing_contact_time(const Particle<D>& a, const Particle<D>& b,
                                      const Vec<D>& offset, double rate) {
  const double t0 = std::max(a.time, b.time);
  const Vec<D> r = position_at(a, t0) - position_at(b, t0) - offset;
  const Vec<D> v = a.velocity - b.velocity;
  const double sum = a.radius + b.radius;
  const double sigma = grown_radius(sum, rate, t0), speed = sum * rate;
  const double quadratic = norm2(v) - speed * speed;
  const double half_linear = dot(r, v) - sigma * speed;
  const double c = norm2(r) - sigma * sigma;
  if (half_linear < 0.0) {
    if (c <= 0.0) return t0;
    const double discriminant = half_linear * half_linear - quadratic * c;
    if (discriminant < 0.0) return kNever;
    return t0 + c / (-half_linear + std::sqrt(discriminant));
  }
  if (!(quadratic < 0.0)) return kNever;
  const double discriminant = half_linear * half_linear - quadratic * std::max(c, 0.0);
  return t0 + (half_linear + std::sqrt(discriminant)) / -quadratic;
}

// How two touching particles change velocity.
enum class Rule {
  swap,     // the classic assignment's rule: the two whole velocity vectors are exchanged
  elastic,  // momentum along the line of centres is exchanged, with masses (real hard disks)
};

// The TC model's default time: far below the mean free time of any gas worth simulating, far
// above the time resolution of a double.
inline constexpr double kDefaultTc = 1e-5;

template <>
struct EnumNames<Rule> {
  static constexpr std::array<std::pair<std::string_view, Rule>, 2> table{
      {{"swap", Rule::swap}, {"elastic", Rule::elastic}}};
};

struct CollisionRule {
  Rule rule = Rule::swap;
  // For Rule::elastic: the normal relative velocity is reversed and scaled by this (1: elastic,
  // < 1: inelastic, as in granular gases).
  double restitution = 1.0;
  // The TC model (Luding and McNamara 1998) against inelastic collapse: a collision of a
  // particle that already collided (with a wall or a particle) less than this long ago is
  // elastic, so that clusters cannot collide infinitely often in finite time.
  double elastic_within = kDefaultTc;
};

// Applies `rule` to two particles already advanced to their moment of contact; `r` is the
// separation a - b of the touching image. Returns the collision virial r . (momentum given to a),
// from which the pressure follows. Growing particles (`growth_speed`, the speed at which their
// contact distance grows) collide elastically in the frame of their moving surfaces: the rate at
// which the gap closes is reversed, so the normal relative velocity u becomes 2 growth_speed - u
// and the pair separates faster than it grows.
template <std::size_t D>
constexpr double collide(Particle<D>& a, Particle<D>& b, const Vec<D>& r, Rule rule,
                         double restitution, double mass_a, double mass_b,
                         double growth_speed = 0.0) {
  const Vec<D> before = a.velocity;
  if (rule == Rule::swap) {
    std::swap(a.velocity, b.velocity);
  } else {
    double approach = dot(a.velocity - b.velocity, r);
    if (growth_speed != 0.0) approach -= growth_speed * std::sqrt(norm2(r));
    // Impulse along r, scaled so that the normal relative velocity is reversed and scaled by the
    // restitution.
    const double j = (1.0 + restitution) * approach / ((mass_a + mass_b) * norm2(r));
    a.velocity -= (j * mass_b) * r;
    b.velocity += (j * mass_a) * r;
  }
  return mass_a * dot(r, a.velocity - before);
}

// Reflects a particle already advanced to its wall hit. The position is put exactly on the
// contact plane so that round-off can never carry a particle through a wall over long runs.
// Returns the momentum given to the wall.
template <std::size_t D>
constexpr double bounce(Particle<D>& p, int wall, const Box<D>& box, double mass) {
  const std::size_t k = wall_axis(wall);
  p.position[k] = wall_is_upper(wall) ? box.size[k] - p.radius : p.radius;
  p.velocity[k] = -p.velocity[k];
  return 2.0 * mass * std::abs(p.velocity[k]);
}

// The same for a particle growing at `rate` (see grown_radius), at stored time t: the rate at which
// the gap to the wall closes is reversed, v + g becoming -(v + g) towards the upper wall (g the
// growth speed), so the particle leaves the wall faster than it grows.
template <std::size_t D>
constexpr double growing_bounce(Particle<D>& p, int wall, const Box<D>& box, double mass,
                                double rate) {
  const std::size_t k = wall_axis(wall);
  const double radius = grown_radius(p.radius, rate, p.time), growth = p.radius * rate;
  const bool upper = wall_is_upper(wall);
  p.position[k] = upper ? box.size[k] - radius : radius;
  const double before = p.velocity[k];
  p.velocity[k] = upper ? -before - 2.0 * growth : -before + 2.0 * growth;
  return mass * std::abs(p.velocity[k] - before);
}

}  // namespace carom
