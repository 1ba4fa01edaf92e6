#include "carom/run/start.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <fstream>

#include "carom/core/observables.hpp"
#include "carom/engine/validation.hpp"
#include "carom/io/checkpoint.hpp"
#include "carom/io/gsd.hpp"
#include "carom/io/trajectory_kind.hpp"
#include "carom/run/request.hpp"

namespace carom {

namespace {

// Says which of the run's boundary and rule were not asked for and are not the classic
// assignment's (walls, swap), and where they came from: the file's record, or the physical rule
// of a periodic box; or, for a plain classic file, that it runs as the classic assignment's.
// Nothing when the run was asked for whole.
std::string describe_defaults(const StartSpec& spec, const StartRecord& record, Boundary boundary,
                              Rule rule) {
  const bool periodic = !spec.boundary && boundary == Boundary::periodic;
  // Event chains have no rule to note.
  const bool elastic = !spec.rule && rule == Rule::elastic && spec.restitution == 1.0 &&
                       spec.sampler == SamplerKind::md;
  // A plain classic file, run as the classic assignment runs it: said once, since a fluid's
  // study would want neither walls nor the swap rule.
  if (!record.boundary && !record.rule && !spec.boundary && !spec.rule &&
      boundary == Boundary::walls && rule == Rule::swap) {
    return fmt::format(
        "{} records no box or rule (a plain classic file): run between walls with the swap "
        "rule, as the classic assignment does (--boundary periodic --rule elastic for a bulk "
        "fluid)",
        spec.path);
  }
  if (!periodic && !elastic) return "";
  const std::string taken = periodic && elastic ? "periodic boundary and elastic rule"
                            : periodic          ? "periodic boundary"
                                                : "elastic rule";
  if (record.boundary || record.rule) {
    return fmt::format("{}, as {} records ({} choose{} otherwise)", taken, spec.path,
                       periodic && elastic ? "--boundary and --rule"
                       : periodic          ? "--boundary"
                                           : "--rule",
                       periodic && elastic ? "" : "s");
  }
  return "elastic rule, the physical one in a periodic box (--rule swap is the classic "
         "assignment's)";
}

template <std::size_t D>
System<D> system_from(const ParticleArrays& a) {
  System<D> system;
  system.box.boundary = a.boundary;
  system.type_names = a.type_names;
  for (std::size_t k = 0; k < D; ++k) system.box.size[k] = a.box[k];
  system.particles.reserve(a.n);
  system.records.reserve(a.n);
  for (std::size_t i = 0; i < a.n; ++i) {
    Particle<D> particle;
    for (std::size_t k = 0; k < D; ++k) {
      particle.position[k] = a.positions[i * D + k];
      particle.velocity[k] = a.velocities[i * D + k];
    }
    particle.radius = a.radii[i];
    system.add(particle, a.masses[i]);
    if (a.types) system.records.back().type = a.types[i];
  }
  check_start(system);
  return system;
}

}  // namespace

void require_dimension(std::int64_t dimension) {
  if (dimension != 2 && dimension != 3) {
    throw RequestError(fmt::format("dim must be 2 (disks) or 3 (spheres), got {}", dimension));
  }
}

namespace {

// `text` in lower case (ASCII).
std::string lowered(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// A start spec's GSD frame, FILE.gsd:K (the ending in any case): the file, and K's text as
// written (checked by the reader); nullopt for a spec without one.
std::optional<std::pair<std::string, std::string>> gsd_frame_of(const std::string& spec) {
  const std::size_t colon = lowered(spec).rfind(".gsd:");
  if (colon == std::string::npos) return std::nullopt;
  return std::pair{spec.substr(0, colon + 4), spec.substr(colon + 5)};
}

bool is_gsd_file(const std::string& path) {
  return trajectory_kind_of(path) == TrajectoryKind::gsd;
}

}  // namespace

std::string start_file_path(const std::string& spec) {
  if (is_gsd_file(spec)) return spec;
  const auto frame = gsd_frame_of(spec);
  return frame ? frame->first : spec;
}

AnyClassicInput read_any_start_file(const std::string& spec, std::optional<Boundary> boundary) {
  // A GSD frame's box is what it is: a boundary asked for must be that one.
  const auto boxed = [&](AnyClassicInput input) {
    const Boundary held = std::visit([](const auto& in) { return in.system.box.boundary; }, input);
    if (boundary && *boundary != held) {
      throw InputError(spec, 0,
                       fmt::format("its box is {}: the boundary cannot be {}", name_of(held),
                                   name_of(*boundary)));
    }
    return input;
  };
  if (is_gsd_file(spec)) return boxed(read_gsd_start(spec, std::nullopt));
  if (const auto frame = gsd_frame_of(spec)) {
    const std::string& number = frame->second;
    if (!number.empty() && number.size() <= 18 &&
        std::all_of(number.begin(), number.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return boxed(read_gsd_start(frame->first, std::stoull(number)));
    }
    throw InputError(spec, 0,
                     fmt::format("'{}' is not a frame number (FILE.gsd:K, K from 0)", number));
  }
  return read_any_classic_file(spec, boundary);
}

AnySystem read_start_system(const std::string& spec, std::optional<Boundary> boundary) {
  return std::visit([](auto&& input) { return AnySystem(std::move(input.system)); },
                    read_any_start_file(spec, boundary));
}

namespace {

// check_number's verdict on the value of the option `key`, naming the option.
void check_option_number(double value, const std::string& key) {
  try {
    check_number(value, "");
  } catch (const std::invalid_argument& e) {
    throw RequestError({option(key), e.what()});
  }
}

// An option event chains cannot take: refused by name, with why.
[[noreturn]] void refuse_for_chains(MessagePiece what, const std::string& why) {
  throw RequestError({std::move(what), " needs dynamics (", option("sampler", "md"),
                      "): ", option("sampler", "ecmc"), " ", why});
}

// A thermostat asked of event chains (which have no velocities to hold), whatever else the
// request lacks.
[[noreturn]] void refuse_thermostat_for_chains() {
  refuse_for_chains(option("thermostat"), "samples at kT = 1 and has no velocities to hold");
}

}  // namespace

Thermostat thermostat_request(ThermostatKind kind, std::optional<double> kT,
                              std::optional<double> every, std::optional<double> rate,
                              std::uint64_t seed, SamplerKind sampler) {
  // Refused for what it is before what it lacks: with chains no --kT would make it work.
  if (kind != ThermostatKind::none && sampler == SamplerKind::ecmc) refuse_thermostat_for_chains();
  if (kind == ThermostatKind::none) {
    if (every || rate) {
      throw RequestError({option("thermostat_every"), " and ", option("thermostat_rate"), " need ",
                          option("thermostat"), " KIND"});
    }
    return {};
  }
  if (!kT) {
    throw RequestError(
        {option("thermostat"), " needs ", option("temperature"), " T: the temperature to hold"});
  }
  if (kind == ThermostatKind::andersen && !rate) {
    throw RequestError({option("thermostat", "andersen"), " needs ", option("thermostat_rate"),
                        " NU: resets per particle per unit time"});
  }
  // Andersen's without an interval resets one particle at a time, as events.
  if (!every && kind != ThermostatKind::andersen) {
    throw RequestError(
        {option("thermostat"), " needs ", option("thermostat_every"), " DT: how often it acts"});
  }
  if (kind != ThermostatKind::andersen && rate) {
    throw RequestError(
        {option("thermostat_rate"), " is Andersen's: ", option("thermostat", "andersen")});
  }
  const Thermostat thermostat{kind, *kT, every.value_or(0.0), rate.value_or(0.0), seed};
  // The magnitudes the command line reads, from every front end.
  check_option_number(*kT, "temperature");
  if (every) check_option_number(*every, "thermostat_every");
  if (rate) check_option_number(*rate, "thermostat_rate");
  try {
    check_thermostat(thermostat);
  } catch (const std::invalid_argument& e) {
    throw RequestError(e.what());
  }
  return thermostat;
}

ShearRequest shear_request(std::optional<double> rate, bool profile) {
  if (!rate) {
    if (profile) {
      throw RequestError(
          {option("velocity_profile"), " needs ", option("shear"), " RATE: the profile's slope"});
    }
    return {};
  }
  check_option_number(*rate, "shear");  // what the command line reads, from every front end
  if (*rate == 0.0 && profile) {
    throw RequestError({option("velocity_profile"), " needs a shear rate other than 0"});
  }
  return {*rate, profile};
}

void check_shear_box(const ShearRequest& shear, bool periodic, Rule rule) {
  if (shear.rate == 0.0) return;
  if (!periodic) {
    throw RequestError({option("shear"), " needs a periodic box (", option("boundary", "periodic"),
                        "): walls cannot slide past each other"});
  }
  if (rule != Rule::elastic) {
    throw RequestError({option("shear"), " needs ", option("rule", "elastic"),
                        ": the swap rule carries no stress"});
  }
}

namespace {

// Shears the start's box as asked (nothing for rate 0). RequestError for a box with walls or a
// rule that is not elastic; the profile goes on top of the velocities drawn or read.
template <std::size_t D>
void apply_shear(System<D>& system, const ShearRequest& shear, Rule rule) {
  check_shear_box(shear, system.box.periodic(), rule);
  if (shear.rate == 0.0) return;
  system.box.shear_rate = shear.rate;
  system.box.shear_offset = 0.0;
  if (!shear.profile) return;
  for (Particle<D>& p : system.particles)
    p.velocity = streaming_velocity(p.velocity, p, system.box);
}

}  // namespace

void check_sampler_request(const Settings& settings, bool periodic, const ShearRequest& shear,
                           bool rule_named, bool draws_velocities) {
  if (settings.sampler.kind != SamplerKind::ecmc) {
    if (settings.sampler.chain_length != 0.0) {
      throw RequestError({option("chain_length"), " needs ", option("sampler", "ecmc"),
                          ": dynamics has no chains"});
    }
    return;
  }
  if (!periodic) {
    throw RequestError({option("sampler", "ecmc"), " needs a periodic box (",
                        option("boundary", "periodic"), "): its chains have no walls to meet"});
  }
  if (shear.rate != 0.0) refuse_for_chains(option("shear"), "samples equilibrium, not a flow");
  if (settings.thermostat.kind != ThermostatKind::none) refuse_thermostat_for_chains();
  if (settings.rule.restitution != 1.0) {
    refuse_for_chains(option("restitution"), "samples hard particles");
  }
  if (settings.rule.elastic_within != kDefaultTc) {
    refuse_for_chains(option("tc"), "has no inelastic collisions for it to make elastic");
  }
  if (rule_named) {
    refuse_for_chains(option("rule"), "moves no two particles at once, under any rule");
  }
  if (settings.engine == EngineKind::reference) {
    refuse_for_chains(option("engine", "reference"), "has its own engine");
  }
  if (draws_velocities) refuse_for_chains(option("temperature"), "samples positions, at kT = 1");
  const double length = settings.sampler.chain_length;
  if (!(length >= 0.0) || !std::isfinite(length)) {
    throw RequestError({option("chain_length"), " must be a number above 0 (0: the default)"});
  }
  if (!within_magnitudes(length)) {
    throw RequestError({option("chain_length"),
                        fmt::format(" is out of range: carom takes magnitudes from {} to {}",
                                    kSmallestMagnitude, kLargestMagnitude)});
  }
}

namespace {

// check_chain_start's refusal as a request's, naming `source` (the start file) when there is one.
void check_chain_request(const Settings& settings, const AnySystem& system,
                         const std::string& source) {
  if (settings.sampler.kind != SamplerKind::ecmc) return;
  try {
    std::visit([](const auto& s) { check_chain_start(s); }, system);
  } catch (const std::invalid_argument& e) {
    throw RequestError(source.empty() ? std::string(e.what())
                                      : fmt::format("{}: {}", source, e.what()));
  }
}

}  // namespace

Start load_start(const StartSpec& spec) {
  return std::visit(
      [&](auto&& input) {
        const Boundary boundary = input.system.box.boundary;
        const Rule rule =
            spec.rule.value_or(default_rule(input.record, boundary, spec.restitution));
        const Settings settings{{rule, spec.restitution, spec.tc},
                                spec.engine,
                                spec.thermostat,
                                {spec.sampler, spec.chain_length, spec.seed}};
        check_sampler_request(settings, boundary == Boundary::periodic, spec.shear,
                              spec.rule.has_value(), spec.temperature.has_value());
        std::string note = describe_defaults(spec, input.record, boundary, rule);
        std::optional<std::uint64_t> seed;
        if (spec.temperature) {
          try {
            draw_velocities(input.system, *spec.temperature, spec.seed);
          } catch (const std::invalid_argument& e) {
            throw RequestError({option("temperature"), fmt::format(": {}", e.what())});
          }
          seed = spec.seed;
        } else if (kinetic_energy(input.system) == 0.0 && !spec.shear.profile &&
                   spec.sampler == SamplerKind::md) {
          note += std::string(note.empty() ? "" : "; ") +
                  "every particle is at rest (kT = 0), so nothing will happen: --kT T draws "
                  "Maxwell-Boltzmann velocities";
        }
        apply_shear(input.system, spec.shear, rule);
        // Only for the reader's messages: not held while the engine is made (a move frees it;
        // `= {}` would keep its capacity).
        input.line_of = std::vector<std::size_t>();
        AnySystem system(std::move(input.system));
        check_chain_request(settings, system, spec.path);
        return Start{AnySimulation(std::move(system), settings),
                     spec.path,
                     spec.path,
                     false,
                     std::move(note),
                     seed,
                     WindowRecords{}};
      },
      read_any_start_file(spec.path, spec.boundary));
}

Start resume_start(const std::string& path) {
  std::ifstream file = open_input(path);
  return std::visit(
      [&](const auto& checkpoint) {
        return Start{AnySimulation(checkpoint), path, checkpoint.source, true, "", checkpoint.seed,
                     checkpoint.records};
      },
      read_checkpoint(file, path));
}

Start init_start(int dimension, const InitialOptions& options, const Settings& settings,
                 const ShearRequest& shear) {
  require_dimension(dimension);
  check_settings(settings);
  // carom.init's rule and kT have defaults (elastic, 1): others were asked for.
  check_sampler_request(settings, options.boundary == Boundary::periodic, shear,
                        settings.rule.rule != Rule::elastic, options.temperature != 1.0);
  AnySystem system =
      dimension == 2 ? AnySystem(make_initial<2>(options)) : AnySystem(make_initial<3>(options));
  std::visit([&](auto& s) { apply_shear(s, shear, settings.rule.rule); }, system);
  check_chain_request(settings, system, "");
  return Start{AnySimulation(std::move(system), settings),
               "",
               "(carom.init)",
               false,
               "",
               std::nullopt,
               WindowRecords{}};
}

Start arrays_start(const ParticleArrays& arrays, const Settings& settings,
                   const ShearRequest& shear) {
  require_dimension(arrays.dimension);
  check_sampler_request(settings, arrays.boundary == Boundary::periodic, shear,
                        settings.rule.rule != Rule::elastic, false);
  AnySystem system =
      arrays.dimension == 2 ? AnySystem(system_from<2>(arrays)) : AnySystem(system_from<3>(arrays));
  std::visit([&](auto& s) { apply_shear(s, shear, settings.rule.rule); }, system);
  check_chain_request(settings, system, "");
  return Start{AnySimulation(std::move(system), settings),
               "",
               "(arrays)",
               false,
               "",
               std::nullopt,
               WindowRecords{}};
}

}  // namespace carom
