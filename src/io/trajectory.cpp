#include "carom/io/trajectory.hpp"
#include "carom/io/shown_velocities.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace carom {

template <std::size_t D>
void FrameWriter<D>::observe(const Simulation<D>& simulation) {
  const double t = simulation.time();
  const auto index = static_cast<std::uint64_t>(std::llround(t / this->trigger().period));
  if (shows_at_rest(simulation)) {
    format_->frame_at_rest(out_, index, t, simulation.state());
  } else {
    format_->frame(out_, index, t, simulation.state());
  }
  if (!out_.flush()) throw std::runtime_error("cannot write the trajectory");
}

template class FrameWriter<2>;
template class FrameWriter<3>;

}  // namespace carom
