#include "carom/core/event.hpp"

#include <fmt/format.h>

#include "carom/core/system.hpp"

namespace carom {

std::string describe(const Event& event) {
  if (event.is_wall()) {
    return fmt::format("Collision: particle {} with wall {} ({})", event.first, event.partner,
                       wall_name(event.partner));
  }
  return fmt::format("Collision: particle {} with particle {}", event.first, event.partner);
}

}  // namespace carom
