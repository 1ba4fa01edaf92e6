#include "carom/io/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string_view>

#include "carom/engine/validation.hpp"
#include "carom/io/atomic_file.hpp"
#include "carom/io/input_error.hpp"
#include "carom/version.hpp"
#include "checkpoint_checksum.hpp"
#include "json_text.hpp"

namespace carom {

namespace {

using Json = nlohmann::ordered_json;

// The fluxes' integrals and rates as stored: every field, so a resumed run goes on bit for bit.
Json fluxes_json(const Fluxes& f) {
  return {{"kinetic_stress", f.kinetic_stress},
          {"collisional_stress", f.collisional_stress},
          {"kinetic_heat", f.kinetic_heat},
          {"collisional_heat", f.collisional_heat},
          {"stress_rate", f.stress_rate},
          {"heat_rate", f.heat_rate},
          {"since", f.since},
          {"time", f.time},
          {"stored", f.stored},
          {"heat", f.heat}};
}

// The key "fluxes" only for a run that keeps them (and checkpoints before carom 1.6 have none).
Json counts_json(const Counts& c) {
  Json j = {{"events", c.events},
            {"pair_collisions", c.pair_collisions},
            {"wall_collisions", c.wall_collisions},
            {"elastic_by_tc", c.elastic_by_tc},
            {"virial", c.virial},
            {"wall_momentum", c.wall_momentum}};
  if (c.fluxes) j["fluxes"] = fluxes_json(*c.fluxes);
  return j;
}

// The drift record, null without one (the key is absent from checkpoints before carom 1.5; those
// of earlier versions hold intervals of another kind, under "every").
Json drift_json(const std::optional<DriftRecord>& drift) {
  if (!drift) return nullptr;
  Json totals = Json::array();
  for (const Counts& c : drift->totals) totals.push_back(counts_json(c));
  return {{"block_length", drift->block_length},
          {"boundaries", drift->boundaries},
          {"totals", totals},
          {"temperatures", drift->temperatures}};
}

// The transport measurement under way (absent from checkpoints of runs without one).
Json transport_json(const TransportRecord& t) {
  Json blocks = Json::array();
  for (const TransportBlock& b : t.blocks) {
    blocks.push_back({b.self_diffusion, b.shear_viscosity, b.thermal_conductivity});
  }
  return {
      {"spacing", t.spacing}, {"lag_spacing", t.lag_spacing}, {"block_samples", t.block_samples},
      {"samples", t.samples}, {"origin", t.origin},           {"half_msd", t.half_msd},
      {"blocks", blocks}};
}

// A time that may be "never" (json null).
Json time_or_null(double t) {
  return std::isfinite(t) ? Json(t) : Json(nullptr);
}

// Where in `json` the first number that is not finite lies (JSON would write it as null, which
// no reader takes back as a number), as "counts/fluxes/kinetic_stress/0"; nullopt if none.
std::optional<std::string> first_non_finite(const Json& json) {
  if (json.is_number_float()) {
    return std::isfinite(json.get<double>()) ? std::nullopt : std::optional<std::string>("");
  }
  if (!json.is_structured()) return std::nullopt;
  std::size_t index = 0;
  for (auto it = json.begin(); it != json.end(); ++it, ++index) {
    if (const auto below = first_non_finite(*it)) {
      const std::string key = json.is_object() ? it.key() : std::to_string(index);
      return below->empty() ? key : key + "/" + *below;
    }
  }
  return std::nullopt;
}

}  // namespace

template <std::size_t D>
void write_checkpoint(std::ostream& out, const Checkpoint<D>& c) {
  Json box = Json::array();
  for (std::size_t k = 0; k < D; ++k) box.push_back(c.system.box.size[k]);
  Json measurement = {{"start_time", c.measurement.start_time},
                      {"kinetic_energy_initial", c.measurement.kinetic_energy_initial},
                      {"counts", counts_json(c.measurement.counts)}};
  if (c.measurement.flux_origin)
    measurement["flux_origin"] = fluxes_json(*c.measurement.flux_origin);
  Json head = {
      {"carom_checkpoint", has_types(c.system) ? kCheckpointFormat : 5},
      {"carom_version", kVersion},
      {"source", c.source},
      {"dimension", D},
      {"box", box},
      {"boundary", name_of(c.system.box.boundary)},
      {"rule", name_of(c.settings.rule.rule)},
      {"restitution", c.settings.rule.restitution},
      {"tc", c.settings.rule.elastic_within},
      {"engine", name_of(c.settings.engine)},
      {"sampler", name_of(c.settings.sampler.kind)},
      {"time", c.time},
      {"epoch", c.system.epoch},
      {"settled", c.settled},
      {"counts", counts_json(c.counts)},
      {"measurement", measurement},
      {"measure_from", c.measure_from ? Json(*c.measure_from) : Json(nullptr)},
      {"z_drift", drift_json(c.records.drift)},
  };
  if (c.records.window_start) {
    head["window_records"] = {{"window_start", *c.records.window_start},
                              {"end_time", *c.records.end_time}};
  }
  if (c.seed) head["seed"] = *c.seed;
  if (has_types(c.system)) head["types"] = c.system.type_names;
  if (c.records.transport) head["transport"] = transport_json(*c.records.transport);
  if (c.system.box.sheared()) {
    head["shear"] = {{"rate", c.system.box.shear_rate}, {"offset", c.system.box.shear_offset}};
  }
  if (const Thermostat& t = c.settings.thermostat; t.kind != ThermostatKind::none) {
    std::ostringstream rng;
    rng << c.thermostat_rng;
    head["thermostat"] = {{"kind", name_of(t.kind)}, {"kT", t.kT},
                          {"every", t.every},        {"rate", t.rate},
                          {"seed", t.seed},          {"instants", c.thermostat_instants},
                          {"rng", rng.str()}};
    if (resets_as_events(t)) head["thermostat"]["next"] = c.thermostat_next;
  }
  if (c.settings.sampler.kind == SamplerKind::ecmc) {
    if (!c.chain) throw std::logic_error("an event-chain checkpoint without its chain");
    std::ostringstream rng;
    rng << c.chain->rng;
    head["chains"] = {{"chain_length", c.settings.sampler.chain_length},
                      {"seed", c.settings.sampler.seed},
                      {"active", c.chain->active},
                      {"axis", c.chain->axis},
                      {"chain_end", c.chain->chain_end},
                      {"rng", rng.str()}};
  }
  // A number the run overflowed would be written as null: a checkpoint carom could not read.
  if (const auto where = first_non_finite(head)) {
    throw std::runtime_error(fmt::format(
        "cannot save a checkpoint: the run's {} is not a finite number (it overflowed double "
        "precision: speeds or a shear rate too large to integrate)",
        *where));
  }
  std::string text = dump_json(head, 1);
  Fnv1a hash;
  add_head(hash, parse_json(text));  // keys sorted, as the reader sees them
  text.resize(text.size() - 2);      // reopen the object
  out << text << ",\n \"particles\": [";
  // One line a particle: position, velocity, time, radius, mass, wall and pair collisions, last
  // collision (null: none yet), image flags, and (format 6) the type's index.
  for (std::size_t i = 0; i < c.system.size(); ++i) {
    const Particle<D>& p = c.system.particles[i];
    const ParticleRecord& r = c.system.records[i];
    Json row = Json::array();
    for (std::size_t k = 0; k < D; ++k) row.push_back(p.position[k]);
    for (std::size_t k = 0; k < D; ++k) row.push_back(p.velocity[k]);
    row.insert(row.end(), {Json(p.time), Json(p.radius), Json(r.mass), Json(r.wall_collisions),
                           Json(r.pair_collisions), time_or_null(r.last_collision)});
    for (std::size_t k = 0; k < D; ++k) row.push_back(r.image[k]);
    if (has_types(c.system)) row.push_back(r.type);
    const std::string line = row.dump();
    hash.add(line);
    hash.add("\n");
    out << (i == 0 ? "\n  " : ",\n  ") << line;
  }
  out << "\n ],\n \"checksum\": \"" << hash.text() << "\"\n}\n";
}

template <std::size_t D>
void save_checkpoint(const std::string& path, const Checkpoint<D>& checkpoint) {
  AtomicFile file(path);
  write_checkpoint(file.stream(), checkpoint);
  file.commit();
}

template void write_checkpoint(std::ostream&, const Checkpoint<2>&);
template void write_checkpoint(std::ostream&, const Checkpoint<3>&);
template void save_checkpoint(const std::string&, const Checkpoint<2>&);
template void save_checkpoint(const std::string&, const Checkpoint<3>&);

}  // namespace carom
