// Reading checkpoints of every format carom has written (1 to kCheckpointFormat).
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
#include "carom/io/checkpoint.hpp"
#include "carom/io/input_error.hpp"
#include "carom/version.hpp"
#include "checked_json.hpp"
#include "checkpoint_check.hpp"
#include "checkpoint_checksum.hpp"
#include "json_text.hpp"

namespace carom {

namespace {

// Particle indices are stored in 32 bits (see Event), as the classic reader also refuses.
constexpr std::size_t kMaxParticles = 0x7FFFFFF0;

// The fields of one checkpoint beyond plain values: counts, fluxes and the transport record,
// each checked for consistency.
template <class Fail>
class CheckpointFields : public CheckedJson<Fail> {
 public:
  using CheckedJson<Fail>::CheckedJson;
  using CheckedJson<Fail>::at;
  using CheckedJson<Fail>::number;
  using CheckedJson<Fail>::coordinate;
  using CheckedJson<Fail>::count;
  using CheckedJson<Fail>::flag;

  Counts counts(const nlohmann::json& object, const std::string& where) const {
    const auto get = [&](const char* key) {
      return count(at(object, key, where),
                   fmt::format("\"{}\"{}", key, where.empty() ? "" : " in " + where));
    };
    const auto real = [&](const char* key) {
      return number(at(object, key, where),
                    fmt::format("\"{}\"{}", key, where.empty() ? "" : " in " + where));
    };
    Counts c;
    c.events = get("events");
    c.pair_collisions = get("pair_collisions");
    c.wall_collisions = get("wall_collisions");
    c.elastic_by_tc = get("elastic_by_tc");
    c.virial = real("virial");
    c.wall_momentum = real("wall_momentum");
    if (const auto found = object.find("fluxes"); found != object.end()) {
      c.fluxes = fluxes(*found, "\"fluxes\"" + in_where(where));
    }
    // Counts::add counts every event as a wall or a pair collision, and TC-made-elastic ones
    // among the pair collisions.
    const std::string in = where.empty() ? "" : " in " + where;
    if (c.events != c.wall_collisions + c.pair_collisions || c.wall_collisions > c.events ||
        c.pair_collisions > c.events) {
      fail_(fmt::format("the counts{} do not add up: {} events, {} wall and {} pair collisions", in,
                        c.events, c.wall_collisions, c.pair_collisions));
    }
    if (c.elastic_by_tc > c.pair_collisions) {
      fail_(
          fmt::format("the counts{} do not add up: {} collisions made elastic by TC out of {} "
                      "pair collisions",
                      in, c.elastic_by_tc, c.pair_collisions));
    }
    return c;
  }

  // The transport record (its origin's size is checked once the particles are read).
  TransportRecord transport(const nlohmann::json& object) const {
    const std::string where = "\"transport\"";
    const auto numbers = [&](const nlohmann::json& list, const std::string& what) {
      if (!list.is_array()) fail_(fmt::format("{} in {} must be a list of numbers", what, where));
      std::vector<double> out;
      out.reserve(list.size());
      for (const auto& value : list)
        out.push_back(number(value, fmt::format("{} in {}", what, where)));
      return out;
    };
    TransportRecord t;
    t.spacing = coordinate(at(object, "spacing", where), "the transport's spacing");
    t.block_samples = count(at(object, "block_samples", where), "the transport's block_samples");
    if (!(t.spacing > 0.0) || t.block_samples < 9) {
      fail_(fmt::format("the transport's spacing ({}) and block_samples ({}) are not a schedule",
                        t.spacing, t.block_samples));
    }
    if (object.contains("lag_spacing")) {  // absent from an older carom's
      t.lag_spacing = coordinate(object.at("lag_spacing"), "the transport's lag_spacing");
      if (!(t.lag_spacing >= t.spacing)) {
        fail_(fmt::format("the transport's lag_spacing ({}) is below its spacing ({})",
                          t.lag_spacing, t.spacing));
      }
    }
    const auto& samples = at(object, "samples", where);
    if (!samples.is_array() || samples.size() >= t.block_samples) {
      fail_(fmt::format("\"samples\" in {} must be a list of fewer than {} samples", where,
                        t.block_samples));
    }
    for (const auto& sample : samples) {
      const std::vector<double> values = numbers(sample, "a sample");
      if (values.size() != 9) fail_(fmt::format("a sample in {} must have 9 numbers", where));
      MomentSample s;
      std::copy(values.begin(), values.end(), s.begin());
      t.samples.push_back(s);
    }
    t.origin = numbers(at(object, "origin", where), "\"origin\"");
    t.half_msd = number(at(object, "half_msd", where), "the transport's half_msd");
    const auto& blocks = at(object, "blocks", where);
    if (!blocks.is_array()) fail_(fmt::format("\"blocks\" in {} must be a list", where));
    for (const auto& block : blocks) {
      const std::vector<double> values = numbers(block, "a block");
      if (values.size() != 3) fail_(fmt::format("a block in {} must have 3 numbers", where));
      t.blocks.push_back({values[0], values[1], values[2]});
    }
    return t;
  }

