// The checks of a run before it runs: what no run can do (check_run_spec), what no run in its box
// can (check_run_in_box), and what this run cannot, against its simulation, its start and the
// disks its files go to (check_run, for Runner::check).
#include "run_checks.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "carom/io/atomic_file.hpp"
#include "carom/io/final_state.hpp"
#include "carom/io/trajectory.hpp"

namespace carom {

namespace {

// Beyond this many frames or rows a cadence is a mistake (or fills a disk), not a measurement.
constexpr double kMostRows = 1e7;

// The files a spec writes, named by their options.
std::vector<NamedFile> output_files(const RunSpec& spec) {
  return {{option("summary"), spec.summary},
          {option("final"), spec.final_state},
          {option("checkpoint"), spec.checkpoint},
          {option("dump"), spec.dump},
          {option("events"), spec.events},
          {option("log"), spec.log}};
}

// Refuses an output of about `bytes`, written to `path` by the option `key`, that its disk cannot
// hold (free space unknown: the write itself will tell); the option `cadence_key` spaces its
// rows or frames.
void check_fits(const std::string& key, const std::string& path, double bytes,
                const std::string& detail, const std::string& cadence_key) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::absolute(path).parent_path();
  std::error_code error;
  const fs::space_info space = fs::space(folder, error);
  if (error || bytes <= static_cast<double>(space.available)) return;
  throw RequestError({option(key),
                      fmt::format(" {} would take about {:.3g} GB ({}) but {} has {:.3g} GB free: "
                                  "raise ",
                                  path, bytes / 1e9, detail, folder.string(),
                                  static_cast<double>(space.available) / 1e9),
                      option(cadence_key), " or lower ", option("end_time")});
}

// The frames still to come times the size of one (measured on up to 1000 particles and scaled
// to all of them), and the rows of the time series (a generous 400 bytes each), against the free
// space of their disks.
template <std::size_t D>
void check_outputs_fit(const Simulation<D>& simulation, const RunSpec& spec) {
  const double now = simulation.time();
  if (!spec.dump.empty()) {
    const System<D>& state = simulation.state();
    System<D> sample;
    sample.box = state.box;
    sample.epoch = state.epoch;
    sample.type_names = state.type_names;
    const std::size_t taken = std::min<std::size_t>(state.size(), 1000);
    sample.particles.assign(state.particles.begin(), state.particles.begin() + taken);
    sample.records.assign(state.records.begin(), state.records.begin() + taken);
    std::ostringstream one;
    try {
      const auto format = trajectory_format_for<D>(spec.dump);
      // Every particle's numbers as the format stores them (a .gsd file's single precision):
      // refused now rather than as the frames go (where the run's speeds, which a thermostat or
      // a shear may raise, are checked frame by frame).
      format->check_frame(state, now);
      format->frame(one, 0, now, sample);
    } catch (const std::invalid_argument& e) {
      throw RequestError(e.what());
    } catch (const std::range_error& e) {
      throw RequestError({option("dump"), fmt::format(" {}: {}", spec.dump, e.what())});
    }
    const double frame_bytes = static_cast<double>(one.tellp()) *
                               static_cast<double>(state.size()) / static_cast<double>(taken);
    const double frames =
        std::floor(spec.end_time / spec.dump_every) - std::floor(now / spec.dump_every) + 1.0;
    check_fits("dump", spec.dump, frames * frame_bytes,
               fmt::format("{:.0f} frames of {:.3g} MB", frames, frame_bytes / 1e6), "dump_every");
  }
  if (!spec.log.empty()) {
    constexpr double kRowBytes = 400.0;
    const double rows = (spec.end_time - now) / spec.log_every + 1.0;
    check_fits("log", spec.log, rows * kRowBytes, fmt::format("{:.0f} rows", rows), "log_every");
  }
}

// Creating (and dropping) a temporary file beside `path` checks it before the run.
void probe(const std::string& path) {
  try {
    const AtomicFile file(path);
  } catch (const std::runtime_error& e) {
    throw RequestError(e.what());
  }
}

}  // namespace

Trigger checkpoint_cadence(const std::string& every) {
  const bool seconds = !every.empty() && every.back() == 's';
  double value = 0.0;
  try {
    value = parse_finite_double(seconds ? every.substr(0, every.size() - 1) : every);
  } catch (const std::invalid_argument& e) {
    throw RequestError({option("checkpoint_every"), fmt::format(": {}", e.what())});
  }
  if (!(value > 0.0)) throw RequestError({option("checkpoint_every"), " must be greater than 0"});
  if (seconds) return Trigger::every_seconds(value);
  if (value < 1.0 || value != std::floor(value)) {
    throw RequestError(
        {option("checkpoint_every"), " counts events: a whole number, or seconds as 600s"});
  }
  // Beyond this a double no longer holds every whole number, and no run has so many events.
  constexpr double kMostEvents = 9007199254740992.0;  // 2^53
  if (value > kMostEvents) {
    throw RequestError({option("checkpoint_every"),
                        fmt::format(" {} is more events than a run can have (at most 2^53 = {})",
                                    every, kMostEvents)});
  }
  return Trigger::every_events(static_cast<std::uint64_t>(value));
}

