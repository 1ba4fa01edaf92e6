// What moves the particles of a run: Newton's dynamics (event-driven molecular dynamics) or
// straight event-chain Monte Carlo (Bernard, Krauth and Wilson, Phys. Rev. E 80, 056704 (2009)),
// which samples the same equilibrium positions, without velocities, faster at high density.
#pragma once

#include <array>
#include <cstdint>
#include <pcg_random.hpp>
#include <string_view>
#include <utility>

#include "carom/core/names.hpp"
#include "carom/core/system.hpp"

namespace carom {

enum class SamplerKind {
  md,    // event-driven molecular dynamics: the collision rule, velocities, a temperature
  ecmc,  // event-chain Monte Carlo: positions sampled at kT = 1, a periodic box, masses 1
};

template <>
struct EnumNames<SamplerKind> {
  static constexpr std::array<std::pair<std::string_view, SamplerKind>, 2> table{
      {{"md", SamplerKind::md}, {"ecmc", SamplerKind::ecmc}}};
};

struct Sampler {
  SamplerKind kind = SamplerKind::md;
  // Event chains: the displacement of each chain, in mean diameters (its direction then turns
  // and a new particle starts the next). 0: default_chain_length.
  double chain_length = 0.0;
  std::uint64_t seed = 1;  // of the chains' particles drawn

  friend bool operator==(const Sampler&, const Sampler&) = default;
};

// The chain length Li, Nishikawa, Hoellmer, Carillo, Maggs and Krauth (J. Chem. Phys. 157,
// 234111 (2022)) use for disks: 0.24 of the side of a box of unit area (3.125 sqrt(N) lambda_0
// with lambda_0 = 0.0768 / sqrt(N)), here 0.24 V^(1/D), in mean diameters. Long enough that a
// chain carries many lifts (their cost is the lifts, not the chains), short enough that the
// directions mix.
template <std::size_t D>
double default_chain_length(const System<D>& system, double mean_diameter);

// How long a turn of event chains lasts (a chain along every axis), in time units, for a run of
// `sampler` over `particles` particles in `dimension` dimensions: a chain lasts its length over N
// (the moving particle runs at N mean diameters a unit of time). A stretch shorter than a turn has
// moved the particles along some axes only, and stretches of it are neither alike nor apart: no
// error comes from blocks shorter than it. Dynamics has no chains: 0. (`sampler.chain_length` as
// the run has it: set, not 0.)
inline double chain_turn_duration(const Sampler& sampler, std::size_t particles,
                                  std::size_t dimension) {
  if (sampler.kind != SamplerKind::ecmc) return 0.0;
  return static_cast<double>(dimension) * sampler.chain_length / static_cast<double>(particles);
}

// Throws std::invalid_argument, saying why, unless chains can run in `system`: a periodic box
// that is not sheared, every mass 1 (chains move positions only), and three cells of the largest
// diameter or more along every axis (the search's two columns of cells must hold one image of a
// particle each).
template <std::size_t D>
void check_chain_start(const System<D>& system);

// Where an event-chain run is: the active particle, the axis it moves along, the stored time its
// chain ends at, and the generator that draws the next chains' active particles. With the stored
// states, all an event-chain run continues from (a checkpoint holds it).
struct ChainState {
  std::uint32_t active = 0;
  std::uint8_t axis = 0;
  double chain_end = 0.0;
  pcg32 rng;

  friend bool operator==(const ChainState&, const ChainState&) = default;
};

}  // namespace carom