  Fluxes fluxes(const nlohmann::json& object, const std::string& where) const {
    const auto components = [&]<std::size_t K>(const char* key, std::array<double, K>& out) {
      const nlohmann::json& list = at(object, key, where);
      if (!list.is_array() || list.size() != K) {
        fail_(fmt::format("\"{}\" in {} must be a list of {} numbers, found {}", key, where, K,
                          shown(list)));
      }
      for (std::size_t k = 0; k < K; ++k)
        out[k] = number(list[k], fmt::format("\"{}\" in {}", key, where));
    };
    Fluxes f;
    components("kinetic_stress", f.kinetic_stress);
    components("collisional_stress", f.collisional_stress);
    components("kinetic_heat", f.kinetic_heat);
    components("collisional_heat", f.collisional_heat);
    components("stress_rate", f.stress_rate);
    components("heat_rate", f.heat_rate);
    f.since = coordinate(at(object, "since", where), fmt::format("\"since\" in {}", where));
    f.time = coordinate(at(object, "time", where), fmt::format("\"time\" in {}", where));
    f.stored = coordinate(at(object, "stored", where), fmt::format("\"stored\" in {}", where));
    f.heat = flag(at(object, "heat", where), fmt::format("\"heat\" in {}", where));
    if (f.since > f.time) {
      fail_(
          fmt::format("the fluxes in {} begin at {}, after their time {}", where, f.since, f.time));
    }
    return f;
  }

