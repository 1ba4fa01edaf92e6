// Progress of a long run on stderr: simulated time, percent, events per second, the time left
// and the compressibility factor Z measured so far. Shown only when stderr is a terminal, only
// once a run has taken more than a second, and never with --quiet; the line is cleared at the
// end, so nothing remains in the output.
#pragma once

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

#include "carom/simulation.hpp"

namespace carom::cli {

template <std::size_t D>
class Progress final : public Observer<D> {
 public:
  // Looks at the clock every few thousand events.
  static constexpr std::uint64_t kEvery = 4096;
  Progress(double start, double end)
      : Observer<D>(Trigger::every_events(kEvery)), start_(start), end_(end) {}
  ~Progress() override {
    if (shown_) std::fprintf(stderr, "\r%*s\r", 100, "");
  }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Whether a progress line belongs on this stderr.
  static bool wanted(bool quiet) { return !quiet && ::isatty(STDERR_FILENO) == 1; }

  void observe(const Simulation<D>& simulation) override {
    events_ += kEvery;
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - began_).count();
    if (elapsed < 1.0 || now - last_ < std::chrono::milliseconds(250)) return;
    last_ = now;
    shown_ = true;
    const double time = simulation.time();
    const double done = end_ > start_ ? (time - start_) / (end_ - start_) : 1.0;
    const double left = done > 0.0 ? elapsed * (1.0 - done) / done : 0.0;
    // The compressibility factor over the measurement window so far (O(N): every 250 ms at most).
    const Observables<D> o = simulation.observables();
    const std::string z =
        o.elapsed > 0.0 ? fmt::format("  Z = {:.5g}", o.compressibility_factor) : std::string();
    std::fprintf(stderr, "\rt = %.6g / %.6g (%4.1f%%)  %.3g events/s  %d:%02d left%s   ", time,
                 end_, 100.0 * done, static_cast<double>(events_) / elapsed,
                 static_cast<int>(left) / 60, static_cast<int>(left) % 60, z.c_str());
    std::fflush(stderr);
  }

 private:
  using Clock = std::chrono::steady_clock;
  double start_, end_;
  bool shown_ = false;
  std::uint64_t events_ = 0;
  Clock::time_point began_ = Clock::now(), last_ = began_;
};

}  // namespace carom::cli
