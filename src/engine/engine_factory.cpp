// make_engine: the one place that knows the concrete engines.
#include <memory>
#include <utility>

#include "carom/engine/engine.hpp"
#include "fast_engine.hpp"
#include "list_engine.hpp"
#include "reference_engine.hpp"

namespace carom {

template <std::size_t D>
std::unique_ptr<Engine<D>> make_engine(EngineKind kind, System<D> system, const CollisionRule& rule,
                                       const Growth& growth) {
  if (kind == EngineKind::reference) {
    return std::make_unique<ReferenceEngine<D>>(std::move(system), rule, growth);
  }
  // Dense systems: a sphere at packing 0.45 has some 26 candidates in the 27 cells around it and
  // about 18 in its list (see ListEngine::suits for when lists pay).
  if (ListEngine<D>::suits(system, growth)) {
    return std::make_unique<ListEngine<D>>(std::move(system), rule);
  }
  return std::make_unique<FastEngine<D>>(std::move(system), rule, growth);
}

template std::unique_ptr<Engine<2>> make_engine(EngineKind, System<2>, const CollisionRule&,
                                                const Growth&);
template std::unique_ptr<Engine<3>> make_engine(EngineKind, System<3>, const CollisionRule&,
                                                const Growth&);

}  // namespace carom
