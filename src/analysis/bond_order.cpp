#include "carom/analysis/bond_order.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "analysis/neighbours.hpp"
#include "carom/analysis/analysis.hpp"

namespace carom {

namespace {

using Complex = std::complex<double>;

// Exact in a double up to 22!, more than the Wigner symbols of l <= 7 and Y_lm of l <= 11 take.
double factorial(int n) {
  double product = 1.0;
  for (int k = 2; k <= n; ++k) product *= k;
  return product;
}

// (-1)^n
double sign_of_power(int n) {
  return n % 2 == 0 ? 1.0 : -1.0;
}

// Every particle's neighbours, each list in the order the search found them.
struct NeighbourLists {
  std::vector<std::size_t> start;  // particle i's are at[start[i]] .. at[start[i + 1]]
  std::vector<std::uint32_t> at;

  std::size_t count(std::size_t i) const { return start[i + 1] - start[i]; }
};

NeighbourLists neighbours_within(Neighbours<3>& search, double cutoff) {
  NeighbourLists lists;
  lists.start.push_back(0);
  const double cutoff2 = cutoff * cutoff;
  for (std::size_t i = 0; i < search.size(); ++i) {
    search.for_each_candidate(i, cutoff, [&](std::size_t j) {
      const double r2 = norm2(search.separation(i, j));
      if (r2 < cutoff2 && r2 > 0.0) lists.at.push_back(static_cast<std::uint32_t>(j));
    });
    lists.start.push_back(lists.at.size());
  }
  return lists;
}

// Y_lm of a bond's direction for m = -l .. l, added to sum[m + l]: Y_lm = N_lm P_l^m(cos theta)
// e^(i m phi) with the Condon-Shortley phase, and Y_l,-m = (-1)^m conj(Y_lm). P_l^m carries a
// factor sin^m theta, taken with e^(i m phi) as ((x + i y) / r)^m, so that no angle is formed and
// the poles need no care; the rest, a polynomial in cos theta, comes from the upward recursion in
// the degree from P_m^m / sin^m theta = (-1)^m (2m - 1)!!.
void add_harmonics(int l, const Vec<3>& bond, Complex* sum) {
  const double r = std::sqrt(norm2(bond));
  const double cos_theta = bond[2] / r;
  const Complex sin_theta_phase(bond[0] / r, bond[1] / r);
  Complex power = 1.0;  // (sin theta e^(i phi))^m
  double diagonal = 1.0;
  for (int m = 0; m <= l; ++m) {
    double below = 0.0, legendre = diagonal;  // degrees n - 1 and n, from n = m
    for (int n = m + 1; n <= l; ++n) {
      const double next = ((2 * n - 1) * cos_theta * legendre - (n + m - 1) * below) / (n - m);
      below = legendre;
      legendre = next;
    }
    const double normalisation =
        std::sqrt((2 * l + 1) / (4.0 * std::numbers::pi) * factorial(l - m) / factorial(l + m));
    const Complex y = normalisation * legendre * power;
    sum[l + m] += y;
    if (m > 0) sum[l - m] += sign_of_power(m) * std::conj(y);
    power *= sin_theta_phase;
    diagonal *= -(2 * m + 1);
  }
}

// The terms of w_l's sum: (l l l; m1 m2 m3) with m3 = -m1 - m2, and where q_lm1, q_lm2 and
// q_lm3 are in a particle's 2l + 1 values (at m + l).
struct ThirdOrderTerm {
  int at1, at2, at3;
  double symbol;
};
std::vector<ThirdOrderTerm> third_order_terms(int l) {
  std::vector<ThirdOrderTerm> terms;
  for (int m1 = -l; m1 <= l; ++m1) {
    for (int m2 = -l; m2 <= l; ++m2) {
      const int m3 = -m1 - m2;
      if (std::abs(m3) <= l)
        terms.push_back({m1 + l, m2 + l, m3 + l, wigner_3j(l, l, l, m1, m2, m3)});
    }
  }
  return terms;
}

double squared_norm(const Complex* qlm, int l) {
  double sum = 0.0;
  for (int m = 0; m <= 2 * l; ++m) sum += std::norm(qlm[m]);
  return sum;
}

// q_l and w_l of one particle's q_lm (2l + 1 of them, m = -l first).
void add_invariants(const Complex* qlm, int l, const std::vector<ThirdOrderTerm>& terms,
                    std::vector<double>& q, std::vector<double>& w) {
  const double norm2 = squared_norm(qlm, l);
  q.push_back(std::sqrt(4.0 * std::numbers::pi / (2 * l + 1) * norm2));
  if (norm2 == 0.0) {
    w.push_back(0.0);
    return;
  }
  Complex sum = 0.0;
  for (const ThirdOrderTerm& t : terms) sum += t.symbol * qlm[t.at1] * qlm[t.at2] * qlm[t.at3];
  w.push_back(sum.real() / (norm2 * std::sqrt(norm2)));
}

// Every particle's q_lm for one l, (2l + 1) a particle.
std::vector<Complex> bond_harmonics(int l, const Neighbours<3>& search,
                                    const NeighbourLists& lists) {
  const std::size_t width = static_cast<std::size_t>(2 * l + 1), n = search.size();
  std::vector<Complex> qlm(n * width, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    Complex* own = &qlm[i * width];
    for (std::size_t b = lists.start[i]; b < lists.start[i + 1]; ++b) {
      add_harmonics(l, search.separation(i, lists.at[b]), own);
    }
    if (lists.count(i) > 0) {
      for (std::size_t m = 0; m < width; ++m) own[m] /= static_cast<double>(lists.count(i));
    }
  }
  return qlm;
}

SteinhardtInvariants invariants_of(int l, const std::vector<Complex>& qlm,
                                   const NeighbourLists& lists) {
  const std::size_t width = static_cast<std::size_t>(2 * l + 1), n = lists.start.size() - 1;
  const std::vector<ThirdOrderTerm> terms = third_order_terms(l);
  SteinhardtInvariants out;
  out.l = l;
  std::vector<Complex> average(width);
  for (std::size_t i = 0; i < n; ++i) {
    add_invariants(&qlm[i * width], l, terms, out.q, out.w);
    std::copy_n(&qlm[i * width], width, average.begin());
    for (std::size_t b = lists.start[i]; b < lists.start[i + 1]; ++b) {
      const Complex* other = &qlm[lists.at[b] * width];
      for (std::size_t m = 0; m < width; ++m) average[m] += other[m];
    }
    for (Complex& c : average) c /= static_cast<double>(lists.count(i) + 1);
    add_invariants(average.data(), l, terms, out.q_bar, out.w_bar);
  }
  return out;
}

// The solid bonds and solid-like particles of ten Wolde et al. from q6m, then the clusters.
void find_solid_clusters(const std::vector<Complex>& q6m, const NeighbourLists& lists,
                         BondOrder& order) {
  constexpr std::size_t kWidth = 13;  // 2l + 1 values of q6m a particle
  const std::size_t n = lists.start.size() - 1;
  std::vector<double> length(n);
  for (std::size_t i = 0; i < n; ++i) length[i] = std::sqrt(squared_norm(&q6m[i * kWidth], 6));
  order.solid_bonds.assign(n, 0);
  order.solid_like.assign(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t b = lists.start[i]; b < lists.start[i + 1]; ++b) {
      const std::size_t j = lists.at[b];
      // A q6 of zero (a shell of special symmetry) has no direction, so no solid bond.
      if (length[i] == 0.0 || length[j] == 0.0) continue;
      Complex product = 0.0;
      for (std::size_t m = 0; m < kWidth; ++m) {
        product += q6m[i * kWidth + m] * std::conj(q6m[j * kWidth + m]);
      }
      if (product.real() / (length[i] * length[j]) > kSolidBondProduct) ++order.solid_bonds[i];
    }
    order.solid_like[i] = order.solid_bonds[i] >= kSolidBondsNeeded;
  }
  // Connected components, each grown from its first particle through a stack.
  std::vector<int> found(n, -1);
  std::vector<std::size_t> sizes, stack;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (!order.solid_like[seed] || found[seed] >= 0) continue;
    const int label = static_cast<int>(sizes.size());
    sizes.push_back(0);
    found[seed] = label;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      ++sizes.back();
      for (std::size_t b = lists.start[i]; b < lists.start[i + 1]; ++b) {
        const std::size_t j = lists.at[b];
        if (order.solid_like[j] && found[j] < 0) {
          found[j] = label;
          stack.push_back(j);
        }
      }
    }
  }
  // Labels renumbered largest first (ties by the order found).
  std::vector<int> by_size(sizes.size());
  std::iota(by_size.begin(), by_size.end(), 0);
  std::stable_sort(by_size.begin(), by_size.end(), [&](int a, int b) {
    return sizes[static_cast<std::size_t>(a)] > sizes[static_cast<std::size_t>(b)];
  });
  std::vector<int> rank(sizes.size());
  for (std::size_t r = 0; r < by_size.size(); ++r) {
    rank[static_cast<std::size_t>(by_size[r])] = static_cast<int>(r);
    order.cluster_sizes.push_back(sizes[static_cast<std::size_t>(by_size[r])]);
  }
  order.cluster.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    order.cluster[i] = found[i] < 0 ? -1 : rank[static_cast<std::size_t>(found[i])];
  }
}

