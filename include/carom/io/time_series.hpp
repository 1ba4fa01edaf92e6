// A run's time series, like LAMMPS' thermo output: one row per interval with the temperature,
// pressure, compressibility factor and collision rate over it, and running averages with a
// block-average error bar.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "carom/core/statistics.hpp"
#include "carom/engine/simulation.hpp"

namespace carom {

// Writes a CSV row every `every` (at t = 0, every, 2 every, ...; flushed, so an interrupted run
// keeps its rows):
//   time,events,pair_collisions,virial,wall_momentum,temperature,pressure,Z,collision_rate,
//   pressure_mean,pressure_error,Z_mean,Z_error
// events to wall_momentum are the run's running totals (Counts); temperature is kT at the row's
// time; pressure, Z = P V / (N kT) and the collision rate (per particle) are measured over the
// interval since the previous row; the means and errors (BlockAverage) are over the rows whose
// interval lies in the measurement window (none while equilibrating), the errors from blocks of at
// least a turn of event chains (chain_turn_duration: none until there are enough). Empty fields:
// not measured (the first row, or no row yet in the window, or no error yet; of event chains, a
// pressure along an axis no chain moved along in the interval). Throws std::runtime_error when
// the stream fails.
template <std::size_t D>
class TimeSeriesWriter final : public Observer<D> {
 public:
  static constexpr const char* kHeader =
      "time,events,pair_collisions,virial,wall_momentum,temperature,pressure,Z,collision_rate,"
      "pressure_mean,pressure_error,Z_mean,Z_error\n";
  TimeSeriesWriter(std::ostream& out, double every)
      : Observer<D>(Trigger::every_time(every)), out_(out), every_(every) {}
  // The header of a log: kHeader's columns, then the pressure tensor over the row's interval
  // (pxx, pyy, pxy; in 3D pxx, pyy, pzz, pxy, pxz, pyz), then running totals like virial. Of
  // dynamics: the tensor's Einstein-Helfand moment, the integral of V P_ab since the run began
  // keeping its fluxes (Gxx, ...). Of event chains, which have no such moment: the two sums their
  // pressure along each axis is the ratio of, beta P_kk = (N / V) (1 + dW_kk / dK_kk) over an
  // interval (Observables::directional_z): K_kk = sum of m v_k^2 dt over the moves (the chains'
  // speed times the distance moved along k: Kxx, ...) and W_ab = sum of r_a dp_b over the lifts
  // (Wxx, ..., Wxy, ...).
  static std::string header(SamplerKind sampler);
  void observe(const Simulation<D>& simulation) override;
  // The running means and errors of Z (what a progress line shows).
  const BlockAverage& compressibility() const { return z_; }
  // The length of the leading part of a log holding the header and the rows before `t` (or at
  // it, when `inclusive`): what a resumed run keeps before appending (0 for a file without a
  // whole line). Throws std::invalid_argument for a log with another header (another sampler's
  // or dimension's, or an event-chain log of carom before 1.9), whose rows it would lose. The
  // writer takes up the running totals and averages of the kept rows, so that the rows it appends
  // are those of a run never interrupted.
  std::uint64_t resume(std::istream& in, double t, bool inclusive, const Simulation<D>& simulation);

 private:
  // One row's own values, as written.
  struct Row {
    double time = 0.0;
    Counts totals;
    double pressure = 0.0, z = 0.0;
    bool measured = false;
  };
  // Counts a row written (or kept from before a resume) into the averages when its interval
  // lies in the measurement window.
  void take(const Row& row, std::optional<double> window_start);

  std::ostream& out_;
  double every_;
  bool started_ = false;
  Row last_;                            // the previous row
  std::optional<double> window_start_;  // the measurement window the averages are over
  BlockAverage pressure_, z_;
};

}  // namespace carom