 private:
  using CheckedJson<Fail>::fail_;
  static std::string in_where(const std::string& where) {
    return where.empty() ? "" : " in " + where;
  }
};

// The checkpoint of one dimension as stored; `format` 1 is carom 1.0's (2D, counts only since the
// window opened, the TC model reading stored times).
template <std::size_t D, class Fail>
Checkpoint<D> checkpoint_from(const nlohmann::json& j, int format, const Fail& fail) {
  const CheckpointFields<Fail> f(fail);
  Checkpoint<D> c;
  c.source = f.text(f.at(j, format == 1 ? "input" : "source"), "the source");
  const nlohmann::json& box = f.at(j, "box");
  if (!box.is_array() || box.size() != D) {
    fail(fmt::format("the box must be a list of {} sides, found {}", D, shown(box)));
  }
  for (std::size_t k = 0; k < D; ++k) c.system.box.size[k] = f.size(box[k], "a box side");
  c.system.box.boundary = f.template choice<Boundary>(j, "boundary");
  if (const auto found = j.find("shear"); found != j.end() && !found->is_null()) {  // carom 1.7
    Box<D>& b = c.system.box;
    b.shear_rate = f.number(f.at(*found, "rate", "\"shear\""), "the shear rate");
    b.shear_offset = f.number(f.at(*found, "offset", "\"shear\""), "the shear offset");
    if (!b.periodic() || b.shear_rate == 0.0) {
      fail("\"shear\" needs a periodic box and a rate other than 0");
    }
    if (!(b.shear_offset >= 0.0 && b.shear_offset <= b.size[0])) {
      fail(fmt::format("the shear offset {} is not within the box's side {}", b.shear_offset,
                       b.size[0]));
    }
  }
  c.settings.rule.rule = f.template choice<Rule>(j, "rule");
  c.settings.rule.restitution = f.number(f.at(j, "restitution"), "the restitution");
  c.settings.rule.elastic_within = f.number(f.at(j, "tc"), "tc");
  c.settings.engine = f.template choice<EngineKind>(j, "engine");
  c.time = f.coordinate(f.at(j, "time"), "the time");
  if (format == 1) {
    // 1.0 saved at its last event and counted only the measurement window.
    c.counts = f.counts(j, "");
    c.measurement = {f.coordinate(f.at(j, "equilibrate"), "\"equilibrate\""),
                     f.number(f.at(j, "kinetic_energy_initial"), "\"kinetic_energy_initial\""),
                     c.counts, std::nullopt};
    if (c.measurement.start_time > c.time) {
      c.measure_from = c.measurement.start_time;
      c.measurement.start_time = 0.0;
    }
  } else {
    c.settled = f.flag(f.at(j, "settled"), "\"settled\"");
    c.counts = f.counts(f.at(j, "counts"), "\"counts\"");
    const auto& m = f.at(j, "measurement");
    c.measurement = {
        f.coordinate(f.at(m, "start_time", "\"measurement\""), "the measurement's start_time"),
        f.number(f.at(m, "kinetic_energy_initial", "\"measurement\""),
                 "the measurement's kinetic_energy_initial"),
        f.counts(f.at(m, "counts", "\"measurement\""), "\"measurement\""), std::nullopt};
    if (const auto found = m.find("flux_origin"); found != m.end()) {  // from carom 1.6
      c.measurement.flux_origin = f.fluxes(*found, "the measurement's \"flux_origin\"");
    }
    if (const auto& from = f.at(j, "measure_from"); !from.is_null()) {
      c.measure_from = f.coordinate(from, "\"measure_from\"");
    }
    // Checkpoints of earlier versions cut the window into intervals that depended on the run's end
    // (under "every"): a run resumed from one measures its errors afresh.
    if (const auto found = j.find("z_drift");
        found != j.end() && !found->is_null() && !found->contains("every")) {
      const std::string where = "\"z_drift\"";
      DriftRecord drift;
      drift.block_length =
          f.coordinate(f.at(*found, "block_length", where), "the drift's block_length");
      if (!(drift.block_length > 0.0)) fail("the drift's \"block_length\" must be above 0");
      const auto& boundaries = f.at(*found, "boundaries", where);
      const auto& totals = f.at(*found, "totals", where);
      const auto& temperatures = f.at(*found, "temperatures", where);
      if (!boundaries.is_array() || !totals.is_array() || !temperatures.is_array() ||
          boundaries.size() != totals.size() || boundaries.size() != temperatures.size()) {
        fail(
            "the drift's \"boundaries\", \"totals\" and \"temperatures\" must be lists of one "
            "length");
      }
      for (std::size_t b = 0; b < boundaries.size(); ++b) {
        drift.boundaries.push_back(f.coordinate(boundaries[b], "a drift block's boundary"));
        drift.totals.push_back(f.counts(totals[b], where));
        drift.temperatures.push_back(f.number(temperatures[b], "a drift block's temperature"));
      }
      c.records.drift = std::move(drift);
    }
    if (const auto found = j.find("thermostat"); found != j.end()) {  // from carom 1.6
      const std::string where = "\"thermostat\"";
      Thermostat& t = c.settings.thermostat;
      t.kind = f.template choice<ThermostatKind>(*found, "kind");
      t.kT = f.number(f.at(*found, "kT", where), "the thermostat's kT");
      t.every = f.number(f.at(*found, "every", where), "the thermostat's every");
      t.rate = f.number(f.at(*found, "rate", where), "the thermostat's rate");
      t.seed = f.count(f.at(*found, "seed", where), "the thermostat's seed");
      c.thermostat_instants = f.count(f.at(*found, "instants", where), "the thermostat's instants");
      std::istringstream rng(f.text(f.at(*found, "rng", where), "the thermostat's rng"));
      if (!(rng >> c.thermostat_rng)) fail("the thermostat's \"rng\" is not a pcg32 state");
      if (resets_as_events(t)) {
        c.thermostat_next =
            f.coordinate(f.at(*found, "next", where), "the thermostat's next reset");
        if (!(c.thermostat_next >= c.time)) {
          fail(fmt::format("the thermostat's next reset {} is before the checkpoint's time {}",
                           c.thermostat_next, c.time));
        }
      }
      try {
        check_thermostat(t);
      } catch (const std::invalid_argument& e) {
        fail(e.what());
      }
    }
    if (format >= 5) c.settings.sampler.kind = f.template choice<SamplerKind>(j, "sampler");
    if (const auto found = j.find("chains"); found != j.end()) {  // from carom 1.9
      const std::string where = "\"chains\"";
      Sampler& sampler = c.settings.sampler;
      sampler.chain_length = f.number(f.at(*found, "chain_length", where), "the chain length");
      if (!(sampler.chain_length > 0.0)) {
        fail(fmt::format("the chain length {} is not above 0", sampler.chain_length));
      }
      sampler.seed = f.count(f.at(*found, "seed", where), "the chains' seed");
      ChainState chain;
      const std::uint64_t active = f.count(f.at(*found, "active", where), "the active particle");
      const std::uint64_t axis = f.count(f.at(*found, "axis", where), "the chain's axis");
      if (axis >= D) fail(fmt::format("the chain's axis {} is not one of {} axes", axis, D));
      chain.active = static_cast<std::uint32_t>(std::min<std::uint64_t>(active, UINT32_MAX));
      chain.axis = static_cast<std::uint8_t>(axis);
      chain.chain_end = f.number(f.at(*found, "chain_end", where), "the chain's end");
      std::istringstream rng(f.text(f.at(*found, "rng", where), "the chains' rng"));
      if (!(rng >> chain.rng)) fail("the chains' \"rng\" is not a pcg32 state");
      c.chain = chain;
    }
    if (const auto found = j.find("transport"); found != j.end()) {
      c.records.transport = f.transport(*found);
    }
    if (const auto found = j.find("window_records"); found != j.end()) {
      const std::string where = "\"window_records\"";
      c.records.window_start =
          f.coordinate(f.at(*found, "window_start", where), "the window records' window_start");
      c.records.end_time =
          f.coordinate(f.at(*found, "end_time", where), "the window records' end_time");
    }
    if (const auto found = j.find("seed"); found != j.end()) {
      c.seed = f.count(*found, "the seed");
    }
  }
  const nlohmann::json& particles = f.at(j, "particles");
  if (!particles.is_array()) fail("\"particles\" must be a list of particle rows");
  if (particles.empty()) fail("no particles");
  if (particles.size() > kMaxParticles) {
    fail(fmt::format("{} particles, more than carom supports ({})", particles.size(),
                     kMaxParticles));
  }
  // Format 3 adds the image flags, format 6 the types (names in the head, an index a row).
  if (format >= 6) {
    const auto& names = f.at(j, "types");
    if (!names.is_array() || names.empty()) fail("\"types\" must be a list of type names");
    c.system.type_names.clear();
    for (const auto& name : names) {
      const std::string text = f.text(name, "a type name");
      if (text.empty()) fail("a type name is empty");
      if (std::find(c.system.type_names.begin(), c.system.type_names.end(), text) !=
          c.system.type_names.end()) {
        fail(fmt::format("the type name \"{}\" appears twice in \"types\"", text));
      }
      c.system.type_names.push_back(text);
    }
  }
  const std::size_t columns = format == 1   ? 2 * D + 5
                              : format == 2 ? 2 * D + 6
                              : format <= 5 ? 3 * D + 6
                                            : 3 * D + 7;
  c.system.particles.reserve(particles.size());
  c.system.records.reserve(particles.size());
  for (const auto& row : particles) {
    const std::size_t i = c.system.size();
    if (!row.is_array() || row.size() != columns) {
      fail(fmt::format("the row of particle {} does not hold {} values, found {}", i, columns,
                       shown(row)));
    }
    Particle<D> p;
    ParticleRecord r;
    const auto of = [&](const char* what) { return fmt::format("the {} of particle {}", what, i); };
    for (std::size_t k = 0; k < D; ++k) {
      p.position[k] = f.coordinate(row[k], of("position"));
      p.velocity[k] = f.coordinate(row[D + k], of("velocity"));
    }
    p.time = f.coordinate(row[2 * D], of("stored time"));
    p.radius = f.size(row[2 * D + 1], of("radius"));
    r.mass = f.size(row[2 * D + 2], of("mass"));
    r.wall_collisions = f.count(row[2 * D + 3], of("wall collision count"));
    r.pair_collisions = f.count(row[2 * D + 4], of("pair collision count"));
    // 1.0's TC model read the stored time, which was the last collision's.
    if (format == 1) r.last_collision = p.time;
    if (format != 1 && !row[2 * D + 5].is_null()) {
      r.last_collision = f.coordinate(row[2 * D + 5], of("last collision time"));
    }
    for (std::size_t k = 0; k < D && format >= 3; ++k) {
      r.image[k] = f.image(row[2 * D + 6 + k], of("image flag"));
    }
    if (format >= 6) {
      const std::uint64_t type = f.count(row[3 * D + 6], of("type"));
      if (type >= c.system.type_names.size()) {
        fail(fmt::format("the type {} of particle {} is not one of the {} in \"types\"", type, i,
                         c.system.type_names.size()));
      }
      r.type = static_cast<std::uint32_t>(type);
    }
    c.system.particles.push_back(p);
    c.system.records.push_back(r);
  }
  if (format >= 3) {
    c.system.epoch = f.coordinate(f.at(j, "epoch"), "the epoch");
  } else {
    // Absolute stored times, as older carom ran on: made small as a new run's would be.
    c.system.shift_epoch(c.system.latest_stored());
  }
  if (const auto& t = c.records.transport;
      t && !t->origin.empty() && t->origin.size() != c.system.size() * D) {
    fail(fmt::format("\"origin\" in \"transport\" has {} numbers, not the particles' {}",
                     t->origin.size(), c.system.size() * D));
  }
  // The kinetic stress is the one relative to the streaming profile of the box's shear.
  for (std::optional<Fluxes>* fluxes :
       {&c.counts.fluxes, &c.measurement.counts.fluxes, &c.measurement.flux_origin}) {
    if (*fluxes) (*fluxes)->shear_rate = c.system.box.shear_rate;
  }
  return c;
}

}  // namespace

AnyCheckpoint read_checkpoint(std::istream& in, const std::string& name) {
  nlohmann::json j;
  try {
    j = parse_json(std::string(std::istreambuf_iterator<char>(in), {}));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(name, 0, fmt::format("not a carom checkpoint (not valid json: {})", e.what()));
  }
  const auto fail = [&](const std::string& what) {
    throw InputError(name, 0, "not a usable carom checkpoint: " + what);
  };
  if (!j.is_object() || !j.contains("carom_checkpoint")) fail("no carom_checkpoint field");
  const auto& format = j["carom_checkpoint"];
  if (!format.is_number_integer() || format < 1 || format > kCheckpointFormat) {
    fail(fmt::format("format {} (this carom {} reads formats 1 to {})", shown(format), kVersion,
                     kCheckpointFormat));
  }
  const int version = format.get<int>();
  // New checkpoints carry one; older ones without it are still read (and validated all the same).
  if (const auto checksum = j.find("checksum"); checksum != j.end()) {
    if (!checksum->is_string() || checksum->get<std::string>().rfind("fnv1a64:", 0) != 0) {
      fail(fmt::format("the checksum {} is not one this carom knows (fnv1a64:...)",
                       shown(*checksum)));
    }
    const auto particles = j.find("particles");
    if (particles == j.end() || !particles->is_array()) fail("no list of particles");
    nlohmann::json head = nlohmann::json::object();
    for (const auto& [key, value] : j.items()) {
      if (key != "particles" && key != "checksum") head[key] = value;
    }
    Fnv1a hash;
    add_head(hash, head);
    for (const auto& row : *particles) {
      hash.add(dump_json(row));
      hash.add("\n");
    }
    if (hash.text() != checksum->get<std::string>()) {
      fail(fmt::format(
          "its checksum does not match what it holds ({} recorded, {} computed): the file was "
          "damaged or changed after carom wrote it (remove the \"checksum\" line to resume an "
          "edited checkpoint: it is then checked like any other)",
          checksum->get<std::string>(), hash.text()));
    }
  }
  const auto dimension_of = [&]() -> int {
    if (version == 1) return 2;
    const auto found = j.find("dimension");
    if (found == j.end() || !found->is_number_integer()) {
      fail("no \"dimension\" field (2 or 3)");
    }
    return found->get<int>();
  };
  try {
    const int dimension = dimension_of();
    if (dimension == 2) {
      Checkpoint<2> c = checkpoint_from<2>(j, version, fail);
      if (const auto problem = checkpoint_problem(c, version)) fail(*problem);
      return c;
    }
    if (dimension == 3) {
      Checkpoint<3> c = checkpoint_from<3>(j, version, fail);
      if (const auto problem = checkpoint_problem(c, version)) fail(*problem);
      return c;
    }
    fail(fmt::format("dimension {} (carom simulates 2 and 3)", dimension));
  } catch (const nlohmann::json::exception& e) {
    fail(e.what());
  }
  return {};  // not reached: fail throws
}

}  // namespace carom
