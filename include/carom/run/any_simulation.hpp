// A Simulation of either dimension, chosen once where a run is made (from a file, a checkpoint,
// arrays or carom init's options), with everything a front end asks of a run in no particular
// dimension: so that no front end (the command line, the Python module, the sweep runner)
// switches on D. The library itself reaches the Simulation<D> inside through visit().
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <variant>
#include <vector>

#include "carom/engine/simulation.hpp"

namespace carom {

template <std::size_t D>
struct Checkpoint;

// A System of either dimension: what a compression makes, or arrays become.
using AnySystem = std::variant<System<2>, System<3>>;

class AnySimulation {
 public:
  template <std::size_t D>
  explicit AnySimulation(Simulation<D> simulation) : simulation_(std::move(simulation)) {}
  // A run from `system` (see Simulation's constructor).
  AnySimulation(AnySystem system, const Settings& settings);
  // Continues a checkpointed run exactly.
  template <std::size_t D>
  explicit AnySimulation(const Checkpoint<D>& checkpoint)
      : simulation_(std::in_place_type<Simulation<D>>, checkpoint) {}

  template <class F>
  decltype(auto) visit(F&& f) {
    return std::visit(std::forward<F>(f), simulation_);
  }
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(std::forward<F>(f), simulation_);
  }

  int dimension() const { return simulation_.index() == 0 ? 2 : 3; }
  std::size_t size() const;
  double time() const;
  bool settled() const;
  const Counts& counts() const;
  const Settings& settings() const;
  Boundary boundary() const;
  std::vector<double> box() const;  // the D sides
  // In a sheared box, the x shift of the images one box up at time() (shown_shift), which the
  // image flags unwrap with along x; 0 otherwise.
  double shear_shift() const;

  void check_target(double t) const;
  RunStatus run_until(double t, std::uint64_t max_events = Simulation<2>::kNoLimit);
  void set_stop_flag(const std::atomic<int>* flag);

  void reset_measurement();
  void measure_from(double t);
  std::optional<double> pending_measurement() const;
  Measurement measurement() const;
  // Z measured over the window so far, when there is a window with a temperature.
  std::optional<double> compressibility_factor() const;

  // Every particle at time(), row-major (N, D) into `out` (N x D values): positions wrapped into
  // a periodic box, velocities (zero under event chains: shows_at_rest), and the image flags
  // that unwrap the positions.
  void positions(double* out) const;
  void velocities(double* out) const;
  void images(std::int32_t* out) const;
  // Per particle, N values.
  void radii(double* out) const;
  void masses(double* out) const;
  // Each particle's type (an index into type_names()), and the types' names ("A" alone unless
  // the start names more).
  void types(std::uint32_t* out) const;
  std::vector<std::string> type_names() const;
  void wall_collisions(std::uint64_t* out) const;
  void pair_collisions(std::uint64_t* out) const;

  // Every particle at time(), as a start at t = 0 (stored times 0, records kept): what a
  // compression of this run begins from.
  AnySystem snapshot_system() const;

 private:
  std::variant<Simulation<2>, Simulation<3>> simulation_;
};

// A start file of either dimension (write_start in classic_output.hpp).
void write_start(std::ostream& out, const AnySystem& system, Rule rule);

}  // namespace carom
