// The momentum and energy fluxes of a run, integrated over time: the pressure tensor over any
// interval, and the Einstein-Helfand moments the shear viscosity and the thermal conductivity
// follow from. Kept event by event (Simulation::track_fluxes), in both engines alike.
//
// Between collisions the particles carry momentum and energy at a constant rate (the kinetic
// parts); at a collision the pair exchanges them across its contact vector at once (the
// collisional parts). So the time integral of V P_ab (the pressure tensor times the volume) is
//   G_ab(t) = integral of sum_i m v_ia v_ib dt + sum over collisions of r_a dp_b,
// and the one of V J_a (the heat flux) is
//   H_a(t) = integral of sum_i (m v_i^2 / 2) v_ia dt + sum over collisions of r_a dE,
// with r the contact vector (first minus partner), dp and dE the momentum and energy the first
// particle received. Walls are outside: like `pressure`, the tensor is the bulk's.
#pragma once

#include <array>
#include <cstddef>
#include <utility>

#include "carom/core/event.hpp"
#include "carom/core/system.hpp"
#include "carom/core/vec.hpp"

namespace carom {

// A symmetric tensor's components in the order xx, yy, zz, xy, xz, yz (the z ones 0 in 2D).
using SymmetricTensor = std::array<double, 6>;
inline constexpr std::array<const char*, 6> kTensorComponents{"xx", "yy", "zz", "xy", "xz", "yz"};
// The two axes of each component, in the order above.
inline constexpr std::array<std::pair<std::size_t, std::size_t>, 6> kTensorAxes{
    {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}}};
// The components a dimension has, in the order above: xx, yy, xy in 2D, all six in 3D.
template <std::size_t D>
constexpr std::array<std::size_t, D == 2 ? 3 : 6> tensor_components() {
  if constexpr (D == 2) {
    return {0, 1, 3};
  } else {
    return {0, 1, 2, 3, 4, 5};
  }
}

// Adds sym(a b) to the components of t a dimension has, in place (per event: no zeros touched).
template <std::size_t D>
constexpr void add_symmetric_outer(SymmetricTensor& t, const Vec<D>& a, const Vec<D>& b) {
  t[0] += a[0] * b[0];
  t[1] += a[1] * b[1];
  t[3] += 0.5 * (a[0] * b[1] + a[1] * b[0]);
  if constexpr (D == 3) {
    t[2] += a[2] * b[2];
    t[4] += 0.5 * (a[0] * b[2] + a[2] * b[0]);
    t[5] += 0.5 * (a[1] * b[2] + a[2] * b[1]);
  }
}

// The velocity the kinetic rates are kept with (see above): w in a sheared box, else v.
template <std::size_t D>
Vec<D> flux_velocity(const Particle<D>& p, const Box<D>& box) {
  if (!box.sheared()) return p.velocity;
  Vec<D> w = p.velocity;
  w[0] -= box.stream_velocity(p.position[1] - p.velocity[1] * p.time);
  return w;
}

// The fluxes since some time: each integral up to `time`, and the kinetic rates then. The
// integrals step on stored times (System::epoch), which resolve a run alike at any absolute
// time, so that a run gives the same integrals whenever it starts.
struct Fluxes {
  SymmetricTensor kinetic_stress{};          // integral of sum m v v dt
  SymmetricTensor collisional_stress{};      // sum of r dp (symmetrised)
  std::array<double, 3> kinetic_heat{};      // integral of sum (m v^2 / 2) v dt
  std::array<double, 3> collisional_heat{};  // sum of r dE
  SymmetricTensor stress_rate{};             // sum m v v now (sum m w w when sheared)
  std::array<double, 3> heat_rate{};         // sum (m v^2 / 2) v now
  double since = 0.0;                        // absolute: when the integrals began
  double time = 0.0;                         // absolute: the integrals' end
  double stored = 0.0;                       // `time` as a stored time
  // Whether the heat flux is kept (a run measuring its thermal conductivity asks for it: it costs
  // more per event than the momentum flux); without it the heat fields stay 0.
  bool heat = false;
  // The box's shear rate (Box::shear_rate): the kinetic stress is then the one relative to the
  // streaming profile.
  double shear_rate = 0.0;

  friend bool operator==(const Fluxes&, const Fluxes&) = default;

  // The integrals brought to the absolute time `now`, which is `now_stored` as a stored time
  // (not before `stored`).
  Fluxes advanced(double now, double now_stored) const {
    Fluxes f = *this;
    f.integrate_to(now_stored);
    f.time = now;
    return f;
  }

