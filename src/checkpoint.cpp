#include "carom/checkpoint.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "carom/classic_input.hpp"
#include "carom/overlap.hpp"
#include "carom/version.hpp"

namespace carom {

void write_checkpoint(std::ostream& out, const Checkpoint& c) {
  nlohmann::ordered_json head = {
      {"carom_checkpoint", kCheckpointFormat},
      {"carom_version", kVersion},
      {"input", c.input},
      {"box", {c.system.box.size[0], c.system.box.size[1]}},
      {"boundary", boundary_name(c.system.box.boundary)},
      {"rule", rule_name(c.rule.rule)},
      {"restitution", c.rule.restitution},
      {"tc", c.rule.elastic_within},
      {"engine", engine_name(c.engine)},
      {"time", c.time},
      {"events", c.counts.events},
      {"pair_collisions", c.counts.pair_collisions},
      {"wall_collisions", c.counts.wall_collisions},
      {"elastic_by_tc", c.counts.elastic_by_tc},
      {"virial", c.counts.virial},
      {"wall_momentum", c.counts.wall_momentum},
      {"equilibrate", c.equilibrate},
      {"kinetic_energy_initial", c.kinetic_energy_initial},
  };
  std::string text = head.dump(1);
  text.resize(text.size() - 2);  // reopen the object
  out << text << ",\n \"particles\": [";
  // One line a particle: x y vx vy time radius mass wall_collisions pair_collisions.
  for (std::size_t i = 0; i < c.system.particles.size(); ++i) {
    const Particle<2>& p = c.system.particles[i];
    const nlohmann::json row = {p.position[0],    p.position[1], p.velocity[0], p.velocity[1],
                                p.time,           p.radius,      p.mass,        p.wall_collisions,
                                p.pair_collisions};
    out << (i == 0 ? "\n  " : ",\n  ") << row.dump();
  }
  out << "\n ]\n}\n";
}

Checkpoint read_checkpoint(std::istream& in, const std::string& name) {
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
  if (j["carom_checkpoint"] != kCheckpointFormat) {
    fail(fmt::format("format {} (this carom {} reads format {})", j["carom_checkpoint"].dump(),
                     kVersion, kCheckpointFormat));
  }
  Checkpoint c;
  try {
    c.input = j.at("input").get<std::string>();
    c.system.box.size = {j.at("box").at(0).get<double>(), j.at("box").at(1).get<double>()};
    const std::string boundary = j.at("boundary").get<std::string>();
    if (boundary != "walls" && boundary != "periodic") fail("unknown boundary " + boundary);
    c.system.box.boundary = boundary == "walls" ? Boundary::walls : Boundary::periodic;
    const std::string rule = j.at("rule").get<std::string>();
    if (rule != "swap" && rule != "elastic") fail("unknown rule " + rule);
    c.rule.rule = rule == "swap" ? Rule::swap : Rule::elastic;
    c.rule.restitution = j.at("restitution").get<double>();
    c.rule.elastic_within = j.at("tc").get<double>();
    const std::string engine = j.at("engine").get<std::string>();
    if (engine != "fast" && engine != "reference") fail("unknown engine " + engine);
    c.engine = engine == "fast" ? EngineKind::fast : EngineKind::reference;
    c.time = j.at("time").get<double>();
    c.counts.events = j.at("events").get<std::uint64_t>();
    c.counts.pair_collisions = j.at("pair_collisions").get<std::uint64_t>();
    c.counts.wall_collisions = j.at("wall_collisions").get<std::uint64_t>();
    c.counts.elastic_by_tc = j.at("elastic_by_tc").get<std::uint64_t>();
    c.counts.virial = j.at("virial").get<double>();
    c.counts.wall_momentum = j.at("wall_momentum").get<double>();
    c.equilibrate = j.at("equilibrate").get<double>();
    c.kinetic_energy_initial = j.at("kinetic_energy_initial").get<double>();
    for (const auto& row : j.at("particles")) {
      if (row.size() != 9) fail("a particle row does not hold 9 numbers");
      Particle<2> p;
      p.position = {row[0].get<double>(), row[1].get<double>()};
      p.velocity = {row[2].get<double>(), row[3].get<double>()};
      p.time = row[4].get<double>();
      p.radius = row[5].get<double>();
      p.mass = row[6].get<double>();
      p.wall_collisions = row[7].get<std::uint64_t>();
      p.pair_collisions = row[8].get<std::uint64_t>();
      if (!(p.radius > 0.0 && p.mass > 0.0 && p.time <= c.time)) fail("a particle is corrupt");
      c.system.particles.push_back(p);
    }
  } catch (const nlohmann::json::exception& e) {
    fail(e.what());
  }
  if (c.system.particles.empty()) fail("no particles");
  if (!(c.system.box.size[0] > 0.0 && c.system.box.size[1] > 0.0)) fail("the box is not positive");
  return c;
}

}  // namespace carom