std::size_t index_of_degree(int l) {
  const auto at = std::find(kBondOrderDegrees.begin(), kBondOrderDegrees.end(), l);
  if (at == kBondOrderDegrees.end()) {
    throw std::invalid_argument(fmt::format("the bond order has no degree l = {}", l));
  }
  return static_cast<std::size_t>(at - kBondOrderDegrees.begin());
}

double mean(const std::vector<double>& values) {
  return std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

}  // namespace

double wigner_3j(int l1, int l2, int l3, int m1, int m2, int m3) {
  if (m1 + m2 + m3 != 0 || l3 < std::abs(l1 - l2) || l3 > l1 + l2 || std::abs(m1) > l1 ||
      std::abs(m2) > l2 || std::abs(m3) > l3) {
    return 0.0;
  }
  // The sum runs over every k for which no factorial's argument is negative.
  const int k_min = std::max({0, l2 - l3 - m1, l1 - l3 + m2});
  const int k_max = std::min({l1 + l2 - l3, l1 - m1, l2 + m2});
  double sum = 0.0;
  for (int k = k_min; k <= k_max; ++k) {
    sum += sign_of_power(k) /
           (factorial(k) * factorial(l3 - l2 + k + m1) * factorial(l3 - l1 + k - m2) *
            factorial(l1 + l2 - l3 - k) * factorial(l1 - k - m1) * factorial(l2 - k + m2));
  }
  const double triangle = factorial(l1 + l2 - l3) * factorial(l1 - l2 + l3) *
                          factorial(-l1 + l2 + l3) / factorial(l1 + l2 + l3 + 1);
  const double projections = factorial(l1 + m1) * factorial(l1 - m1) * factorial(l2 + m2) *
                             factorial(l2 - m2) * factorial(l3 + m3) * factorial(l3 - m3);
  return sign_of_power(l1 - l2 - m3) * std::sqrt(triangle * projections) * sum;
}

