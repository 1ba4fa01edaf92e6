#include "carom/engine/engine.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <string>

#include "cell_grid.hpp"

namespace carom {

template <std::size_t D>
Engine<D>::Engine(System<D> system, const CollisionRule& rule, const Growth& growth)
    : system_(std::move(system)), rule_(rule), growth_(growth) {
  // No records at all: every particle of mass 1, nothing happened to it yet.
  if (system_.records.empty()) system_.records.resize(system_.particles.size());
  if (system_.records.size() != system_.particles.size()) {
    throw std::invalid_argument("a system needs one record per particle (or none)");
  }
  for (const Particle<D>& p : system_.particles) now_ = std::max(now_, p.time);
  largest_ = grown_radius(largest_radius(system_), growth_.rate, growth_.until);
  if (growing()) {
    for (const Particle<D>& p : system_.particles) {
      raise_speed_bound(norm2(p.velocity));
    }
  }
  if (system_.box.sheared()) {
    if (!system_.box.periodic()) throw std::invalid_argument("only a periodic box can be sheared");
    if (rule_.rule != Rule::elastic) {
      throw std::invalid_argument("a sheared box needs the elastic rule");
    }
    if (growing()) throw std::invalid_argument("a sheared box cannot grow its particles");
    fastest_ = fastest_in_box(now_);
  }
  if (system_.box.periodic()) {
    for (std::size_t k = 0; k < D; ++k) {
      if (!(system_.box.size[k] > 4.0 * largest_)) {
        throw std::invalid_argument(
            "a periodic box side must exceed two diameters of the largest particle");
      }
    }
  }
}

template <std::size_t D>
Event Engine<D>::apply(Event event) {
  // Simultaneous events are common (corners, symmetric starts) but bounded: a few per particle.
  events_at_now_ = event.time == now_ ? events_at_now_ + 1 : 0;
  if (events_at_now_ > 64 * system_.particles.size() + 1000) throw_stuck(event);
  now_ = event.time;
  const double t = event.time;
  Particle<D>& a = system_.particles[event.first];
  ParticleRecord& ra = system_.records[event.first];
  if (event.is_wall()) {
    advance(a, t);
    const Vec<D> before = a.velocity;
    if (growing()) [[unlikely]] {
      event.impulse = growing_bounce(a, event.partner, system_.box, ra.mass, growth_.rate);
      raise_speed_bound(norm2(a.velocity));
    } else {
      event.impulse = bounce(a, event.partner, system_.box, ra.mass);
    }
    for (std::size_t k = 0; k < D; ++k) event.momentum[k] = ra.mass * (a.velocity[k] - before[k]);
    ++ra.wall_collisions;
    ++ra.changes;
  } else {
    const auto j = static_cast<std::size_t>(event.partner);
    Particle<D>& b = system_.particles[j];
    ParticleRecord& rb = system_.records[j];
    // The TC model reads each particle's own last collision, never its stored time.
    event.elastic_by_tc =
        rule_.restitution < 1.0 && (t - ra.last_collision < rule_.elastic_within ||
                                    t - rb.last_collision < rule_.elastic_within);
    advance(a, t);
    advance(b, t);
    // In a sheared box b becomes the image a touches, so that the rule sees their relative
    // velocity (the wraps below bring it back); the separation is then the one seen directly.
    Vec<D> cells{};
    if (system_.box.sheared()) [[unlikely]]
      cells = to_touching_image(a, b, t);
    const double restitution = event.elastic_by_tc ? 1.0 : rule_.restitution;
    const Vec<D> r = image_separation(a, b, system_.box), before = a.velocity;
    if (growing()) [[unlikely]] {
      event.impulse = collide(a, b, r, rule_.rule, restitution, ra.mass, rb.mass,
                              (a.radius + b.radius) * growth_.rate);
      raise_speed_bound(std::max(norm2(a.velocity), norm2(b.velocity)));
    } else {
      event.impulse = collide(a, b, r, rule_.rule, restitution, ra.mass, rb.mass);
    }
    for (std::size_t k = 0; k < D; ++k) {
      event.momentum[k] = ra.mass * (a.velocity[k] - before[k]);
      event.contact[k] = r[k];
    }
    if (system_.box.sheared()) [[unlikely]] {
      back_into_sheared_box(a, b, cells);
    } else {
      wrap(a.position, system_.box, ra.image);
      wrap(b.position, system_.box, rb.image);
    }
    ra.count_pair_collision(t);
    rb.count_pair_collision(t);
    event.time = system_.absolute(t);
    return event;
  }
  ra.last_collision = t;
  event.time = system_.absolute(t);
  return event;
}

template <std::size_t D>
Vec<D> Engine<D>::to_touching_image(const Particle<D>& a, Particle<D>& b, double t) const {
  const Vec<D> cells = sheared_cells(a.position - b.position, system_.box, t);
  b.position += sheared_offset(cells, system_.box, t);
  b.velocity[0] += cells[1] * system_.box.image_speed();
  return cells;
}

template <std::size_t D>
void Engine<D>::back_into_sheared_box(Particle<D>& a, Particle<D>& b, const Vec<D>& cells) {
  const auto first = static_cast<std::size_t>(&a - system_.particles.data());
  const auto partner = static_cast<std::size_t>(&b - system_.particles.data());
  std::array<std::int32_t, 3>& partner_image = system_.records[partner].image;
  wrap(a, system_.box, system_.records[first].image);
  wrap(b, system_.box, partner_image);
  // Wrapping b back undid the move into the touching image as well as any real crossing: the
  // flags count only real crossings (the move was no journey of b's).
  for (std::size_t k = 0; k < D; ++k) add_sides(partner_image[k], -cells[k]);
  raise_speed_bound(std::max(norm2(a.velocity), norm2(b.velocity)));
}

template <std::size_t D>
void Engine<D>::rebase() {
  const double shift = now_;
  if (shift == 0.0) return;
  // Radii grow from stored time 0: a grown run is restarted instead (see Compression).
  if (growing()) throw std::logic_error("a growing engine cannot be rebased");
  // The new epoch is the absolute time step() reported for the last event, exactly.
  system_.shift_epoch(shift);
  now_ = 0.0;
  if (system_.box.sheared()) fastest_ = fastest_in_box(now_);
  rebased(shift);
}

template <std::size_t D>
void Engine<D>::move_all_to(double t) {
  if (growing()) throw std::logic_error("a growing engine cannot be intervened in");
  if (!(t >= now_)) throw std::logic_error("an intervention before the last event");
  for (std::size_t i = 0; i < system_.size(); ++i) {
    Particle<D>& p = system_.particles[i];
    p.position = position_at(p, t);
    p.time = t;
    wrap(p, system_.box, system_.records[i].image);
  }
}

template <std::size_t D>
void Engine<D>::reset_velocity(std::uint32_t i, double t, const Vec<D>& velocity) {
  if (growing()) throw std::logic_error("a growing engine cannot be intervened in");
  if (!(t >= now_)) throw std::logic_error("a velocity reset before the last event");
  Particle<D>& p = system_.particles[i];
  ParticleRecord& record = system_.records[i];
  advance(p, t);
  p.velocity = velocity;
  wrap(p, system_.box, record.image);
  ++record.changes;
  now_ = t;
  if (system_.box.sheared()) raise_speed_bound(norm2(p.velocity));
  velocity_reset(i);
}

template <std::size_t D>
void Engine<D>::restart_at(double t) {
  system_.shift_epoch(t);
  now_ = 0.0;
  events_at_now_ = 0;
  if (system_.box.sheared()) fastest_ = fastest_in_box(now_);
  rebased(t);
}

template <std::size_t D>
double Engine<D>::fastest_in_box(double t) const {
  double fastest = 0.0;
  for (const Particle<D>& p : system_.particles) {
    Particle<D> inside = p;
    advance(inside, std::max(t, p.time));
    std::array<std::int32_t, 3> image{};
    wrap(inside, system_.box, image);
    fastest = std::max(fastest, std::sqrt(norm2(inside.velocity)));
  }
  return fastest * (1.0 + 1e-9);
}

template <std::size_t D>
Vec<D> Engine<D>::image(std::uint32_t i, std::uint32_t j, double t) const {
  if (!system_.box.periodic()) return Vec<D>{};
  const auto& particles = system_.particles;
  return image_offset(position_at(particles[i], t) - position_at(particles[j], t), system_.box);
}

template <std::size_t D>
double Engine<D>::image_horizon() const {
  if (!system_.box.periodic()) return kNever;
  if (system_.box.sheared()) return image_horizon(fastest_);
  return image_horizon(growing() ? fastest_ : speed_bound(system_));
}

template <std::size_t D>
double Engine<D>::image_horizon(double speed) const {
  // Two particles close in on each other at up to twice the speed, and the images across the
  // sheared boundary slide by at the images' speed besides.
  const double closing = 2.0 * speed + std::abs(system_.box.image_speed());
  const double room = shortest_side(system_.box) / 2.0 - 2.0 * largest_;
  return closing > 0.0 ? room / closing : kNever;
}

template <std::size_t D>
std::string Engine<D>::describe_stall(const Event& event, std::string_view events) const {
  const std::string partner =
      event.is_wall() ? std::string("a wall") : fmt::format("particle {}", event.partner);
  return fmt::format("{} {} at t = {} without time advancing (particle {} and {})", events_at_now_,
                     events, system_.absolute(event.time), event.first, partner);
}

template <std::size_t D>
void Engine<D>::throw_stuck(const Event& event) const {
  const std::string stuck = describe_stall(event, "collisions");
  // The message names only a cause this run can have: a collapse needs inelastic collisions, a
  // wedge needs walls.
  if (rule_.restitution < 1.0) {
    throw JamError(fmt::format(
        "inelastic collapse: {}: with restitution {} a cluster of {} collides ever faster, "
        "infinitely often in finite time, unless the TC model keeps its collisions elastic; {}",
        stuck, rule_.restitution, kParticlesName<D>,
        rule_.elastic_within > 0.0
            ? fmt::format("a --tc longer than {} does so sooner", rule_.elastic_within)
            : std::string("--tc 0 turned it off (give it a time above 0)")));
  }
  throw JamError(fmt::format(
      "the {} are jammed: {}{}", kParticlesName<D>, stuck,
      system_.box.periodic()
          ? std::string()
          : fmt::format("; is a {} wedged exactly between two walls?", kParticleName<D>)));
}

template <std::size_t D>
void Engine<D>::throw_too_fast(double t) const {
  throw JamError(fmt::format(
      "the {} move too fast for the box: at t = {} a double cannot resolve the time it takes "
      "them to cross it ({} at most); rescale the velocities or the time unit",
      kParticlesName<D>, system_.absolute(t), image_horizon()));
}

namespace {

// Cell crossings (engine work between events) allowed in one slice of a run: a few milliseconds.
constexpr double kCrossingsPerSlice = 1e5;

}  // namespace

// No cell is narrower than the fast engine's grid makes them (at least a largest diameter, wider
// in a sparse box), and no particle is ever faster than speed_bound(). (Regression, found by the
// fuzzer: with the diameter alone, twelve points of radius 1e-41 cut time into slices of 1e-38
// and a run to t = 1 never ended.) In a sheared box every image horizon renews the predictions of
// up to every particle, however few events there are: each renewal counts as N crossings.
// (Regression: 2 disks sheared at 1e9 renewed for minutes without looking at the stop flag.)
template <std::size_t D>
double Engine<D>::slice_length() const {
  const double width =
      CellGrid<D>::least_width(system_.box, 2.0 * largest_radius(system_), system_.size());
  double crossings_per_time = moving_particles() * D * speed_bound(system_) / width;
  if (system_.box.sheared()) {
    crossings_per_time += static_cast<double>(system_.size()) / image_horizon();
  }
  return crossings_per_time > 0.0 ? kCrossingsPerSlice / crossings_per_time : kNever;
}

template class Engine<2>;
template class Engine<3>;

}  // namespace carom
