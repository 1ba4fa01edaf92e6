#include "carom/run/compress_run.hpp"

#include <fmt/format.h>

#include <chrono>
#include <nlohmann/json.hpp>

#include "carom/engine/initial.hpp"
#include "carom/run/request.hpp"
#include "carom/version.hpp"
#include "io/json_text.hpp"

namespace carom {

namespace {

template <std::size_t D>
CompressionResult compress_system(System<D> start, const CompressionSpec& spec,
                                  const CompressionHooks& hooks) {
  const auto began = std::chrono::steady_clock::now();
  std::optional<Compression<D>> compression;
  try {
    compression.emplace(std::move(start), spec.settings);
  } catch (const std::invalid_argument& e) {
    throw RequestError(fmt::format("cannot compress {}: {}", spec.input, e.what()));
  }
  Compression<D>& c = *compression;
  c.set_stop_flag(hooks.stop);
  while (c.status() == CompressionStatus::running &&
         !(hooks.stop != nullptr && hooks.stop->load() != 0)) {
    c.run(c.system().size());
    if (hooks.progress) {
      hooks.progress({c.packing_fraction(), c.compressibility_factor(), c.time(), c.events()});
    }
  }
  System<D> packing = c.system();
  CompressionSummary s;
  s.grown_diameter = mean_diameter(packing);
  if (spec.unit_diameter) scale_lengths(packing, 1.0 / s.grown_diameter);
  s.input = spec.input;
  s.dimension = static_cast<int>(D);
  s.n = packing.size();
  s.boundary = packing.box.boundary;
  s.status = c.status() == CompressionStatus::reached_target ? "reached_target"
             : c.status() == CompressionStatus::jammed       ? "jammed"
                                                             : "interrupted";
  s.target = spec.settings.target;
  s.packing_fraction = c.packing_fraction();
  s.compressibility_factor = c.compressibility_factor();
  s.rate = spec.settings.rate;
  s.temperature = spec.settings.temperature;
  s.jammed_pressure = spec.settings.jammed_pressure;
  s.time = c.time();
  s.events = c.events();
  s.mean_diameter = mean_diameter(packing);
  s.unit_diameter = spec.unit_diameter;
  s.box.assign(packing.box.size.c.begin(), packing.box.size.c.begin() + D);
  s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  return {AnySystem(std::move(packing)), std::move(s)};
}

}  // namespace

void write_json(std::ostream& out, const CompressionSummary& s) {
  const nlohmann::json json = {
      {"carom_version", kVersion},
      {"input", s.input},
      {"dimension", s.dimension},
      {"n", s.n},
      {"boundary", name_of(s.boundary)},
      {"status", s.status},
      {"target", s.target ? nlohmann::json(*s.target) : nlohmann::json(nullptr)},
      {"packing_fraction", s.packing_fraction},
      {"compressibility_factor", s.compressibility_factor},
      {"rate", s.rate},
      {"kT", s.temperature},
      {"jam_pressure", s.jammed_pressure},
      {"time", s.time},
      {"events", s.events},
      {"mean_diameter", s.mean_diameter},
      {"unit_diameter", s.unit_diameter},
      {"box", s.box},
      {"wall_seconds", s.wall_seconds}};
  out << dump_json(json, 2) << '\n';
}

std::optional<std::string> jammed_short(const CompressionSummary& s) {
  if (!s.target || s.status != "jammed") return std::nullopt;
  return fmt::format("the {} jammed at packing fraction {:.6f} (Z = {:.3g}) before reaching {}",
                     s.dimension == 2 ? "disks" : "spheres", s.packing_fraction,
                     s.compressibility_factor, *s.target);
}

std::optional<std::string> shortfall(const CompressionSummary& s, const std::string& packing) {
  const std::optional<std::string> jammed = jammed_short(s);
  if (!jammed) return std::nullopt;
  return fmt::format("{}; the jammed packing is in {}", *jammed, packing);
}

CompressionResult compress(AnySystem start, const CompressionSpec& spec,
                           const CompressionHooks& hooks) {
  return std::visit([&](auto& system) { return compress_system(std::move(system), spec, hooks); },
                    start);
}

}  // namespace carom