void check_run_spec(const RunSpec& spec) {
  const auto positive = [](double dt) { return dt > 0.0 && std::isfinite(dt); };
  if (!spec.dump.empty() && !positive(spec.dump_every)) {
    throw RequestError(
        {option("dump"), " needs ", option("dump_every"), " DT > 0: the time between frames"});
  }
  if (spec.dump.empty() && spec.dump_every != 0.0) {
    throw RequestError({option("dump_every"), " needs ", option("dump"), " FILE"});
  }
  if (!spec.log.empty() && !positive(spec.log_every)) {
    throw RequestError(
        {option("log"), " needs ", option("log_every"), " DT > 0: the time between rows"});
  }
  if (spec.log.empty() && spec.log_every != 0.0) {
    throw RequestError({option("log_every"), " needs ", option("log"), " FILE"});
  }
  if (spec.checkpoint_every && spec.checkpoint.empty()) {
    throw RequestError(
        {option("checkpoint_every"), " needs ", option("checkpoint"), " FILE: where to save"});
  }
  if (spec.measure_from && !(*spec.measure_from >= 0.0 && std::isfinite(*spec.measure_from))) {
    throw RequestError(
        {option("measure_from"), fmt::format(" must be >= 0, got {}", *spec.measure_from)});
  }
  if (!spec.final_state.empty()) {
    try {
      final_format(spec.final_state);
    } catch (const std::invalid_argument& e) {
      throw RequestError({option("final"), std::string(" ") + e.what()});
    }
  }
  check_files_apart({}, output_files(spec));
}

void check_run_in_box(const RunSpec& spec, double now, bool periodic, bool sheared,
                      SamplerKind sampler) {
  check_latest_time(spec.end_time);
  if (!spec.dump.empty() && (spec.end_time - now) / spec.dump_every > kMostRows) {
    throw RequestError(
        {option("dump_every"), fmt::format(" {} would write more than 10^7 frames up to {}",
                                           spec.dump_every, spec.end_time)});
  }
  if (!spec.log.empty() && (spec.end_time - now) / spec.log_every > kMostRows) {
    throw RequestError(
        {option("log_every"), fmt::format(" {} would write more than 10^7 rows up to {}",
                                          spec.log_every, spec.end_time)});
  }
  if (spec.transport && !periodic) {
    throw RequestError({option("transport"),
                        " needs a periodic box: walls take momentum and energy out of the fluxes "
                        "the coefficients come from"});
  }
  if (spec.transport && sampler == SamplerKind::ecmc) {
    throw RequestError({option("transport"), " needs dynamics (", option("sampler", "md"),
                        "): event chains have no velocities, so no fluxes to take coefficients "
                        "from"});
  }
  if (spec.transport && sheared) {
    throw RequestError({option("transport"),
                        " measures the coefficients of a fluid at rest (Einstein-Helfand); a "
                        "sheared run gives its viscosity directly, in the summary's "
                        "\"shear_viscosity\""});
  }
}

template <std::size_t D>
void check_run(const Simulation<D>& simulation, const Start& start, const RunSpec& spec,
               const std::vector<NamedFile>& others) {
  check_run_spec(spec);
  std::vector<NamedFile> outputs = others;
  const std::vector<NamedFile> own = output_files(spec);
  outputs.insert(outputs.end(), own.begin(), own.end());
  // A resumed run may save its checkpoint where it read it.
  check_files_apart(
      {{"the input FILE", start_file_path(start.input), start.resumed ? "checkpoint" : ""}},
      outputs);

  simulation.check_target(spec.end_time);
  const double now = simulation.time();
  check_run_in_box(spec, now, simulation.state().box.periodic(), simulation.state().box.sheared(),
                   simulation.settings().sampler.kind);
  check_outputs_fit(simulation, spec);
  if (spec.measure_from) {
    const double from = *spec.measure_from;
    if (from < now && start.resumed) {
      throw RequestError({option("measure_from"),
                          fmt::format(" {} is before the checkpoint's time {}: the measurement "
                                      "can only start from there on",
                                      from, now)});
    }
    // A checkpointed run may stop before its equilibration ends: the resumed run finishes it.
    if (from < now || (from > spec.end_time && spec.checkpoint.empty())) {
      throw RequestError({option("measure_from"), fmt::format(" must be between {} and ", now),
                          option("end_time"), fmt::format(" ({}), got {}", spec.end_time, from)});
    }
  }
  if (!spec.checkpoint.empty()) probe(spec.checkpoint);
  if (!spec.summary.empty() && spec.summary != "-") probe(spec.summary);
  if (!spec.final_state.empty()) probe(spec.final_state);
}

template void check_run(const Simulation<2>&, const Start&, const RunSpec&,
                        const std::vector<NamedFile>&);
template void check_run(const Simulation<3>&, const Start&, const RunSpec&,
                        const std::vector<NamedFile>&);

}  // namespace carom
