#include "carom/run/z_drift.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>

#include "carom/core/statistics.hpp"

namespace carom {

std::optional<std::string> DriftVerdict::drift_warning() const {
  if (!drifted()) return std::nullopt;
  return fmt::format(
      "Z drifted from {:.6g} (first half of the measurement window) to {:.6g} (second half), "
      "{:.1f} standard errors: {}",
      first, second, sigmas, kDriftAdvice);
}

std::optional<std::string> DriftVerdict::correlation_warning() const {
  if (drifted() || !blocks_correlated()) return std::nullopt;
  return fmt::format(
      "Z's blocks of the measurement window are correlated (lag-one autocorrelation {:.2f} over "
      "{} blocks, where independent ones give 0 +- {:.2f}): {}",
      block_correlation, intervals, 1.0 / std::sqrt(static_cast<double>(intervals)),
      kCorrelationAdvice);
}

namespace {

// The blocks' first length: 2^-20, or 2^-40 of the window's start where that is longer (a time
// trigger counts multiples of it from t = 0 in doubles).
double first_block_length(double window_start) {
  const double shortest = std::ldexp(1.0, -20);
  if (!(std::abs(window_start) * std::ldexp(1.0, -40) > shortest)) return shortest;
  return std::ldexp(1.0, std::ilogb(window_start) + 1 - 40);
}

DriftRecord record_for(double window_start, const std::optional<DriftRecord>& earlier) {
  if (earlier && earlier->block_length > 0.0) return *earlier;
  return DriftRecord{first_block_length(window_start), {}, {}, {}};
}

}  // namespace

template <std::size_t D>
ZDrift<D>::ZDrift(double window_start, const std::optional<DriftRecord>& earlier)
    : ZDrift(record_for(window_start, earlier)) {}

template <std::size_t D>
ZDrift<D>::ZDrift(DriftRecord record)
    : Observer<D>(Trigger::every_time(record.block_length)), record_(std::move(record)) {}

template <std::size_t D>
void ZDrift<D>::observe(const Simulation<D>& simulation) {
  const double now = simulation.time();
  if (const std::optional<double> opens = simulation.pending_measurement()) {
    // Nothing is measured before the window opens: look again by then, at a cadence that at
    // least halves the wait each time (blocks of 2^-20 through an equilibration of 2000 would
    // stop the run 2 x 10^9 times), down to the blocks' own where the window opens.
    double period = record_.block_length;
    while (2.0 * period <= *opens - now) period *= 2.0;
    this->set_period(period);
    return;
  }
  this->set_period(record_.block_length);
  if (now < simulation.measurement().start_time) return;
  // Only boundaries: a first look at a resumed run's own time is none, and an instant is taken
  // once (a run resumed from a failed one looks at it again).
  if (std::fmod(now, record_.block_length) != 0.0) return;
  if (!record_.boundaries.empty() && !(now > record_.boundaries.back())) return;
  record_.boundaries.push_back(now);
  record_.totals.push_back(simulation.current_counts());
  record_.temperatures.push_back(simulation.kinetic_temperature());
  if (record_.boundaries.size() > kMostBlocks) coarsen();
}

template <std::size_t D>
void ZDrift<D>::coarsen() {
  const double length = 2.0 * record_.block_length;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < record_.boundaries.size(); ++i) {
    if (std::fmod(record_.boundaries[i], length) != 0.0) continue;
    record_.boundaries[kept] = record_.boundaries[i];
    record_.totals[kept] = std::move(record_.totals[i]);
    record_.temperatures[kept] = record_.temperatures[i];
    ++kept;
  }
  record_.boundaries.resize(kept);
  record_.totals.resize(kept);
  record_.temperatures.resize(kept);
  record_.block_length = length;
  this->set_period(length);
}

template <std::size_t D>
BlockErrors block_errors(const DriftRecord& record, const Simulation<D>& simulation) {
  constexpr std::size_t kLeastPerHalf = ZDrift<D>::kLeastPerHalf;
  BlockErrors errors;
  errors.block_length = record.block_length;
  std::vector<double> z;
  // Whether each block in z begins where the one before it ended (no gap, no block left out).
  std::vector<std::uint8_t> follows;
  double last_end = std::numeric_limits<double>::quiet_NaN();
  std::vector<SymmetricTensor> tensors;
  const auto n = static_cast<double>(simulation.state().size());
  const double volume = box_volume(simulation.state().box);
  for (std::size_t i = 1; i < record.boundaries.size(); ++i) {
    const double from = record.boundaries[i - 1], to = record.boundaries[i];
    if (to - from != record.block_length) continue;  // a gap, not a block
    const Measurement block{from, 0.0, difference(record.totals[i], record.totals[i - 1]),
                            std::nullopt};
    const Observables<D> o = simulation.observables_over(block, to);
    // Z as the window's is measured, but with the temperature at the block's end, not the run's
    // (a cooling gas's blocks would otherwise all be measured at its last temperature).
    const double kinetic = n * record.temperatures[i];
    const double block_z = compressibility_factor_of(
        pressure_over<D>(block.counts.virial, to - from, kinetic, volume), kinetic, volume);
    if (std::isfinite(block_z)) {
      z.push_back(block_z);
      follows.push_back(from == last_end ? 1 : 0);
      last_end = to;
    }
    // An event-chain block with no move along an axis has no pressure along it (NaN): it holds
    // less than a turn of chains, and the run gives no error from such blocks.
    if (o.pressure_tensor &&
        std::ranges::all_of(*o.pressure_tensor, [](double p) { return std::isfinite(p); })) {
      tensors.push_back(*o.pressure_tensor);
    }
  }
  const std::size_t half = z.size() / 2;
  if (half >= kLeastPerHalf) {
    // The halves' means and the squared standard errors of those means; the middle block of an
    // odd count is in neither half.
    const std::span<const double> all(z);
    const auto [first, first_variance] = mean_and_variance_of_mean(all.first(half));
    const auto [second, second_variance] = mean_and_variance_of_mean(all.last(half));
    const double error = std::sqrt(first_variance + second_variance);
    const double sigmas = error > 0.0 ? (second - first) / error : 0.0;
    errors.verdict =
        DriftVerdict{first, second, sigmas, z.size(), lag_one_autocorrelation(z, follows)};
    errors.compressibility_factor = std::sqrt(mean_and_variance_of_mean(z).second);
  }
  if (tensors.size() >= 2 * kLeastPerHalf) {
    SymmetricTensor error{};
    std::vector<double> component(tensors.size());
    for (std::size_t c = 0; c < 6; ++c) {
      for (std::size_t i = 0; i < tensors.size(); ++i) component[i] = tensors[i][c];
      error[c] = std::sqrt(mean_and_variance_of_mean(component).second);
    }
    errors.pressure_tensor = error;
  }
  return errors;
}

template BlockErrors block_errors(const DriftRecord&, const Simulation<2>&);
template BlockErrors block_errors(const DriftRecord&, const Simulation<3>&);
template class ZDrift<2>;
template class ZDrift<3>;

}  // namespace carom
