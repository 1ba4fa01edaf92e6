#include "carom/io/event_log.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <stdexcept>

#include "whole_lines.hpp"

namespace carom {

template <std::size_t D>
void EventLogWriter<D>::observe(const Simulation<D>& simulation) {
  const Event& event = simulation.last_event();
  out_ << fmt::format("{},{},{},{}\n", event.time, event.is_wall() ? "wall" : "pair", event.first,
                      event.partner);
  if (!out_) throw std::runtime_error("cannot write the event log");
}

template <std::size_t D>
std::uint64_t EventLogWriter<D>::events_before(std::istream& in, double t, bool inclusive) {
  LineReader reader{in, 0, {}};
  if (!reader.next() || reader.line + "\n" != kHeader) return 0;
  std::uint64_t kept = reader.offset;
  while (reader.next()) {
    char* end = nullptr;
    const double time = std::strtod(reader.line.c_str(), &end);
    if (end == reader.line.c_str() || *end != ',' || !written_before(time, t, inclusive)) break;
    kept = reader.offset;
  }
  return kept;
}

template class EventLogWriter<2>;
template class EventLogWriter<3>;

}  // namespace carom
