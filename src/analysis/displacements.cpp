#include "carom/analysis/displacements.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace carom {

namespace {

// Each frame's centre of mass (every particle weighed alike).
std::array<double, 3> centre_of_mass(const UnwrappedTrajectory& trajectory, std::size_t f) {
  const std::size_t n = trajectory.particles, d = trajectory.dimension;
  const double* const at = trajectory.frame(f);
  std::array<double, 3> centre{};
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < d; ++k) centre[k] += at[i * d + k];
  }
  for (std::size_t k = 0; k < d; ++k) centre[k] /= static_cast<double>(n);
  return centre;
}

}  // namespace

double centre_of_mass_shift_squared(const UnwrappedTrajectory& trajectory) {
  if (trajectory.particles == 0 || trajectory.frames == 0) return 0.0;
  const std::array<double, 3> first = centre_of_mass(trajectory, 0);
  const std::array<double, 3> last = centre_of_mass(trajectory, trajectory.frames - 1);
  double squared = 0.0;
  for (std::size_t k = 0; k < trajectory.dimension; ++k) {
    squared += (last[k] - first[k]) * (last[k] - first[k]);
  }
  return squared;
}

UnwrappedTrajectory unwrap(const std::vector<Frame>& frames, std::string_view what) {
  if (frames.empty()) throw std::invalid_argument(fmt::format("{} needs at least one frame", what));
  const Frame& first = frames.front();
  UnwrappedTrajectory out;
  out.frames = frames.size();
  out.particles = first.position.size();
  out.dimension = static_cast<std::size_t>(first.dimension);
  const std::size_t count = out.frames, n = out.particles, d = out.dimension;
  if (first.periodic) {
    for (std::size_t f = 0; f < count; ++f) {
      if (frames[f].image.size() != n) {
        throw std::invalid_argument(fmt::format(
            "{} of a periodic trajectory needs image flags, and frame {} (t = {:g}) has none "
            "(carom 1.2 and later write them in .gsd and .xyz dumps; HOOMD in every frame of a "
            "GSD file written with dynamic=['property', 'momentum'])",
            what, f, frames[f].time));
      }
    }
  }
  out.spacing =
      count > 1 ? (frames.back().time - first.time) / static_cast<double>(count - 1) : 0.0;
  if (count > 1 && !(out.spacing > 0.0)) {
    throw std::invalid_argument(
        fmt::format("{} needs frames evenly spaced in time, and these go from t = {:g} to t = {:g}",
                    what, first.time, frames.back().time));
  }
  for (std::size_t f = 0; f < count; ++f) {
    const double expected = first.time + static_cast<double>(f) * out.spacing;
    if (std::abs(frames[f].time - expected) > 1e-6 * out.spacing + 1e-12 * std::abs(expected)) {
      throw std::invalid_argument(fmt::format(
          "{} needs frames evenly spaced in time, and frame {} is at t = {:g}, not {:g}", what, f,
          frames[f].time, expected));
    }
  }
  out.positions.resize(count * n * d);
  for (std::size_t f = 0; f < count; ++f) {
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < d; ++k) {
        double x = frames[f].position[i][k];
        if (first.periodic) {
          const std::array<std::int32_t, 3>& image = frames[f].image[i];
          x += frames[f].box[k] * static_cast<double>(image[k]);
          // A sheared box's images one box up lie the shift further along x.
          if (k == 0) x += frames[f].shear_shift * static_cast<double>(image[1]);
        }
        out.positions[(f * n + i) * d + k] = x;
      }
    }
  }
  return out;
}

void remove_centre_of_mass_motion(UnwrappedTrajectory& trajectory) {
  const std::size_t n = trajectory.particles, d = trajectory.dimension;
  if (n == 0 || trajectory.frames == 0) return;
  const std::array<double, 3> origin = centre_of_mass(trajectory, 0);
  for (std::size_t f = 1; f < trajectory.frames; ++f) {
    const std::array<double, 3> centre = centre_of_mass(trajectory, f);
    double* const at = &trajectory.positions[f * n * d];
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < d; ++k) at[i * d + k] -= centre[k] - origin[k];
    }
  }
}

std::vector<std::size_t> displacement_lags(std::size_t frames) {
  constexpr std::size_t kEveryLag = 200;
  std::vector<std::size_t> lags;
  for (std::size_t lag = 0; lag < frames && lag <= kEveryLag; ++lag) lags.push_back(lag);
  if (frames > kEveryLag + 1) {
    const double from = std::log(static_cast<double>(kEveryLag));
    const double to = std::log(static_cast<double>(frames - 1));
    for (int m = 1; m <= 100; ++m) {
      const double lag = std::round(std::exp(from + (to - from) * m / 100.0));
      if (lag > static_cast<double>(lags.back())) lags.push_back(static_cast<std::size_t>(lag));
    }
  }
  return lags;
}

DisplacementMoments displacement_moments(const UnwrappedTrajectory& trajectory) {
  const std::size_t count = trajectory.frames, n = trajectory.particles, d = trajectory.dimension;
  DisplacementMoments moments;
  moments.lags = displacement_lags(count);
  for (const std::size_t lag : moments.lags) {
    double r2 = 0.0, r4 = 0.0;
    for (std::size_t f = 0; f + lag < count; ++f) {
      const double* from = trajectory.frame(f);
      const double* to = trajectory.frame(f + lag);
      for (std::size_t i = 0; i < n; ++i) {
        double squared = 0.0;
        for (std::size_t k = i * d; k < (i + 1) * d; ++k) {
          squared += (to[k] - from[k]) * (to[k] - from[k]);
        }
        r2 += squared;
        r4 += squared * squared;
      }
    }
    const double samples = static_cast<double>(count - lag) * static_cast<double>(n);
    moments.t.push_back(static_cast<double>(lag) * trajectory.spacing);
    moments.r2.push_back(r2 / samples);
    moments.r4.push_back(r4 / samples);
  }
  return moments;
}

}  // namespace carom
