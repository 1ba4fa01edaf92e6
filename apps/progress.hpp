// Progress of a long command on stderr. On a terminal, one line rewritten in place every 250 ms
// once the work has taken more than a second, cleared at the end so that nothing remains; with
// --progress SECONDS, a whole line every SECONDS whatever stderr is (a batch job's log, like
// LAMMPS' thermo output). Never with --quiet unless --progress asks for it.
#pragma once

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include "carom/run/run.hpp"

namespace carom::cli {

// Where the status goes, and when.
class StatusLine {
 public:
  // `every`: --progress's period in seconds, if given.
  StatusLine(bool quiet, std::optional<double> every)
      : every_(every), live_(!every && !quiet && ::isatty(STDERR_FILENO) == 1) {}
  ~StatusLine() {
    if (shown_) std::fprintf(stderr, "\r%*s\r", 100, "");
  }
  StatusLine(const StatusLine&) = delete;
  StatusLine& operator=(const StatusLine&) = delete;

  bool active() const { return live_ || every_.has_value(); }

  // Whether a line is due now; the caller then makes it and calls print.
  bool due() {
    if (!active()) return false;
    const auto now = Clock::now();
    const double elapsed = seconds_since(began_, now);
    const bool due = every_ ? seconds_since(last_, now) >= *every_
                            : elapsed >= 1.0 && seconds_since(last_, now) >= 0.25;
    if (due) last_ = now;
    return due;
  }

  void print(const std::string& text) {
    if (live_) {
      shown_ = true;
      std::fprintf(stderr, "\r%s   ", text.c_str());
    } else {
      std::fprintf(stderr, "%s\n", text.c_str());
    }
    std::fflush(stderr);
  }

  double elapsed() const { return seconds_since(began_, Clock::now()); }

 private:
  using Clock = std::chrono::steady_clock;
  static double seconds_since(Clock::time_point then, Clock::time_point now) {
    return std::chrono::duration<double>(now - then).count();
  }
  std::optional<double> every_;
  bool live_;
  bool shown_ = false;
  Clock::time_point began_ = Clock::now(), last_ = began_;
};

// A duration as 0:42, 12:05 or 3:07:59.
inline std::string clock_time(double seconds) {
  const auto s = static_cast<long long>(seconds);
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

// A run's status: simulated time, percent, events per second, the time left and the
// compressibility factor Z measured so far (the library calls show() every few thousand events).
class RunStatusLine {
 public:
  RunStatusLine(bool quiet, std::optional<double> every) : line_(quiet, every) {}

  // Whether a status belongs on this stderr at all.
  static bool wanted(bool quiet, std::optional<double> every) {
    return StatusLine(quiet, every).active();
  }

  void show(const AnySimulation& simulation, const RunProgress& progress) {
    if (!line_.due()) return;
    const double time = simulation.time();
    const double span = progress.end_time - progress.start_time;
    const double done = span > 0.0 ? (time - progress.start_time) / span : 1.0;
    const double left = done > 0.0 ? progress.wall_seconds * (1.0 - done) / done : 0.0;
    // The compressibility factor over the measurement window so far (O(N), once a line).
    const std::optional<double> z = simulation.compressibility_factor();
    line_.print(fmt::format("t = {:.6g} / {:.6g} ({:4.1f}%)  {:.3g} events/s  {} left{}", time,
                            progress.end_time, 100.0 * done,
                            static_cast<double>(progress.events) / progress.wall_seconds,
                            clock_time(left), z ? fmt::format("  Z = {:.5g}", *z) : ""));
  }

 private:
  StatusLine line_;
};

}  // namespace carom::cli
