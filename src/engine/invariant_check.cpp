#include "carom/engine/invariant_check.hpp"

#include <fmt/format.h>

#include "carom/engine/overlap.hpp"

namespace carom {

template <std::size_t D>
void InvariantCheck<D>::observe(const Simulation<D>& simulation) {
  const Event& event = simulation.last_event();
  ++events_;
  std::optional<std::string> violation;
  if (event.time < last_) {
    violation = fmt::format("time ran backwards from {} to {}", last_, event.time);
  } else if (events_ % every_ == 0) {
    violation = find_violation(simulation.state(), simulation.stored_time());
  }
  last_ = event.time;
  if (violation) {
    throw InvariantError(fmt::format("invariant violated at event {} (t = {}, {}): {}",
                                     simulation.counts().events, event.time, describe(event),
                                     *violation));
  }
}

template class InvariantCheck<2>;
template class InvariantCheck<3>;

}  // namespace carom
