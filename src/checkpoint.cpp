#include "carom/checkpoint.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "carom/atomic_file.hpp"
#include "carom/classic_input.hpp"
#include "carom/version.hpp"

namespace carom {

namespace {

using Json = nlohmann::ordered_json;

Json counts_json(const Counts& c) {
  return {{"events", c.events},
          {"pair_collisions", c.pair_collisions},
          {"wall_collisions", c.wall_collisions},
          {"elastic_by_tc", c.elastic_by_tc},
          {"virial", c.virial},
          {"wall_momentum", c.wall_momentum}};
}

Counts counts_from(const nlohmann::json& j) {
  Counts c;
  c.events = j.at("events").get<std::uint64_t>();
  c.pair_collisions = j.at("pair_collisions").get<std::uint64_t>();
  c.wall_collisions = j.at("wall_collisions").get<std::uint64_t>();
  c.elastic_by_tc = j.at("elastic_by_tc").get<std::uint64_t>();
  c.virial = j.at("virial").get<double>();
  c.wall_momentum = j.at("wall_momentum").get<double>();
  return c;
}

// A time that may be "never" (json null).
Json time_or_null(double t) {
  return std::isfinite(t) ? Json(t) : Json(nullptr);
}

template <class E>
E enum_from(const nlohmann::json& j, const char* key, const auto& fail) {
  const std::string name = j.at(key).get<std::string>();
  const std::optional<E> value = from_name<E>(name);
  if (!value) fail(fmt::format("unknown {} '{}' (expected {})", key, name, names_list<E>()));
  return *value;
}

// The checkpoint of one dimension; `format` 1 is carom 1.0's (2D, counts only since the window
// opened, the TC model reading stored times).
template <std::size_t D>
Checkpoint<D> checkpoint_from(const nlohmann::json& j, int format, const auto& fail) {
  Checkpoint<D> c;
  c.source = j.at(format == 1 ? "input" : "source").get<std::string>();
  for (std::size_t k = 0; k < D; ++k) c.system.box.size[k] = j.at("box").at(k).get<double>();
  if (j.at("box").size() != D) fail(fmt::format("the box does not have {} sides", D));
  c.system.box.boundary = enum_from<Boundary>(j, "boundary", fail);
  c.settings.rule.rule = enum_from<Rule>(j, "rule", fail);
  c.settings.rule.restitution = j.at("restitution").get<double>();
  c.settings.rule.elastic_within = j.at("tc").get<double>();
  c.settings.engine = enum_from<EngineKind>(j, "engine", fail);
  c.time = j.at("time").get<double>();
  if (format == 1) {
    // 1.0 saved at its last event and counted only the measurement window.
    c.counts = counts_from(j);
    c.measurement = {j.at("equilibrate").get<double>(),
                     j.at("kinetic_energy_initial").get<double>(), c.counts};
    if (c.measurement.start_time > c.time) {
      c.measure_from = c.measurement.start_time;
      c.measurement.start_time = 0.0;
    }
  } else {
    c.settled = j.at("settled").get<bool>();
    c.counts = counts_from(j.at("counts"));
    const auto& m = j.at("measurement");
    c.measurement = {m.at("start_time").get<double>(), m.at("kinetic_energy_initial").get<double>(),
                     counts_from(m.at("counts"))};
    if (!j.at("measure_from").is_null()) c.measure_from = j.at("measure_from").get<double>();
  }
  const std::size_t columns = format == 1 ? 2 * D + 5 : 2 * D + 6;
  for (const auto& row : j.at("particles")) {
    if (row.size() != columns) {
      fail(fmt::format("a particle row does not hold {} numbers", columns));
    }
    Particle<D> p;
    ParticleRecord r;
    for (std::size_t k = 0; k < D; ++k) {
      p.position[k] = row[k].get<double>();
      p.velocity[k] = row[D + k].get<double>();
    }
    p.time = row[2 * D].get<double>();
    p.radius = row[2 * D + 1].get<double>();
    r.mass = row[2 * D + 2].get<double>();
    r.wall_collisions = row[2 * D + 3].get<std::uint64_t>();
    r.pair_collisions = row[2 * D + 4].get<std::uint64_t>();
    // 1.0's TC model read the stored time, which was the last collision's.
    if (format == 1) r.last_collision = p.time;
    if (format != 1 && !row[2 * D + 5].is_null()) r.last_collision = row[2 * D + 5].get<double>();
    bool finite = std::isfinite(p.time);
    for (std::size_t k = 0; k < D; ++k) {
      finite = finite && std::isfinite(p.position[k]) && std::isfinite(p.velocity[k]);
    }
    if (!(finite && p.radius > 0.0 && std::isfinite(p.radius) && r.mass > 0.0 &&
          std::isfinite(r.mass) && p.time <= c.time && !(r.last_collision > c.time))) {
      fail(fmt::format("particle {} is corrupt", c.system.size()));
    }
    c.system.particles.push_back(p);
    c.system.records.push_back(r);
  }
  if (c.system.particles.empty()) fail("no particles");
  for (std::size_t k = 0; k < D; ++k) {
    if (!(c.system.box.size[k] > 0.0 && std::isfinite(c.system.box.size[k]))) {
      fail("the box is not positive");
    }
  }
  const CollisionRule& rule = c.settings.rule;
  if (!(rule.restitution > 0.0 && rule.restitution <= 1.0 && rule.elastic_within >= 0.0)) {
    fail("the restitution or tc is out of range");
  }
  if (!(std::isfinite(c.time) && c.measurement.start_time <= c.time)) fail("the time is corrupt");
  return c;
}

}  // namespace

template <std::size_t D>
void write_checkpoint(std::ostream& out, const Checkpoint<D>& c) {
  Json box = Json::array();
  for (std::size_t k = 0; k < D; ++k) box.push_back(c.system.box.size[k]);
  const Json head = {
      {"carom_checkpoint", kCheckpointFormat},
      {"carom_version", kVersion},
      {"source", c.source},
      {"dimension", D},
      {"box", box},
      {"boundary", name_of(c.system.box.boundary)},
      {"rule", name_of(c.settings.rule.rule)},
      {"restitution", c.settings.rule.restitution},
      {"tc", c.settings.rule.elastic_within},
      {"engine", name_of(c.settings.engine)},
      {"time", c.time},
      {"settled", c.settled},
      {"counts", counts_json(c.counts)},
      {"measurement",
       {{"start_time", c.measurement.start_time},
        {"kinetic_energy_initial", c.measurement.kinetic_energy_initial},
        {"counts", counts_json(c.measurement.counts)}}},
      {"measure_from", c.measure_from ? Json(*c.measure_from) : Json(nullptr)},
  };
  std::string text = head.dump(1);
  text.resize(text.size() - 2);  // reopen the object
  out << text << ",\n \"particles\": [";
  // One line a particle: position, velocity, time, radius, mass, wall and pair collisions, last
  // collision (null: none yet).
  for (std::size_t i = 0; i < c.system.size(); ++i) {
    const Particle<D>& p = c.system.particles[i];
    const ParticleRecord& r = c.system.records[i];
    Json row = Json::array();
    for (std::size_t k = 0; k < D; ++k) row.push_back(p.position[k]);
    for (std::size_t k = 0; k < D; ++k) row.push_back(p.velocity[k]);
    row.insert(row.end(), {Json(p.time), Json(p.radius), Json(r.mass), Json(r.wall_collisions),
                           Json(r.pair_collisions), time_or_null(r.last_collision)});
    out << (i == 0 ? "\n  " : ",\n  ") << row.dump();
  }
  out << "\n ]\n}\n";
}

AnyCheckpoint read_checkpoint(std::istream& in, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(name, 0, fmt::format("not a carom checkpoint (not valid json: {})", e.what()));
  }
  const auto fail = [&](const std::string& what) {
    throw InputError(name, 0, "not a usable carom checkpoint: " + what);
  };
  if (!j.is_object() || !j.contains("carom_checkpoint")) fail("no carom_checkpoint field");
  const auto& format = j["carom_checkpoint"];
  if (format != 1 && format != kCheckpointFormat) {
    fail(fmt::format("format {} (this carom {} reads formats 1 and {})", format.dump(), kVersion,
                     kCheckpointFormat));
  }
  try {
    const int version = format.get<int>();
    const int dimension = version == 1 ? 2 : j.at("dimension").get<int>();
    if (dimension == 2) return checkpoint_from<2>(j, version, fail);
    if (dimension == 3) return checkpoint_from<3>(j, version, fail);
    fail(fmt::format("dimension {} (carom simulates 2 and 3)", dimension));
  } catch (const nlohmann::json::exception& e) {
    fail(e.what());
  }
  return {};  // not reached: fail throws
}

template <std::size_t D>
void save_checkpoint(const std::string& path, const Simulation<D>& simulation,
                     const std::string& source) {
  AtomicFile file(path);
  write_checkpoint(file.stream(), simulation.checkpoint(source));
  file.commit();
}

template void write_checkpoint(std::ostream&, const Checkpoint<2>&);
template void write_checkpoint(std::ostream&, const Checkpoint<3>&);
template void save_checkpoint(const std::string&, const Simulation<2>&, const std::string&);
template void save_checkpoint(const std::string&, const Simulation<3>&, const std::string&);

}  // namespace carom
