// make_engine and make_run_engine: the one place that knows the concrete engines.
#include <cmath>
#include <memory>
#include <optional>
#include <utility>

#include "carom/engine/engine.hpp"
#include "ecmc_engine.hpp"
#include "fast_engine.hpp"
#include "list_engine.hpp"
#include "reference_engine.hpp"
#include "run_engine.hpp"

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

template <std::size_t D>
double default_chain_length(const System<D>& system, double mean_diameter) {
  const double side = std::pow(box_volume(system.box), 1.0 / static_cast<double>(D));
  return 0.24 * side / mean_diameter;
}

template <std::size_t D>
std::unique_ptr<Engine<D>> make_run_engine(const Settings& settings, System<D> system,
                                           const std::optional<ChainState>& chain) {
  if (settings.sampler.kind == SamplerKind::md) {
    return make_engine(settings.engine, std::move(system), settings.rule);
  }
  const double length = settings.sampler.chain_length;
  if (chain) return std::make_unique<EcmcEngine<D>>(std::move(system), length, *chain);
  pcg32 rng(settings.sampler.seed);
  return std::make_unique<EcmcEngine<D>>(std::move(system), length, rng);
}

template double default_chain_length(const System<2>&, double);
template double default_chain_length(const System<3>&, double);
template std::unique_ptr<Engine<2>> make_run_engine(const Settings&, System<2>,
                                                    const std::optional<ChainState>&);
template std::unique_ptr<Engine<3>> make_run_engine(const Settings&, System<3>,
                                                    const std::optional<ChainState>&);
template std::unique_ptr<Engine<2>> make_engine(EngineKind, System<2>, const CollisionRule&,
                                                const Growth&);
template std::unique_ptr<Engine<3>> make_engine(EngineKind, System<3>, const CollisionRule&,
                                                const Growth&);

}  // namespace carom
