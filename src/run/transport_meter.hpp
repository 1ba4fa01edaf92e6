// The observer that measures transport coefficients over a run's measurement window
// (transport.hpp): it samples the flux moments and, at each block's start, middle and end, the
// particles' unwrapped positions, on a schedule fixed by the window's start and the run's end,
// so that a run continued from a checkpoint (which keeps its TransportRecord) samples as a run
// in one piece would.
#pragma once

#include <cmath>
#include <numbers>
#include <optional>
#include <tuple>
#include <vector>

#include "carom/core/observables.hpp"
#include "carom/core/transport.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/time_series.hpp"

namespace carom {

template <std::size_t D>
class TransportMeter final : public Observer<D> {
 public:
  // Sample intervals a block spans: four lags of the moments' estimator.
  static constexpr std::size_t kBlockIntervals = 256;
  // The lag: long against the fluxes' correlation times (a few collision times up to packing
  // 0.45), short against a run, so that a longer run has more blocks and smaller errors.
  static constexpr double kLagCollisionTimes = 50.0;
  // The fewest blocks a window is cut into: a shorter window gets shorter blocks.
  static constexpr std::size_t kLeastBlocks = 10;

  // The spacing of samples for a window long enough for kLeastBlocks blocks, of the system as
  // it is now: a lag of kLagCollisionTimes of Enskog's collision time.
  static double lag_spacing(const System<D>& system) {
    double diameters = 0.0, masses = 0.0;
    for (std::size_t i = 0; i < system.size(); ++i) {
      diameters += 2.0 * system.particles[i].radius;
      masses += system.records[i].mass;
    }
    const auto n = static_cast<double>(system.size());
    const double collision_time = enskog_collision_time(D, packing_fraction(system), diameters / n,
                                                        masses / n, kinetic_temperature(system));
    return kLagCollisionTimes * collision_time / static_cast<double>(kBlockIntervals / 4);
  }
  // The spacing of samples for a window from `start` to `end`: `lag_spacing`, unless
  // kLeastBlocks blocks of it do not fit.
  static double spacing(double lag_spacing, double start, double end) {
    return std::min(lag_spacing,
                    (end - start) / static_cast<double>(kLeastBlocks * kBlockIntervals + 1));
  }

  // A measurement of the window from `start` to `end` of the system as it is now; or `earlier`'s
  // continued (a checkpoint's, or a run's before), where it measured the same window to the same
  // end or to one that gives its spacing too (both windows kLeastBlocks lags' blocks long or
  // more, so that a run continued to a later end measures what one run to it would).
  TransportMeter(const System<D>& system, double start, double end,
                 const std::optional<TransportRecord>& earlier)
      : TransportMeter(earlier ? *earlier : fresh(system, start, end)) {}
  // The record of `records` a measurement from `start` to `end` continues, if any (see above).
  static std::optional<TransportRecord> continued(const WindowRecords& records, double start,
                                                  double end) {
    const std::optional<TransportRecord>& earlier = records.transport;
    if (!earlier || !records.same_window(start)) return std::nullopt;
    const bool same_spacing =
        earlier->lag_spacing > 0.0 && spacing(earlier->lag_spacing, start, end) == earlier->spacing;
    if (records.end_time == end || same_spacing) return earlier;
    return std::nullopt;
  }

  void observe(const Simulation<D>& simulation) override {
    if (simulation.pending_measurement() || !simulation.tracks_fluxes() ||
        simulation.time() < simulation.measurement().start_time) {
      return;
    }
    const Fluxes fluxes = *simulation.current_counts().fluxes;
    const SymmetricTensor g = fluxes.stress_moment();
    const std::array<double, 3> h = fluxes.heat_moment();
    record_.samples.push_back({g[0], g[1], g[2], g[3], g[4], g[5], h[0], h[1], h[2]});
    const std::size_t taken = record_.samples.size();
    if (taken == 1) {
      record_.origin = unwrapped_positions(simulation);
    } else if (taken == (record_.block_samples - 1) / 2 + 1) {
      record_.half_msd = msd(simulation);
    } else if (taken == record_.block_samples) {
      finish_block(simulation);
    }
  }

  const TransportRecord& record() const { return record_; }

