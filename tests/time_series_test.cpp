// The block average behind the time series' error bars, and the series itself on a run.
#include "carom/io/time_series.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <pcg_random.hpp>
#include <random>
#include <sstream>
#include <vector>

#include "carom/core/statistics.hpp"
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

// Consecutive values' correlation: about 0 (within 1/sqrt(n)) for independent values, the
// process's own for a correlated one, -1 for alternating ones; none without three values that
// differ.
TEST(LagOneAutocorrelation, TellsIndependentValuesFromCorrelatedOnes) {
  pcg32 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  constexpr int kValues = 1 << 14;
  std::vector<double> independent(kValues), remembering(kValues);
  double x = 0.0;
  for (int i = 0; i < kValues; ++i) {
    independent[i] = 5.0 + normal(rng);
    x = 0.8 * x + normal(rng);  // AR(1): lag-one autocorrelation 0.8
    remembering[i] = 5.0 + x;
  }
  const double spread = 1.0 / std::sqrt(kValues);
  EXPECT_NEAR(lag_one_autocorrelation(independent), 0.0, 4 * spread);
  EXPECT_NEAR(lag_one_autocorrelation(remembering), 0.8, 0.03);
  const std::vector<double> alternating = {1, 3, 1, 3, 1, 3, 1, 3};
  EXPECT_NEAR(lag_one_autocorrelation(alternating), -7.0 / 8.0, 1e-15);
  EXPECT_TRUE(std::isnan(lag_one_autocorrelation(std::vector<double>{1.0, 2.0})));
  EXPECT_TRUE(std::isnan(lag_one_autocorrelation(std::vector<double>{2.0, 2.0, 2.0})));
  // Values apart by round-off only (a gas that never collides: Z = 1 to the last bits).
  const double one = 1.0, below = std::nextafter(1.0, 0.0);
  EXPECT_TRUE(std::isnan(lag_one_autocorrelation(std::vector<double>{one, one, below, below})));
}

// Pairs across a gap are left out: two alternating runs that meet at equal values have the
// alternation's autocorrelation once the meeting is flagged, and more without the flag.
TEST(LagOneAutocorrelation, LeavesPairsAcrossAGapOut) {
  const std::vector<double> joined = {1, 3, 1, 3, 3, 1, 3, 1};
  const std::vector<std::uint8_t> follows = {0, 1, 1, 1, 0, 1, 1, 1};
  EXPECT_NEAR(lag_one_autocorrelation(joined, follows), -7.0 / 8.0, 1e-15);
  EXPECT_NEAR(lag_one_autocorrelation(joined), -5.0 / 8.0, 1e-15);
  const std::vector<std::uint8_t> every(8, 1);
  EXPECT_EQ(lag_one_autocorrelation(joined, every), lag_one_autocorrelation(joined));
  EXPECT_TRUE(std::isnan(lag_one_autocorrelation(joined, std::vector<std::uint8_t>(8, 0))));
  EXPECT_THROW(lag_one_autocorrelation(joined, std::vector<std::uint8_t>(7, 1)),
               std::invalid_argument);
}

