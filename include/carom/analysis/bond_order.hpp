// The local crystalline order of spheres, for studies of nucleation and melting: the Steinhardt
// bond order q_l and w_l (l = 4 and 6), plain and averaged over neighbours, and the solid-like
// clusters built on q6. Pure functions of a frame: nothing here reads files or prints.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "carom/io/trajectory_reader.hpp"

namespace carom {

// The Wigner 3j symbol (l1 l2 l3; m1 m2 m3) by the Racah formula, 0 where its selection rules
// make it vanish. Every factorial the formula takes for l up to 7 is a whole number a double holds
// exactly (up to 22!), so the symbol is exact to the double's rounding.
double wigner_3j(int l1, int l2, int l3, int m1, int m2, int m3);

// The degrees l of the bond order: q4 and w4 tell cubic from hexagonal stacking, q6 and w6 solid
// from liquid.
inline constexpr std::array<int, 2> kBondOrderDegrees = {4, 6};

// The neighbour distance of the bond order, in mean diameters, when none is given: the first
// minimum of g(r) of dense hard spheres, so that a crystal's 12 nearest (FCC, HCP) or 8 + 6
// (BCC) are all neighbours.
inline constexpr double kDefaultBondOrderCutoff = 1.5;

// The bond of ten Wolde, Ruiz-Montero and Frenkel (1996): i-j is solid when the normalised
// product of their q6 vectors exceeds kSolidBondProduct, and a particle with at least
// kSolidBondsNeeded solid bonds is solid-like.
inline constexpr double kSolidBondProduct = 0.7;
inline constexpr std::size_t kSolidBondsNeeded = 7;

struct BondOrderOptions {
  double cutoff = 0.0;  // the neighbour distance; 0: kDefaultBondOrderCutoff mean diameters
};

// The rotational invariants of degree l, one value a particle (bond_order) or a frame's mean
// over its particles (bond_order_series):
//   q_lm(i) = (1/N_b(i)) sum over the neighbours j of Y_lm(r_ij / |r_ij|)     (Condon-Shortley)
//   q_l(i) = sqrt(4 pi / (2l + 1) sum_m |q_lm(i)|^2)
//   w_l(i) = sum over m1 + m2 + m3 = 0 of (l l l; m1 m2 m3) q_lm1 q_lm2 q_lm3 / (sum_m
//   |q_lm|^2)^(3/2)
// (Steinhardt, Nelson and Ronchetti 1983), and q_bar, w_bar the same of the Lechner-Dellago
// average q_bar_lm(i) = (q_lm(i) + sum over the neighbours j of q_lm(j)) / (N_b(i) + 1) (J. Chem.
// Phys. 129, 114707 (2008)). A particle without neighbours has q_lm = 0: q_l = 0, and w_l (0/0)
// is taken as 0, no order.
struct SteinhardtInvariants {
  int l = 0;
  std::vector<double> q, w, q_bar, w_bar;
};

// The bond order of every particle of one frame. The neighbours of particle i are every other
// particle j closer than `cutoff` to it (|r_ij| < cutoff, by minimum image in a periodic box),
// however many there are, so that the relation is symmetric; a particle at the very same position
// as i gives no direction and is not one.
struct BondOrder {
  double cutoff = 0.0;
  std::vector<std::size_t> neighbours;             // N_b(i)
  std::array<SteinhardtInvariants, 2> invariants;  // of kBondOrderDegrees, in order
  std::vector<std::size_t> solid_bonds;            // how many of i's bonds are solid
  std::vector<bool> solid_like;                    // at least kSolidBondsNeeded solid bonds
  // The clusters: the connected components of the solid-like particles over neighbour bonds,
  // largest first; each particle's index into cluster_sizes, -1 if it is not solid-like.
  std::vector<std::size_t> cluster_sizes;
  std::vector<int> cluster;

  const SteinhardtInvariants& degree(int l) const;
};

// Throws std::invalid_argument for disks, or for a cutoff beyond half the smallest side of a
// periodic box (a neighbour could then be one through two of its images).
BondOrder bond_order(const Frame& frame, const BondOrderOptions& options = {});

// Per frame: the means of the invariants over the particles, the number of solid-like particles,
// the largest cluster's size (0 without one) and every cluster's size, largest first; and the
// last frame's bond order, particle by particle.
struct BondOrderSeries {
  double cutoff = 0.0;
  std::vector<double> t;
  std::array<SteinhardtInvariants, 2> means;  // of kBondOrderDegrees, in order
  std::vector<std::size_t> solid_like, largest_cluster;
  std::vector<std::vector<std::size_t>> cluster_sizes;
  BondOrder last_frame;

  const SteinhardtInvariants& degree(int l) const;
};
BondOrderSeries bond_order_series(const std::vector<Frame>& frames,
                                  const BondOrderOptions& options = {});

}  // namespace carom
