// The event log (carom run --events FILE): one line a collision, as the run processes them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <ostream>

#include "carom/engine/simulation.hpp"

namespace carom {

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

}  // namespace carom
