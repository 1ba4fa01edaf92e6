// Transport coefficients (transport.hpp): the estimators on series with known answers, Enskog's
// values in their dilute limit, and a measurement continued from a checkpoint bit for bit.
#include "carom/core/transport.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <pcg_random.hpp>
#include <sstream>
#include <variant>

#include "carom/engine/initial.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/checkpoint.hpp"
#include "run/transport_meter.hpp"

namespace carom {
namespace {

TEST(Transport, MeanSquareIncrementAveragesOverOrigins) {
  const std::vector<double> x{0.0, 1.0, 3.0, 6.0};
  EXPECT_EQ(mean_square_increment(x, 1), (1.0 + 4.0 + 9.0) / 3.0);
  EXPECT_EQ(mean_square_increment(x, 2), (9.0 + 25.0) / 2.0);
  EXPECT_THROW(mean_square_increment(x, 0), std::invalid_argument);
  EXPECT_THROW(mean_square_increment(x, 4), std::invalid_argument);
}

TEST(Transport, TheSlopeOfARandomWalkIsItsDiffusion) {
  // Steps of +-1 every 0.5: <dx^2> = lag, growing at 2 per unit time.
  pcg32 rng(7);
  std::vector<double> x{0.0};
  for (int j = 0; j < 200000; ++j) x.push_back(x.back() + ((rng() & 1U) != 0 ? 1.0 : -1.0));
  EXPECT_NEAR(einstein_helfand_slope(x, 40, 0.5), 2.0, 0.05);
  // A drift without noise (ballistic) has <dx^2> = (v tau)^2: the slope between tau / 2 and tau
  // is v^2 (tau^2 - tau^2 / 4) / (tau / 2).
  std::vector<double> line;
  for (int j = 0; j < 100; ++j) line.push_back(3.0 * j);
  EXPECT_DOUBLE_EQ(einstein_helfand_slope(line, 10, 1.0), 9.0 * (100.0 - 25.0) / 5.0);
}

TEST(Transport, EnskogValuesReachTheDiluteGasOnes) {
  const double pi = std::numbers::pi;
  const double phi = 1e-9, n = 6.0 * phi / pi;
  const auto [d, eta, lambda] = enskog_spheres(phi, 1.0, 1.0, 1.0);
  EXPECT_NEAR(d * n / (1.01896 * 3.0 / 8.0 / std::sqrt(pi)), 1.0, 1e-7);
  EXPECT_NEAR(eta / (1.016 * 5.0 / 16.0 / std::sqrt(pi)), 1.0, 1e-7);
  EXPECT_NEAR(lambda / (1.02513 * 75.0 / 64.0 / std::sqrt(pi)), 1.0, 1e-7);
  // Denser, the collisional transfer raises the viscosity above the dilute value and the
  // contact value lowers the diffusion below its 1 / n law.
  const auto [d3, eta3, lambda3] = enskog_spheres(0.3, 1.0, 1.0, 1.0);
  EXPECT_GT(eta3, 2.0 * eta);
  EXPECT_GT(lambda3, 2.0 * lambda);
  EXPECT_LT(d3 * 6.0 * 0.3 / pi, d * n);
}

template <std::size_t D>
System<D> fluid(std::uint64_t n, double phi) {
  InitialOptions o;
  o.n = n;
  o.packing_fraction = phi;
  o.seed = 3;
  o.boundary = Boundary::periodic;
  return make_initial<D>(o);
}

// A measurement stopped halfway, saved with its simulation and continued, ends with the record
// of one never stopped, bit for bit.
template <std::size_t D>
void expect_continued_measurement_equal(std::uint64_t n, double phi, double end) {
  Simulation<D> whole(fluid<D>(n, phi), {{Rule::elastic}});
  whole.keep_heat_flux();  // as a run with --transport does
  auto whole_meter = std::make_shared<TransportMeter<D>>(whole.state(), 0.0, end, std::nullopt);
  whole.add_observer(whole_meter);
  whole.run_until(end);
  ASSERT_EQ(whole_meter->record().blocks.size(), TransportMeter<D>::kLeastBlocks);
  const auto estimate = whole_meter->estimate(whole.state());
  ASSERT_TRUE(estimate.has_value());
  EXPECT_GT(estimate->self_diffusion, 0.0);
  EXPECT_GT(estimate->shear_viscosity, 0.0);
  EXPECT_GT(estimate->thermal_conductivity, 0.0);

  Simulation<D> first(fluid<D>(n, phi), {{Rule::elastic}});
  first.keep_heat_flux();
  auto first_meter = std::make_shared<TransportMeter<D>>(first.state(), 0.0, end, std::nullopt);
  first.add_observer(first_meter);
  first.run_until(0.43 * end);
  Checkpoint<D> saved = first.checkpoint("test");
  saved.records.transport = first_meter->record();
  std::stringstream file;
  write_checkpoint(file, saved);
  const auto read = std::get<Checkpoint<D>>(read_checkpoint(file, "saved"));
  ASSERT_EQ(read.records.transport, first_meter->record());
  Simulation<D> resumed(read);
  auto resumed_meter =
      std::make_shared<TransportMeter<D>>(resumed.state(), 0.0, end, read.records.transport);
  resumed.add_observer(resumed_meter);
  resumed.run_until(end);
  EXPECT_EQ(resumed_meter->record(), whole_meter->record());
}

TEST(Transport, ALongWindowHasMoreBlocksOfTheSameLag) {
  // Spheres at 0.3 collide about every 0.16: a lag of 50 collision times, 4 lags a block.
  const System<3> spheres = fluid<3>(500, 0.3);
  const double t_c = enskog_collision_time(3, 0.3, 1.0, 1.0, 1.0);
  EXPECT_NEAR(t_c,
              1.0 / (4.0 * std::sqrt(std::numbers::pi) * (1.8 / std::numbers::pi) *
                     (0.85 / (0.7 * 0.7 * 0.7))),
              1e-12);
  const double lag = TransportMeter<3>::lag_spacing(spheres);
  EXPECT_NEAR(lag * 64.0, 50.0 * t_c, 0.05 * t_c);  // kT of the start: 1 within rounding
  EXPECT_EQ(TransportMeter<3>::spacing(lag, 0.0, 10000.0), lag);
  // A short window: 10 blocks, shorter.
  EXPECT_EQ(TransportMeter<3>::spacing(lag, 0.0, 20.0), 20.0 / (10.0 * 256.0 + 1.0));
  // A record continues to another end that spaces it alike: from one long window to a longer
  // one, not from a short window (nor from another window); to its own end, always.
  const auto records = [](double end, const TransportRecord& record) {
    return WindowRecords{0.0, end, std::nullopt, record};
  };
  const TransportRecord long_window{lag, lag, 257, {}, {}, 0.0, {}};
  EXPECT_TRUE(TransportMeter<3>::continued(records(10000.0, long_window), 0.0, 20000.0));
  EXPECT_FALSE(TransportMeter<3>::continued(records(10000.0, long_window), 5.0, 20000.0));
  const TransportRecord short_window{
      TransportMeter<3>::spacing(lag, 0.0, 20.0), lag, 257, {}, {}, 0.0, {}};
  EXPECT_FALSE(TransportMeter<3>::continued(records(20.0, short_window), 0.0, 10000.0));
  EXPECT_TRUE(TransportMeter<3>::continued(records(20.0, short_window), 0.0, 20.0));
  const TransportRecord older{lag, 0.0, 257, {}, {}, 0.0, {}};  // an older carom's: no lag kept
  EXPECT_FALSE(TransportMeter<3>::continued(records(10000.0, older), 0.0, 20000.0));
  EXPECT_TRUE(TransportMeter<3>::continued(records(10000.0, older), 0.0, 10000.0));
  EXPECT_EQ(enskog_collision_time(2, 0.3, 1.0, 1.0, 0.0), std::numeric_limits<double>::infinity());
}

TEST(Transport, ADiskMeasurementContinuesBitForBit) {
  expect_continued_measurement_equal<2>(200, 0.4, 30.0);
}

TEST(Transport, ASphereMeasurementContinuesBitForBit) {
  expect_continued_measurement_equal<3>(200, 0.3, 30.0);
}

}  // namespace
}  // namespace carom