const SteinhardtInvariants& BondOrder::degree(int l) const {
  return invariants[index_of_degree(l)];
}

const SteinhardtInvariants& BondOrderSeries::degree(int l) const {
  return means[index_of_degree(l)];
}

BondOrder bond_order(const Frame& frame, const BondOrderOptions& options) {
  if (frame.dimension != 3) {
    throw std::invalid_argument("the Steinhardt bond order is defined for spheres (3D)");
  }
  BondOrder order;
  order.cutoff = options.cutoff > 0.0 ? options.cutoff
                                      : kDefaultBondOrderCutoff * shape_of(frame).mean_diameter;
  if (frame.periodic) {
    const double smallest = std::min({frame.box[0], frame.box[1], frame.box[2]});
    if (order.cutoff > 0.5 * smallest) {
      throw std::invalid_argument(fmt::format(
          "the bond order's neighbours reach r = {:g} at most in this box (half its smallest "
          "side), not {:g}",
          0.5 * smallest, order.cutoff));
    }
  }
  Neighbours<3> search(frame);
  const NeighbourLists lists = neighbours_within(search, order.cutoff);
  for (std::size_t i = 0; i < search.size(); ++i) order.neighbours.push_back(lists.count(i));
  for (std::size_t d = 0; d < kBondOrderDegrees.size(); ++d) {
    const int l = kBondOrderDegrees[d];
    const std::vector<Complex> qlm = bond_harmonics(l, search, lists);
    order.invariants[d] = invariants_of(l, qlm, lists);
    if (l == 6) find_solid_clusters(qlm, lists, order);
  }
  return order;
}

BondOrderSeries bond_order_series(const std::vector<Frame>& frames,
                                  const BondOrderOptions& options) {
  BondOrderSeries series;
  for (std::size_t d = 0; d < kBondOrderDegrees.size(); ++d) {
    series.means[d].l = kBondOrderDegrees[d];
  }
  for (const Frame& frame : frames) {
    BondOrder order = bond_order(frame, options);
    series.cutoff = order.cutoff;
    series.t.push_back(frame.time);
    for (std::size_t d = 0; d < kBondOrderDegrees.size(); ++d) {
      const SteinhardtInvariants& of = order.invariants[d];
      SteinhardtInvariants& to = series.means[d];
      to.q.push_back(mean(of.q));
      to.w.push_back(mean(of.w));
      to.q_bar.push_back(mean(of.q_bar));
      to.w_bar.push_back(mean(of.w_bar));
    }
    series.solid_like.push_back(static_cast<std::size_t>(
        std::count(order.solid_like.begin(), order.solid_like.end(), true)));
    series.largest_cluster.push_back(order.cluster_sizes.empty() ? 0 : order.cluster_sizes.front());
    series.cluster_sizes.push_back(order.cluster_sizes);
    series.last_frame = std::move(order);
  }
  return series;
}

}  // namespace carom
