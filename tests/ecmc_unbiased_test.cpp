// Event chains sample the equilibrium dynamics samples: at one small state point, independent
// replicas of each give the same Z (the lifts' estimator against the collision virial) and the
// same g(r), within their errors. Seconds long: CTest label `long`. Sabotaged once by a lift that
// stops the mover 1% of a diameter short of contact (its g(r) loses the first bins and its Z
// moves): both comparisons failed.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "carom/analysis/analysis.hpp"
#include "carom/core/statistics.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/simulation.hpp"

namespace carom {
namespace {

constexpr std::size_t kParticles = 100;
constexpr double kPacking = 0.55;
constexpr int kReplicas = 8;
constexpr double kEquilibrate = 50.0, kMeasure = 600.0, kFrameEvery = 2.0;

System<2> gas(std::uint64_t seed) {
  InitialOptions options;
  options.n = kParticles;
  options.packing_fraction = kPacking;
  options.boundary = Boundary::periodic;
  options.placement = Placement::lattice;
  options.seed = seed;
  options.temperature = 1.0;
  return make_initial<2>(options);
}

Frame frame_of(const Simulation<2>& simulation) {
  Frame frame;
  frame.time = simulation.time();
  frame.dimension = 2;
  frame.periodic = true;
  const Box<2>& box = simulation.state().box;
  frame.box = {box.size[0], box.size[1], 0.0};
  for (const Particle<2>& p : simulation.snapshot()) {
    frame.position.push_back({p.position[0], p.position[1], 0.0});
    frame.radius.push_back(p.radius);
  }
  return frame;
}

struct Sampled {
  std::vector<double> z;               // a replica's Z over its window
  std::vector<std::vector<double>> g;  // a replica's g(r)
  std::vector<double> r;
};

Sampled sample(const Settings& settings) {
  Sampled s;
  for (int replica = 0; replica < kReplicas; ++replica) {
    Settings seeded = settings;
    seeded.sampler.seed = 100 + static_cast<std::uint64_t>(replica);
    Simulation<2> simulation(gas(1 + static_cast<std::uint64_t>(replica)), seeded);
    simulation.measure_from(kEquilibrate);
    std::vector<Frame> frames;
    for (double t = kEquilibrate; t <= kEquilibrate + kMeasure; t += kFrameEvery) {
      simulation.run_until(t);
      frames.push_back(frame_of(simulation));
    }
    s.z.push_back(simulation.observables().compressibility_factor);
    const Rdf rdf = radial_distribution(frames, {0.05, 2.5});
    s.g.push_back(rdf.g);
    s.r = rdf.r;
  }
  return s;
}

TEST(EcmcUnbiased, ChainsAndDynamicsGiveTheSameZAndPairStructure) {
  Settings dynamics;
  dynamics.rule = {Rule::elastic, 1.0, 0.0};
  Settings chains;
  chains.sampler = {SamplerKind::ecmc, 0.0, 1};
  const Sampled md = sample(dynamics), mc = sample(chains);

  const auto [z_md, var_md] = mean_and_variance_of_mean(md.z);
  const auto [z_mc, var_mc] = mean_and_variance_of_mean(mc.z);
  const double sigma = std::sqrt(var_md + var_mc);
  EXPECT_LT(std::abs(z_md - z_mc), 3.5 * sigma)
      << "dynamics " << z_md << ", chains " << z_mc << ", combined error " << sigma;
  EXPECT_LT(sigma, 0.01 * z_md) << "too few samples for the comparison to mean anything";

  // g(r) bin by bin, errors from the replicas' spread: chi^2 per bin about 1 when they agree.
  double chi2 = 0.0;
  int bins = 0;
  std::vector<double> md_bin(kReplicas), mc_bin(kReplicas);
  for (std::size_t b = 0; b < md.r.size(); ++b) {
    if (md.r[b] < 1.0) continue;  // inside contact: empty in both
    for (int k = 0; k < kReplicas; ++k) md_bin[k] = md.g[k][b], mc_bin[k] = mc.g[k][b];
    const auto [a, va] = mean_and_variance_of_mean(md_bin);
    const auto [c, vc] = mean_and_variance_of_mean(mc_bin);
    if (va + vc <= 0.0) continue;
    chi2 += (a - c) * (a - c) / (va + vc);
    ++bins;
  }
  ASSERT_GT(bins, 20);
  // With 8 replicas the variance estimates are rough (chi^2 per bin has a heavy tail): 2 per bin
  // is far beyond what agreement gives and far below what a biased sampler gives.
  EXPECT_LT(chi2 / bins, 2.0) << "chi^2 " << chi2 << " over " << bins << " bins";
}

}  // namespace
}  // namespace carom