// An error from blocks of at least K values: the levels of shorter blocks left out, none (NaN)
// until a level of long enough blocks holds kLeastBlocks of them.
TEST(BlockAverage, AnErrorFromLongBlocksOnlyLeavesTheShortOnesOut) {
  BlockAverage a;
  for (int i = 0; i < 64; ++i) a.add(i % 2 == 0 ? 1.0 : 3.0);  // alternating: pairs average to 2
  EXPECT_GT(a.error(), 0.0);
  EXPECT_EQ(a.error(2), 0.0);           // blocks of 2 and 4 (32 and 16 of them), every one 2
  EXPECT_TRUE(std::isnan(a.error(8)));  // 8 blocks of 8: too few
  EXPECT_TRUE(std::isnan(BlockAverage().error(2)));
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

// Event chains longer than the rows: a row's interval moves the particles along one axis only,
// and the log gives Z's mean but no error from blocks shorter than a turn of chains (x then y),
// as the summary gives none; with rows that hold turns, it gives one.
TEST(TimeSeries, EventChainsLongerThanItsBlocksGiveNoError) {
  pcg32 rng(3);
  System<2> gas = carom::testing::random_gas(rng, 64, 0.5, 0.5, 16, 16);
  gas.box.boundary = Boundary::periodic;
  for (ParticleRecord& record : gas.records) record.mass = 1.0;  // chains move positions only
  ASSERT_EQ(gas.size(), 64u);
  const auto last_row = [&](double chain_length, double every) {
    Settings settings;
    settings.sampler = {SamplerKind::ecmc, chain_length, 1};
    Simulation<2> simulation(gas, settings);
    std::ostringstream out;
    simulation.add_observer(std::make_shared<TimeSeriesWriter<2>>(out, every));
    simulation.run_until(64.0 * every);
    const std::string text = out.str();
    const std::size_t end = text.rfind('\n', text.size() - 2);
    std::vector<std::string> fields;
    std::stringstream row(text.substr(end + 1));
    for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
    return fields;
  };
  // Columns 11 and 12 (from 0): Z_mean and Z_error. A turn of chains of 64 diameters over 64
  // disks lasts 2 time units: rows 0.01 apart hold a 200th of one.
  const std::vector<std::string> short_rows = last_row(64.0, 0.01);
  EXPECT_FALSE(short_rows[11].empty());
  EXPECT_TRUE(short_rows[12].empty()) << short_rows[12];
  EXPECT_TRUE(short_rows[10].empty()) << short_rows[10];  // pressure_error
  const std::vector<std::string> turns = last_row(1.0, 1.0);
  EXPECT_FALSE(turns[12].empty());
}

// Each row's pressure along an axis is N / V (1 + the lifts along it over the distance moved
// along it), as the summary's: a row inside one chain moved along one axis only, gives that
// axis's pressure (the row's own) and none along the other, and one row over the whole run gives
// the summary's tensor. (Scaled by the time moved along each axis instead, a row of x chains
// read 2 N / V Z along x and 0 along y.)
TEST(TimeSeries, EventChainsRowsGiveThePressureAlongEachAxisMovedAlong) {
  pcg32 rng(5);
  System<2> gas = carom::testing::random_gas(rng, 64, 0.5, 0.5, 16, 16);
  gas.box.boundary = Boundary::periodic;
  for (ParticleRecord& record : gas.records) record.mass = 1.0;
  const double density = 64.0 / box_volume(gas.box);
  const auto rows_of = [&](double every, double end) {
    Settings settings;
    settings.sampler = {SamplerKind::ecmc, 64.0, 1};  // a chain of 64 diameters lasts 1 unit
    Simulation<2> simulation(gas, settings);
    std::ostringstream out;
    simulation.add_observer(std::make_shared<TimeSeriesWriter<2>>(out, every));
    simulation.run_until(end);
    std::vector<std::vector<std::string>> rows;
    std::stringstream text(out.str());
    for (std::string line; std::getline(text, line);) {
      std::vector<std::string> fields;
      std::stringstream row(line);
      for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
      if (line.back() == ',') fields.emplace_back();
      rows.push_back(fields);
    }
    return std::pair{rows, simulation.observables()};
  };
  // Columns (from 0): 6 pressure, 13 pxx, 14 pyy, 15 pxy.
  const auto rows = rows_of(0.25, 4.0).first;
  ASSERT_EQ(rows.size(), 17u);  // t = 0, 0.25, ..., 4
  EXPECT_NE(TimeSeriesWriter<2>::header(SamplerKind::ecmc).find(",pxy,Kxx,Kyy,Wxx,Wyy,Wxy\n"),
            std::string::npos);
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const bool along_x = !rows[r][13].empty();
    ASSERT_NE(along_x, !rows[r][14].empty()) << "row " << r;
    const double p = std::stod(rows[r][along_x ? 13 : 14]);
    EXPECT_NEAR(p, std::stod(rows[r][6]), 1e-12 * p) << "row " << r;
    EXPECT_GT(p, density);
  }
  const auto [whole, summary] = rows_of(4.0, 4.0);
  ASSERT_TRUE(summary.pressure_tensor);
  const std::array<std::size_t, 3> components = tensor_components<2>();  // xx, yy, xy
  for (std::size_t m = 0; m < 3; ++m) {
    EXPECT_DOUBLE_EQ(std::stod(whole[1][13 + m]), (*summary.pressure_tensor)[components[m]]) << m;
  }
}

}  // namespace
}  // namespace carom
