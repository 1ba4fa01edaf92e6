#include "carom/io/final_state.hpp"

#include <fmt/format.h>

#include <optional>
#include <stdexcept>

#include "carom/engine/engine.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/trajectory_kind.hpp"
#include "gsd_format.hpp"

namespace carom {

FinalFormat final_format(std::string_view path) {
  const std::optional<TrajectoryKind> kind = trajectory_kind_of(path);
  if (!kind) return FinalFormat::classic;
  if (*kind == TrajectoryKind::gsd) return FinalFormat::gsd;
  throw std::invalid_argument(fmt::format(
      "{} names a trajectory format, which runs do not start from: name the end state "
      "FILE.gsd (GSD, with carom's double-precision copy) or anything else for carom's start "
      "format (FILE.txt)",
      path));
}

template <std::size_t D>
void write_final_state(std::ostream& out, FinalFormat format, const System<D>& system, double t,
                       Rule rule, bool at_rest) {
  System<D> end = system;
  const double stored = system.stored(t);
  for (std::size_t i = 0; i < end.size(); ++i) {
    Particle<D>& p = end.particles[i];
    p = synchronised(p, end.box, stored, end.records[i].image);
    if (at_rest) p.velocity = Vec<D>{};
  }
  if (format == FinalFormat::gsd) {
    GsdFormat<D>(true).frame(out, 0, t, end);
  } else {
    write_start(out, end, rule);
  }
  if (!out) throw std::runtime_error("cannot write the end state");
}

template void write_final_state(std::ostream&, FinalFormat, const System<2>&, double, Rule, bool);
template void write_final_state(std::ostream&, FinalFormat, const System<3>&, double, Rule, bool);

}  // namespace carom
