#include "carom/core/transport.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace carom {

double mean_square_increment(std::span<const double> x, std::size_t lag) {
  if (lag == 0 || lag >= x.size()) {
    throw std::invalid_argument("a lag must be at least 1 and shorter than the samples");
  }
  double sum = 0.0;
  const std::size_t origins = x.size() - lag;
  for (std::size_t j = 0; j < origins; ++j) {
    const double step = x[j + lag] - x[j];
    sum += step * step;
  }
  return sum / static_cast<double>(origins);
}

double einstein_helfand_slope(std::span<const double> x, std::size_t lag, double spacing) {
  const std::size_t half = lag / 2;
  if (half == 0) throw std::invalid_argument("the lag must be at least 2 samples");
  return (mean_square_increment(x, lag) - mean_square_increment(x, half)) /
         (static_cast<double>(lag - half) * spacing);
}

namespace {

// The series of one combination of a sample's components.
template <class F>
std::vector<double> series(std::span<const MomentSample> samples, F component) {
  std::vector<double> x;
  x.reserve(samples.size());
  for (const MomentSample& s : samples) x.push_back(component(s));
  return x;
}

}  // namespace

template <std::size_t D>
std::array<double, 2> block_viscosity_and_conductivity(std::span<const MomentSample> samples,
                                                       double spacing, double volume, double kT) {
  const std::size_t lag = (samples.size() - 1) / 4;
  // Components: xx 0, yy 1, zz 2, xy 3, xz 4, yz 5; heat x 6, y 7, z 8.
  std::vector<std::vector<double>> shear;
  shear.push_back(series(samples, [](const MomentSample& s) { return s[3]; }));
  shear.push_back(series(samples, [](const MomentSample& s) { return 0.5 * (s[0] - s[1]); }));
  if constexpr (D == 3) {
    shear.push_back(series(samples, [](const MomentSample& s) { return s[4]; }));
    shear.push_back(series(samples, [](const MomentSample& s) { return s[5]; }));
    shear.push_back(series(samples, [](const MomentSample& s) { return 0.5 * (s[1] - s[2]); }));
    shear.push_back(series(samples, [](const MomentSample& s) { return 0.5 * (s[0] - s[2]); }));
  }
  double eta = 0.0;
  for (const auto& x : shear) eta += einstein_helfand_slope(x, lag, spacing);
  eta /= 2.0 * volume * kT * static_cast<double>(shear.size());
  double lambda = 0.0;
  for (std::size_t k = 0; k < D; ++k) {
    const auto x = series(samples, [k](const MomentSample& s) { return s[6 + k]; });
    lambda += einstein_helfand_slope(x, lag, spacing);
  }
  lambda /= 2.0 * volume * kT * kT * static_cast<double>(D);
  return {eta, lambda};
}

template std::array<double, 2> block_viscosity_and_conductivity<2>(std::span<const MomentSample>,
                                                                   double, double, double);
template std::array<double, 2> block_viscosity_and_conductivity<3>(std::span<const MomentSample>,
                                                                   double, double, double);

double enskog_collision_time(std::size_t dimension, double phi, double sigma, double mass,
                             double kT) {
  const double pi = std::numbers::pi;
  const double speed = std::sqrt(kT / mass);
  double omega = 0.0;
  if (dimension == 2) {
    const double n = 4.0 * phi / (pi * sigma * sigma);
    const double chi = (1.0 - 7.0 * phi / 16.0) / ((1.0 - phi) * (1.0 - phi));
    omega = 2.0 * std::sqrt(pi) * n * sigma * chi * speed;
  } else {
    const double n = 6.0 * phi / (pi * sigma * sigma * sigma);
    const double chi = (1.0 - 0.5 * phi) / std::pow(1.0 - phi, 3);
    omega = 4.0 * std::sqrt(pi) * n * sigma * sigma * chi * speed;
  }
  return omega > 0.0 ? 1.0 / omega : std::numeric_limits<double>::infinity();
}

std::array<double, 3> enskog_spheres(double phi, double sigma, double mass, double kT) {
  const double pi = std::numbers::pi;
  const double chi = (1.0 - 0.5 * phi) / std::pow(1.0 - phi, 3);  // Carnahan-Starling g(sigma)
  const double n = 6.0 * phi / (pi * sigma * sigma * sigma);
  const double bn = 4.0 * phi;  // b n, b = 2 pi sigma^3 / 3
  const double thermal = std::sqrt(kT / (pi * mass));
  // The dilute-gas values, with their higher Sonine corrections (1.01896, 1.016, 1.02513).
  const double d0 = 1.01896 * 3.0 / (8.0 * n * sigma * sigma) * thermal;
  const double eta0 = 1.016 * 5.0 / (16.0 * sigma * sigma) * std::sqrt(mass * kT / pi);
  const double lambda0 = 1.02513 * 75.0 / (64.0 * sigma * sigma) * thermal;
  return {d0 / chi, eta0 * (1.0 / chi + 0.8 * bn + 0.7614 * bn * bn * chi),
          lambda0 * (1.0 / chi + 1.2 * bn + 0.7574 * bn * bn * chi)};
}

}  // namespace carom
