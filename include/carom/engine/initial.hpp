// Start configurations: non-overlapping disks (D = 2) or spheres (D = 3) at a chosen packing
// fraction with Maxwell-Boltzmann velocities, reproducible bit for bit from a seed.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <pcg_random.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "carom/core/names.hpp"
#include "carom/core/random.hpp"
#include "carom/core/system.hpp"

namespace carom {

enum class Placement {
  automatic,  // random up to random_placement_limit unless it jams, else the lattice
  random,     // random sequential placement
  lattice,    // a triangular (2D) or face-centred cubic (3D) lattice: both reach close packing
};

template <>
struct EnumNames<Placement> {
  static constexpr std::array<std::pair<std::string_view, Placement>, 3> table{
      {{"auto", Placement::automatic},
       {"random", Placement::random},
       {"lattice", Placement::lattice}}};
};

// The radius of a start whose box is not given: diameter 1, the unit of length.
inline constexpr double kDefaultRadius = 0.5;

// One species of a mixture start: its name, its number fraction and its particles' diameter (in
// the unit the box is derived in: diameter 1 is the default start's).
struct Species {
  std::string name;
  double fraction = 0.0;
  double diameter = 0.0;

  friend bool operator==(const Species&, const Species&) = default;
};

struct InitialOptions {
  std::uint64_t n = 0;
  double packing_fraction = 0.0;
  std::vector<double> box;       // the box's D sides; empty: from the packing fraction and aspect
  double aspect = 1.0;           // Lx / Ly of a derived box (in 3D Lz = Ly)
  std::optional<double> radius;  // the mean radius; default 0.5 (diameter 1), or derived
                                 // from the packing fraction when the box is given
  double polydispersity = 0.0;   // standard deviation of the radius / its mean (uniform)
  double temperature = 1.0;      // kT, masses 1
  std::uint64_t seed = 1;
  // Periodic: the bulk a study means (walls add a surface that biases the pressure, and are on
  // request).
  Boundary boundary = Boundary::periodic;
  Placement placement = Placement::automatic;
  // A mixture: each species' share of the n particles (largest remainder) at its diameter, types
  // placed in an order shuffled by the seed. Empty: one species "A" (radius, polydispersity).
  std::vector<Species> species;
};

// The species of `carom init --species` and carom.init(species=...): "NAME:FRACTION:DIAMETER"
// entries separated by commas, as "A:0.5:1.0,B:0.5:1.4". Names are distinct, of letters, digits
// and _ . + - (a file's one token); fractions above 0 summing to 1 within 1e-12; diameters finite
// and above 0. Throws InitialError saying what is wrong.
std::vector<Species> parse_species(std::string_view text);
// The species as parse_species reads them (round trip), for messages and sweep plans.
std::string species_text(const std::vector<Species>& species);
// The counts of n particles in the species' fractions, by largest remainder (ties to the first):
// they sum to n.
std::vector<std::uint64_t> species_counts(const std::vector<Species>& species, std::uint64_t n);

// A request that cannot be met (packing fraction above close packing, a random placement that
// jams, conflicting sizes), with a message saying why.
class InitialError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Close packing of equal disks, the triangular lattice: pi / (2 sqrt 3).
inline constexpr double kClosePacking = 0.9068996821171089;
// Close packing of equal spheres, face-centred cubic (Kepler, Hales): pi / (3 sqrt 2).
inline constexpr double kClosePackingSpheres = 0.7404804896930610;

constexpr double close_packing(std::size_t dimension) {
  return dimension == 2 ? kClosePacking : kClosePackingSpheres;
}
// Automatic placement is random up to here, below where random sequential addition slows down
// sharply (it saturates near 0.547 for disks and 0.384 for spheres).
constexpr double random_placement_limit(std::size_t dimension) {
  return dimension == 2 ? 0.4 : 0.25;
}

// Velocities are Maxwell-Boltzmann at `temperature`, shifted to zero total momentum and scaled so
// that the kinetic temperature is kT exactly (over D N degrees of freedom with walls, D (N - 1) in
// a periodic box). Radii (polydisperse) are uniform around the mean. Particles are numbered along
// a space-filling curve, so that neighbours in space are neighbours in memory.
template <std::size_t D>
System<D> make_initial(const InitialOptions& options);

// Throws the InitialError make_initial would for options no start of `dimension` (2 or 3) can
// have (a packing fraction above close packing, a polydispersity above 0.5, ...), without
// making one. A random placement that jams is found only by making it.
void check_initial_options(std::size_t dimension, const InitialOptions& options);

// Gives every particle of `system` a velocity as make_initial does (Maxwell-Boltzmann at
// `temperature` over each mass, zero total momentum, kinetic temperature kT exactly), from pcg32
// seeded with `seed`: for a start that has none, or is to be rethermalised. Throws
// std::invalid_argument for a temperature that is not a number above 0.
template <std::size_t D>
void draw_velocities(System<D>& system, double temperature, std::uint64_t seed);

// The particles' mean diameter.
template <std::size_t D>
double mean_diameter(const System<D>& system);

// The same configuration in another unit of length: the box, every position and radius times
// `factor` (> 0), velocities kept (so kT, Z and the packing fraction are unchanged). A packing
// compressed from diameter 1 is brought back to a mean diameter of 1 with 1 / mean_diameter.
template <std::size_t D>
void scale_lengths(System<D>& system, double factor);

}  // namespace carom
