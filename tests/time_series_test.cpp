// The block average behind the time series' error bars, and the series itself on a run.
#include "carom/io/time_series.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <pcg_random.hpp>
#include <random>
#include <sstream>

#include "test_systems.hpp"

namespace carom {
namespace {

TEST(BlockAverage, IsExactForFewValues) {
  BlockAverage a;
  EXPECT_EQ(a.count(), 0u);
  EXPECT_TRUE(std::isnan(a.mean()));
  EXPECT_TRUE(std::isnan(a.error()));
  a.add(2.0);
  EXPECT_EQ(a.mean(), 2.0);
  EXPECT_TRUE(std::isnan(a.error()));
  a.add(4.0);
  a.add(6.0);
  EXPECT_EQ(a.count(), 3u);
  EXPECT_EQ(a.mean(), 4.0);
  EXPECT_DOUBLE_EQ(a.error(), std::sqrt(4.0 / 3.0));  // sample variance 4, three values
  a.clear();
  EXPECT_EQ(a.count(), 0u);
}

TEST(BlockAverage, IndependentValuesGiveTheNaiveErrorAndCorrelatedOnesALargerOne) {
  pcg32 rng(7);
  std::normal_distribution<double> normal(10.0, 2.0);
  BlockAverage independent, correlated;
  constexpr int kValues = 1 << 14;
  for (int i = 0; i < kValues; ++i) independent.add(normal(rng));
  // Each value held for 32 steps: the naive error is about sqrt(32) times too small.
  for (int i = 0; i < kValues / 32; ++i) {
    const double value = normal(rng);
    for (int k = 0; k < 32; ++k) correlated.add(value);
  }
  const double naive = 2.0 / std::sqrt(kValues);
  EXPECT_NEAR(independent.mean(), 10.0, 5 * naive);
  EXPECT_NEAR(independent.error(), naive, 0.25 * naive);
  const double blocked = 2.0 / std::sqrt(kValues / 32.0);
  EXPECT_NEAR(correlated.error(), blocked, 0.4 * blocked);
}

TEST(TimeSeries, RowsComeAtMultiplesOfTheIntervalWithTheWindowsZ) {
  pcg32 rng(3);
  System<2> gas = carom::testing::random_gas(rng, 60, 0.5, 0.5, 14, 14);
  gas.box.boundary = Boundary::periodic;
  Simulation<2> simulation(gas, {{Rule::elastic}});
  std::ostringstream out;
  auto series = std::make_shared<TimeSeriesWriter<2>>(out, 1.0);
  simulation.add_observer(series);
  simulation.run_until(40.0);
  const std::string text = out.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 41);  // t = 0, 1, ..., 40
  EXPECT_EQ(series->compressibility().count(), 40u);
  EXPECT_NEAR(series->compressibility().mean(), simulation.observables().compressibility_factor,
              1e-12);
}

}  // namespace
}  // namespace carom