  // Adds the kinetic integrals from `stored` to the stored time `to`, and moves `stored` there.
  void integrate_to(double to) {
    const double dt = to - stored;
    for (std::size_t c = 0; c < 6; ++c) kinetic_stress[c] += stress_rate[c] * dt;
    if (shear_rate != 0.0) {
      // The drift of c_x (see above): the integrals of t and t^2 over the step.
      const double g = shear_rate, t1 = stored, t2 = to;
      const double linear = dt * (t1 + t2) / 2.0, square = dt * (t1 * t1 + t1 * t2 + t2 * t2) / 3.0;
      kinetic_stress[0] += -2.0 * g * stress_rate[3] * linear + g * g * stress_rate[1] * square;
      kinetic_stress[3] += -g * stress_rate[1] * linear;
      kinetic_stress[4] += -g * stress_rate[5] * linear;
    }
    for (std::size_t k = 0; k < 3; ++k) kinetic_heat[k] += heat_rate[k] * dt;
    stored = to;
  }

  // What an event-chain lift adds: the moving particle stops and the one it touched moves on
  // with its velocity, so the kinetic rates stay as they were (exactly: add_event would add
  // zeros) and the kinetic integrals need not be brought to the event; only the collisional
  // stress sym(r dp) changes. The integrals stay at `stored` until the next velocity change
  // (change_velocity), rebase or look (advanced). Added to `collisional_stress`, the fluxes' own
  // or a copy held over a batch of lifts (LiftTally).
  template <std::size_t D>
  static void add_lift(SymmetricTensor& collisional_stress, const Event& event) {
    Vec<D> dp, r;
    for (std::size_t k = 0; k < D; ++k) {
      dp[k] = event.momentum[k];
      r[k] = event.contact[k];
    }
    add_symmetric_outer<D>(collisional_stress, r, dp);
  }

  // Brings the integrals to the time of a processed event, `event_stored` as a stored time (as
  // advanced() does, in place), then adds what the event did, from the velocities after it
  // (`first_after`, and `partner_after` for a pair) and the momentum dp the first particle
  // received. Per event, so in few operations: a particle of mass m whose velocity goes from v to
  // v' = v + dp / m changes sum m v v by sym(dp (v + v')) and its energy by dp . (v + v') / 2, so
  // a pair changes the kinetic rate by sym(dp (a + a' - b - b')), one outer product, and
  // transfers sym(r dp) and r dE across its contact r.
  //
  // In a sheared box the velocities are w's (flux_velocity), which a momentum dp changes by
  // (dp_x + shear_rate t dp_y, dp_y, dp_z) / m at stored time t (y0 moves as vy changes).
  template <std::size_t D>
  void add_event(const Event& event, double event_stored, double first_mass,
                 const Vec<D>& first_after, double partner_mass, const Vec<D>& partner_after) {
    if (shear_rate != 0.0) [[unlikely]] {
      add_event_as<D, true>(event, event_stored, first_mass, first_after, partner_mass,
                            partner_after);
    } else {
      add_event_as<D, false>(event, event_stored, first_mass, first_after, partner_mass,
                             partner_after);
    }
  }

  // Brings the integrals to the stored time `at` (the absolute `now`), where a particle of mass
  // m had its velocity (flux_velocity) changed from `before` to `after` other than by a
  // collision (a thermostat's reset): the kinetic rates follow.
  template <std::size_t D>
  void change_velocity(double now, double at, double mass, const Vec<D>& before,
                       const Vec<D>& after) {
    integrate_to(at);
    time = now;
    add_symmetric_outer<D>(stress_rate, mass * (after - before), after + before);
    if (!heat) return;
    const double energy_after = 0.5 * mass * norm2(after);
    const double energy_before = 0.5 * mass * norm2(before);
    for (std::size_t k = 0; k < D; ++k) {
      heat_rate[k] += energy_after * after[k] - energy_before * before[k];
    }
  }

  // The Einstein-Helfand moments: the integral of V P_ab, and of V J_a.
  SymmetricTensor stress_moment() const {
    SymmetricTensor g{};
    for (std::size_t c = 0; c < 6; ++c) g[c] = kinetic_stress[c] + collisional_stress[c];
    return g;
  }
  std::array<double, 3> heat_moment() const {
    std::array<double, 3> h{};
    for (std::size_t k = 0; k < 3; ++k) h[k] = kinetic_heat[k] + collisional_heat[k];
    return h;
  }

