// Output formats of a run: the classic assignment's table and trace, the classic csv, json, and the
// event log. Disks print (x, y), spheres (x, y, z).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <ostream>
#include <span>
#include <string>

#include "carom/any_simulation.hpp"
#include "carom/event.hpp"
#include "carom/simulation.hpp"
#include "carom/system.hpp"
#include "carom/time_series.hpp"

namespace carom {

enum class Format { table, csv, json };

template <>
struct EnumNames<Format> {
  static constexpr std::array<std::pair<std::string_view, Format>, 3> table{
      {{"table", Format::table}, {"csv", Format::csv}, {"json", Format::json}}};
};

// `particle %d: (%.6f, %.6f) (%.6f, %.6f): %.6f : (%d, %d)`, without a newline.
template <std::size_t D>
std::string particle_line(std::size_t index, const Particle<D>& p, const ParticleRecord& record);

// The header `particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)`, then one
// particle_line a particle: the stored (lazy) states, each at its absolute stored time (the
// classic assignment's trace).
template <std::size_t D>
void write_table(std::ostream& out, const System<D>& system);

// One line a particle: `%.6f, %.6f, %d, %d` (x, y, wall collisions, particle collisions).
template <std::size_t D>
void write_csv(std::ostream& out, std::span<const Particle<D>> particles,
               std::span<const ParticleRecord> records);

// The table and the csv of every particle at the simulation's time, brought there one at a
// time: a result of 10^6 particles costs no copy of the state.
template <std::size_t D>
void write_table(std::ostream& out, const Simulation<D>& simulation);
template <std::size_t D>
void write_csv(std::ostream& out, const Simulation<D>& simulation);

// What a json result says beyond the simulation itself.
struct RunReport {
  std::string input;          // the file the run began from
  double wall_seconds = 0.0;  // wall-clock time of the simulation (of this process)
  std::uint64_t events = 0;   // the events processed in that time
  std::optional<std::uint64_t> seed;  // of the velocities the run drew, if it drew any
  std::optional<DriftVerdict> drift;  // of Z over the measurement window, if measured
  // The standard error of the window's pressure tensor (ZDrift::pressure_tensor_error).
  std::optional<SymmetricTensor> pressure_tensor_error;
  // The transport coefficients of a run that measured them (--transport), once two blocks of
  // its window are done.
  std::optional<TransportEstimate> transport;
};

// The settings, the whole run's counts (from t = 0, across resumes), the measurement window's
// counts (window_*) and observables, the rate of this process's events and, with `particles`,
// every particle at the simulation's time; numbers in full precision.
template <std::size_t D>
void write_json(std::ostream& out, const Simulation<D>& simulation, const RunReport& report,
                bool particles = true);

// The result of a run at its time, in either dimension: `format` table, csv, or json (with
// every particle, or without: the summary).
void write_result(std::ostream& out, const AnySimulation& simulation, Format format,
                  const RunReport& report, bool particles = true);

// A start file of either dimension (write_start).
void write_start(std::ostream& out, const AnySystem& system, Rule rule);

// The step-by-step trace users compare their own programs against: `Input File:`, `Target
// Time:` and the initial particles; after every event its time, what collided and every
// particle's stored state; at the end every particle brought to the end time.
template <std::size_t D>
class TraceWriter final : public Observer<D> {
 public:
  explicit TraceWriter(std::ostream& out) : Observer<D>(Trigger::each_event()), out_(out) {}
  void start(const std::string& input, double end_time, const Simulation<D>& simulation);
  void observe(const Simulation<D>& simulation) override;
  void finish(const Simulation<D>& simulation);

 private:
  std::ostream& out_;
};

// `time,kind,first,partner` a collision (kind wall or pair; partner a particle or a wall label),
// times in full precision. Throws std::runtime_error when the stream fails.
template <std::size_t D>
class EventLogWriter final : public Observer<D> {
 public:
  static constexpr const char* kHeader = "time,kind,first,partner\n";
  explicit EventLogWriter(std::ostream& out) : Observer<D>(Trigger::each_event()), out_(out) {}
  void observe(const Simulation<D>& simulation) override;
  // The length of the leading part of an event log holding the header and the events before
  // `t` (or at it, when `inclusive`): what a resumed run keeps before appending.
  static std::uint64_t events_before(std::istream& in, double t, bool inclusive);

 private:
  std::ostream& out_;
};

// A system in the classic input format, every number in its shortest form that reads back as the
// same double. Particles whose radius differs from `radius`, or whose mass is not 1, carry the
// optional columns `r [m]`. Spheres have three box sides and `x y z vx vy vz` lines.
template <std::size_t D>
void write_classic(std::ostream& out, const System<D>& system, double radius);
// A start as carom init and carom compress write it: the line recording its boundary and `rule`
// (start_record_line), then the classic lines with R the particles' common radius, or their mean
// when they differ (those particles then carry their own).
template <std::size_t D>
void write_start(std::ostream& out, const System<D>& system, Rule rule);

// One line naming an event: `Collision: particle 1 with particle 2` or
// `Collision: particle 3 with wall -2 (right)`.
std::string describe(const Event& event);

}  // namespace carom