  // The coefficients over the blocks done (none before two are).
  std::optional<TransportEstimate> estimate(const System<D>& system) const {
    const std::vector<TransportBlock>& blocks = record_.blocks;
    if (blocks.size() < 2) return std::nullopt;
    const auto mean_and_error = [&](double TransportBlock::*field) {
      std::vector<double> values;
      for (const TransportBlock& b : blocks) values.push_back(b.*field);
      const auto [mean, variance] = mean_and_variance_of_mean(values);
      return std::pair{mean, std::sqrt(variance)};
    };
    TransportEstimate e;
    e.blocks = blocks.size();
    std::tie(e.self_diffusion, e.self_diffusion_error) =
        mean_and_error(&TransportBlock::self_diffusion);
    std::tie(e.shear_viscosity, e.shear_viscosity_error) =
        mean_and_error(&TransportBlock::shear_viscosity);
    std::tie(e.thermal_conductivity, e.thermal_conductivity_error) =
        mean_and_error(&TransportBlock::thermal_conductivity);
    if constexpr (D == 3) {
      const double kT = kinetic_temperature(system);
      const Vec<D>& side = system.box.size;
      if (side[0] == side[1] && side[1] == side[2] && e.shear_viscosity > 0.0) {
        e.self_diffusion_corrected =
            e.self_diffusion +
            kYehHummerXi * kT / (6.0 * std::numbers::pi * e.shear_viscosity * side[0]);
      }
      // Enskog's values need spheres of one size and one mass.
      bool alike = true;
      for (std::size_t i = 1; i < system.size(); ++i) {
        alike = alike && system.particles[i].radius == system.particles[0].radius &&
                system.records[i].mass == system.records[0].mass;
      }
      if (alike) {
        const auto [d, eta, lambda] = enskog_spheres(
            packing_fraction(system), 2.0 * system.particles[0].radius, system.records[0].mass, kT);
        e.enskog_self_diffusion = d;
        e.enskog_shear_viscosity = eta;
        e.enskog_thermal_conductivity = lambda;
      }
    }
    return e;
  }

 private:
  explicit TransportMeter(TransportRecord record)
      : Observer<D>(Trigger::every_time(record.spacing)), record_(std::move(record)) {}
  static TransportRecord fresh(const System<D>& system, double start, double end) {
    const double lag = lag_spacing(system);
    return TransportRecord{spacing(lag, start, end), lag, kBlockIntervals + 1, {}, {}, 0.0, {}};
  }

  std::vector<double> unwrapped_positions(const Simulation<D>& simulation) const {
    const System<D>& system = simulation.state();
    std::vector<double> x(system.size() * D);
    for (std::size_t i = 0; i < system.size(); ++i) {
      std::array<std::int32_t, 3> image = system.records[i].image;
      const Particle<D> p =
          synchronised(system.particles[i], system.box, simulation.stored_time(), image);
      for (std::size_t k = 0; k < D; ++k) {
        x[i * D + k] = p.position[k] + static_cast<double>(image[k]) * system.box.size[k];
      }
    }
    return x;
  }

  double msd(const Simulation<D>& simulation) const {
    const std::vector<double> now = unwrapped_positions(simulation);
    double sum = 0.0;
    for (std::size_t c = 0; c < now.size(); ++c) {
      const double step = now[c] - record_.origin[c];
      sum += step * step;
    }
    return sum / static_cast<double>(simulation.state().size());
  }

  void finish_block(const Simulation<D>& simulation) {
    const System<D>& system = simulation.state();
    const double half_time = static_cast<double>((record_.block_samples - 1) / 2) * record_.spacing;
    TransportBlock block;
    block.self_diffusion = (msd(simulation) - record_.half_msd) / (2.0 * D * half_time);
    const auto [eta, lambda] = block_viscosity_and_conductivity<D>(
        record_.samples, record_.spacing, box_volume(system.box), kinetic_temperature(system));
    block.shear_viscosity = eta;
    block.thermal_conductivity = lambda;
    record_.blocks.push_back(block);
    // The block's end is the next one's start.
    record_.samples = {record_.samples.back()};
    record_.origin = unwrapped_positions(simulation);
    record_.half_msd = 0.0;
  }

  TransportRecord record_;
};

}  // namespace carom
