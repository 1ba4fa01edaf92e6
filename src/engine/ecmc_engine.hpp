// Straight event-chain Monte Carlo (Bernard, Krauth and Wilson, Phys. Rev. E 80, 056704 (2009)) as
// an engine: one particle, the active one, moves along +x (then +y, then +z in 3D, in turn) at
// constant speed while every other rests; when it touches another it stops and hands its velocity
// on (a lift), and the one struck carries the rest of the displacement. After a chain of
// `chain_length` mean diameters of displacement the direction turns and a new active particle is
// drawn uniformly at random. No move is ever rejected, and the moves sample the equilibrium of
// hard particles at any temperature.
//
// A lift is the swap rule's collision of a moving particle with one at rest, so the engine speaks
// the engines' language: stored (lazy) states with times, lifts as pair events with the momentum
// they carry (unit masses), the epoch and its rebasing. The active particle moves at N times the
// mean diameter per unit time, so that a unit of time moves every particle one diameter on
// average. With it the virial and the kinetic temperature (m v^2 / (D N), the one moving
// particle's) give ECMC's pressure exactly: Z = 1 + (sum over lifts of the separation along the
// move) / (the displacement) (Michel, Kapfer and Krauth, J. Chem. Phys. 140, 054116 (2014)).
//
// Candidates come from a cell grid: a particle the active one touches while inside its cell lies
// in the block of cells around it, and not in the layer behind (CellGrid::for_each_ahead), so the
// nearest lift there is the next event if it comes before the active particle leaves its cell;
// otherwise the cell changes and the cells are searched again. No calendar: the next event is
// always the active particle's.
#pragma once

#include <cstdint>
#include <optional>
#include <pcg_random.hpp>

#include "carom/engine/engine.hpp"
#include "carom/engine/sampler.hpp"
#include "cell_grid.hpp"

namespace carom {

template <std::size_t D>
class EcmcEngine final : public Engine<D> {
 public:
  // Starts chains in `system` (a periodic box; velocities are ignored and masses taken as 1): the
  // first active particle is drawn from `rng`, moving along x. `chain_length` in mean diameters.
  EcmcEngine(System<D> system, double chain_length, pcg32 rng);
  // Continues from `chain`, with `system`'s stored states as an EcmcEngine left them.
  EcmcEngine(System<D> system, double chain_length, const ChainState& chain);

  std::optional<Event> step(double end_time) override;

  const ChainState& chain() const { return chain_; }
  // The active particle's speed: N mean diameters per unit time.
  double speed() const { return speed_; }

 private:
  void rebased(double shift) override { chain_.chain_end -= shift; }
  void velocity_reset(std::uint32_t) override;

  // Stops the active particle at the chain's end and starts the next chain.
  void start_next_chain();
  // The nearest lift of the active particle `a` among the particles around its cell: the partner
  // and the distance from a's stored position (kNever if none).
  std::pair<std::uint32_t, double> nearest_lift(const Particle<D>& a) const;
  // Draws the next chain's active particle, at rest until now, and sets it moving along the
  // chain's axis from stored time t.
  void start_moving_at(double t);

  double chain_duration_ = 0.0;  // stored time a chain lasts
  double speed_ = 0.0;
  ChainState chain_;
  CellGrid<D> grid_;
};

}  // namespace carom