  // add_event, its few shear terms compiled in or out (a run not sheared pays nothing for them),
  // for a caller that knows which (Sheared: shear_rate is not 0).
  template <std::size_t D, bool Sheared>
  void add_event_as(const Event& event, double event_stored, double first_mass,
                    const Vec<D>& first_after, double partner_mass, const Vec<D>& partner_after) {
    if constexpr (Sheared) {
      integrate_to(event_stored);
    } else {
      const double dt = event_stored - stored;
      for (const std::size_t c : tensor_components<D>()) kinetic_stress[c] += stress_rate[c] * dt;
      if (heat) {
        for (std::size_t k = 0; k < D; ++k) kinetic_heat[k] += heat_rate[k] * dt;
      }
      stored = event_stored;
    }
    time = event.time;

    Vec<D> dp, r;
    for (std::size_t k = 0; k < D; ++k) {
      dp[k] = event.momentum[k];
      r[k] = event.contact[k];
    }
    Vec<D> dw = dp;
    if constexpr (Sheared) dw[0] += shear_rate * event_stored * dp[1];
    const auto carried_heat = [this](double mass, const Vec<D>& before, const Vec<D>& after) {
      const double energy_after = 0.5 * mass * norm2(after);
      const double energy_before = 0.5 * mass * norm2(before);
      for (std::size_t k = 0; k < D; ++k) {
        heat_rate[k] += energy_after * after[k] - energy_before * before[k];
      }
    };
    const Vec<D> first_before = first_after - (1.0 / first_mass) * dw;
    if (event.is_wall()) {
      add_symmetric_outer<D>(stress_rate, dw, first_before + first_after);
      if (heat) carried_heat(first_mass, first_before, first_after);
      return;
    }
    const Vec<D> partner_before = partner_after + (1.0 / partner_mass) * dw;
    add_symmetric_outer<D>(stress_rate, dw,
                           (first_before + first_after) - (partner_before + partner_after));
    add_symmetric_outer<D>(collisional_stress, r, dp);
    if (!heat) return;
    carried_heat(first_mass, first_before, first_after);
    carried_heat(partner_mass, partner_before, partner_after);
    const double energy = 0.5 * dot(dp, first_before + first_after);
    for (std::size_t k = 0; k < D; ++k) collisional_heat[k] += r[k] * energy;
  }
};

// Fluxes starting at the absolute time t (`stored` as a stored time), with the rates of the
// system's velocities (the heat flux's with `heat`).
template <std::size_t D>
Fluxes fluxes_of(const System<D>& system, double t, double stored, bool heat) {
  Fluxes f;
  f.heat = heat;
  f.shear_rate = system.box.shear_rate;
  for (std::size_t i = 0; i < system.size(); ++i) {
    const double mass = system.records[i].mass;
    const Vec<D> v = flux_velocity(system.particles[i], system.box);
    add_symmetric_outer<D>(f.stress_rate, mass * v, v);
    if (!heat) continue;
    const double energy = 0.5 * mass * norm2(v);
    for (std::size_t k = 0; k < D; ++k) f.heat_rate[k] += energy * v[k];
  }
  f.since = f.time = t;
  f.stored = stored;
  return f;
}

// The integrals between two flux records of one run, each brought to its own time (advanced()):
// `later`'s time and rates with the integrals since `earlier`.
inline Fluxes flux_difference(const Fluxes& later, const Fluxes& earlier) {
  Fluxes d = later;
  d.since = earlier.time;
  for (std::size_t c = 0; c < 6; ++c) {
    d.kinetic_stress[c] -= earlier.kinetic_stress[c];
    d.collisional_stress[c] -= earlier.collisional_stress[c];
  }
  for (std::size_t k = 0; k < 3; ++k) {
    d.kinetic_heat[k] -= earlier.kinetic_heat[k];
    d.collisional_heat[k] -= earlier.collisional_heat[k];
  }
  return d;
}

// The pressure tensor between two flux records of one run: the difference of their moments
// over the time between and the volume. Taken from the moments alone (not their kinetic and
// collisional parts), so that a log continued from the moments it wrote gives the same rows.
inline SymmetricTensor pressure_tensor_between(const Fluxes& later, const Fluxes& earlier,
                                               double volume) {
  const SymmetricTensor now = later.stress_moment(), then = earlier.stress_moment();
  SymmetricTensor p{};
  for (std::size_t c = 0; c < 6; ++c)
    p[c] = (now[c] - then[c]) / ((later.time - earlier.time) * volume);
  return p;
}

}  // namespace carom
