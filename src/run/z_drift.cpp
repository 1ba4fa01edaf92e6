#include "carom/run/z_drift.hpp"

#include <algorithm>
#include <cmath>

#include "carom/core/statistics.hpp"

namespace carom {

template <std::size_t D>
void ZDrift<D>::observe(const Simulation<D>& simulation) {
  const double now = simulation.time();
  const bool measuring = !simulation.pending_measurement();
  std::optional<double>& last_time = record_.last_time;
  if (last_time && measuring && *last_time >= simulation.measurement().start_time &&
      now > *last_time) {
    const Measurement interval{*last_time, 0.0,
                               difference(simulation.current_counts(), record_.last_totals),
                               std::nullopt};
    const Observables<D> o = simulation.observables_over(interval, now);
    if (std::isfinite(o.compressibility_factor)) record_.z.push_back(o.compressibility_factor);
    // An event-chain interval with no move along an axis has no pressure along it (NaN): it
    // holds less than a turn of chains, and the run gives no error from such intervals.
    if (o.pressure_tensor && std::ranges::all_of(*o.pressure_tensor,
                                                 [](double p) { return std::isfinite(p); })) {
      record_.pressure_tensors.push_back(*o.pressure_tensor);
    }
  }
  last_time = now;
  record_.last_totals = simulation.current_counts();
}

template <std::size_t D>
std::optional<DriftVerdict> ZDrift<D>::verdict() const {
  const std::vector<double>& z_ = record_.z;
  const std::size_t half = z_.size() / 2;
  if (half < kLeastPerHalf) return std::nullopt;
  // The halves' means and the squared standard errors of those means; the middle interval of an
  // odd count is in neither half.
  const std::span<const double> z(z_);
  const auto [first, first_variance] = mean_and_variance_of_mean(z.first(half));
  const auto [second, second_variance] = mean_and_variance_of_mean(z.last(half));
  const double error = std::sqrt(first_variance + second_variance);
  const double sigmas = error > 0.0 ? (second - first) / error : 0.0;
  return DriftVerdict{first, second, sigmas, z_.size()};
}

template <std::size_t D>
std::optional<SymmetricTensor> ZDrift<D>::pressure_tensor_error() const {
  const std::vector<SymmetricTensor>& tensors = record_.pressure_tensors;
  if (tensors.size() < 2 * kLeastPerHalf) return std::nullopt;
  SymmetricTensor error{};
  std::vector<double> component(tensors.size());
  for (std::size_t c = 0; c < 6; ++c) {
    for (std::size_t i = 0; i < tensors.size(); ++i) component[i] = tensors[i][c];
    error[c] = std::sqrt(mean_and_variance_of_mean(component).second);
  }
  return error;
}

template <std::size_t D>
std::optional<double> ZDrift<D>::compressibility_factor_error() const {
  if (record_.z.size() < 2 * kLeastPerHalf) return std::nullopt;
  return std::sqrt(mean_and_variance_of_mean(record_.z).second);
}

template class ZDrift<2>;
template class ZDrift<3>;

}  // namespace carom
