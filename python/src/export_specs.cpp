// carom._carom.RunSpec, StartSpec and InitSpec: the library's requests, made from Python's
// keywords. Each keyword is declared here once, with the field it sets (its key, which names it in
// the library's RequestErrors) and how a Python value becomes the field's; a request's defaults
// are those of a default-made C++ request, and the library checks what it asks.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "carom/core/names.hpp"
#include "specs.hpp"

namespace carom::python {

namespace {

// key -> Python keyword, filled as the keywords are declared.
std::map<std::string, std::string, std::less<>>& keywords_of_keys() {
  static std::map<std::string, std::string, std::less<>> keywords;
  return keywords;
}

bool is_python_bool(py::handle value) {
  return py::isinstance<py::bool_>(value) ||
         py::isinstance(value, py::module_::import("numpy").attr("bool_"));
}

// A finite number (not a bool), as the command line reads numbers.
double number(const std::string& keyword, py::handle value) {
  if (is_python_bool(value) ||
      !py::isinstance(value, py::module_::import("numbers").attr("Real"))) {
    throw py::value_error(
        fmt::format("{} must be a number, got {}", keyword, std::string(py::repr(value))));
  }
  const double x = py::float_(py::reinterpret_borrow<py::object>(value));
  if (!std::isfinite(x)) {
    throw py::value_error(fmt::format("{} must be a finite number, got {}", keyword,
                                      std::string(py::str(py::float_(x)))));
  }
  return x;
}

bool flag(const std::string& keyword, py::handle value) {
  if (!is_python_bool(value)) {
    throw py::value_error(
        fmt::format("{} must be True or False, got {}", keyword, std::string(py::repr(value))));
  }
  return value.cast<bool>();
}

std::uint64_t whole(const std::string& keyword, py::handle value, std::uint64_t least = 0,
                    std::uint64_t most = std::numeric_limits<std::uint64_t>::max()) {
  if (is_python_bool(value) ||
      !py::isinstance(value, py::module_::import("numbers").attr("Integral"))) {
    throw py::value_error(
        fmt::format("{} must be a whole number, got {}", keyword, std::string(py::repr(value))));
  }
  const py::int_ n(py::reinterpret_borrow<py::object>(value));
  if (n < py::int_(least)) {
    throw py::value_error(
        fmt::format("{} must be at least {}, got {}", keyword, least, std::string(py::repr(n))));
  }
  if (n > py::int_(most)) {
    throw py::value_error(
        fmt::format("{} must be at most {}, got {}", keyword, most, std::string(py::repr(n))));
  }
  return n.cast<std::uint64_t>();
}

// A file name (str, bytes or os.PathLike; anything else as its str) as the bytes that name the
// file: a name that is not UTF-8 (os.fsdecode's surrogate escapes) reaches the library as the
// file's own name.
std::string file_name(py::handle value) {
  const py::module_ os = py::module_::import("os");
  const bool named = py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) ||
                     py::isinstance(value, os.attr("PathLike"));
  return os.attr("fsencode")(named ? py::reinterpret_borrow<py::object>(value) : py::str(value))
      .cast<std::string>();
}

// A Python value as a field of type T: None leaves an optional field empty.
template <class T>
struct From;
template <>
struct From<double> {
  static double of(const std::string& k, py::handle v) { return number(k, v); }
};
template <>
struct From<bool> {
  static bool of(const std::string& k, py::handle v) { return flag(k, v); }
};
template <>
struct From<std::uint64_t> {
  static std::uint64_t of(const std::string& k, py::handle v) { return whole(k, v); }
};
template <>
struct From<std::string> {
  static std::string of(const std::string&, py::handle v) { return file_name(v); }
};
template <>
struct From<std::vector<double>> {
  static std::vector<double> of(const std::string& k, py::handle v) {
    std::vector<double> numbers;  // None: none
    if (v.is_none()) return numbers;
    for (const py::handle x : py::iter(v)) numbers.push_back(number(k, x));
    return numbers;
  }
};
template <class T>
struct From<std::optional<T>> {
  static std::optional<T> of(const std::string& k, py::handle v) {
    if (v.is_none()) return std::nullopt;
    return From<T>::of(k, v);
  }
};
template <class T>
requires std::is_enum_v<T>
struct From<T> {
  static T of(const std::string& k, py::handle v) { return choice<T>(k, v); }
};

// A field's value as Python shows it (a default in a signature).
template <class T>
py::object shown(const T& value) {
  if constexpr (std::is_enum_v<T>) {
    return py::str(std::string(name_of(value)));
  } else {
    return py::cast(value);
  }
}
template <class T>
py::object shown(const std::optional<T>& value) {
  return value ? shown(*value) : py::none();
}

// The keywords of a request R: for each, how a value sets it and what a default R holds.
template <class R>
class Keywords {
 public:
  // `keyword` sets the field the member pointers `path` lead to from the request (R::a, A::b,
  // ...); `key` names the field in the library's messages.
  template <class... Path>
  Keywords& field(const std::string& keyword, const std::string& key, Path... path) {
    using T = std::remove_cvref_t<decltype((std::declval<R&>().*....*path))>;
    return custom(
        keyword, key, [=](R& r, py::handle v) { (r.*....*path) = From<T>::of(keyword, v); },
        [=](R& r) { return shown((r.*....*path)); });
  }

  // `keyword` set by `set`, its default shown by `show`.
  Keywords& custom(const std::string& keyword, const std::string& key,
                   std::function<void(R&, py::handle)> set, std::function<py::object(R&)> show) {
    keywords_of_keys().emplace(key, keyword);
    set_[keyword] = std::move(set);
    show_.emplace_back(keyword, std::move(show));
    return *this;
  }

  // A request from `given`, keywords of R's; TypeError names one that is not.
  R make(const py::kwargs& given, const std::string& type) const {
    R request;
    for (const auto& [keyword, value] : given) {
      const std::string name = py::str(keyword);
      const auto set = set_.find(name);
      if (set == set_.end()) {
        throw py::type_error(
            fmt::format("{}() got an unexpected keyword argument '{}'", type, name));
      }
      set->second(request, value);
    }
    return request;
  }

  // {keyword: default}, in the order declared: what a default-made request holds.
  py::dict defaults() const {
    R request;
    py::dict shown_defaults;
    for (const auto& [keyword, show] : show_) shown_defaults[py::str(keyword)] = show(request);
    return shown_defaults;
  }

 private:
  std::map<std::string, std::function<void(R&, py::handle)>> set_;
  std::vector<std::pair<std::string, std::function<py::object(R&)>>> show_;
};

// checkpoint_every: a whole number of events, or seconds as "600s".
std::optional<Trigger> cadence(py::handle value) {
  if (value.is_none()) return std::nullopt;
  if (py::isinstance<py::str>(value)) {
    return checkpoint_cadence(py::str(value.attr("strip")()).cast<std::string>());
  }
  return checkpoint_cadence(std::to_string(whole("checkpoint_every", value, 1)));
}

// RunSpec's keywords are sim.run's.
Keywords<RunSpec> run_keywords() {
  using R = RunSpec;
  Keywords<R> k;
  k.field("t", "end_time", &R::end_time)
      .field("dump", "dump", &R::dump)
      .field("every", "dump_every", &R::dump_every)
      .field("log", "log", &R::log)
      .field("log_every", "log_every", &R::log_every)
      .field("events", "events", &R::events)
      .field("checkpoint", "checkpoint", &R::checkpoint)
      .custom(
          "checkpoint_every", "checkpoint_every",
          [](R& r, py::handle v) { r.checkpoint_every = cadence(v); },
          [](R&) { return py::object(py::none()); })
      .field("summary", "summary", &R::summary)
      .field("final", "final", &R::final_state)
      .field("check", "check", &R::check)
      .custom(
          "check_every", "check_every",
          [](R& r, py::handle v) { r.check_every = whole("check_every", v, 1); },
          [](R& r) { return py::object(py::int_(r.check_every)); })
      .field("equilibrate", "measure_from", &R::measure_from)
      .field("transport", "transport", &R::transport);
  return k;
}

// The thermostat and the shear as asked, before thermostat_request and shear_request make them
// (with the start's temperature and seed).
struct AskedThermostatAndShear {
  ThermostatKind thermostat = Thermostat{}.kind;
  std::optional<double> thermostat_every, thermostat_rate, shear;
  bool velocity_profile = ShearRequest{}.profile;

  Thermostat thermostat_at(std::optional<double> kT, std::uint64_t seed,
                           SamplerKind sampler) const {
    return thermostat_request(thermostat, kT, thermostat_every, thermostat_rate, seed, sampler);
  }
  ShearRequest shear_request() const { return carom::shear_request(shear, velocity_profile); }
};

// The keywords of AskedThermostatAndShear, in a request R that has one as `asked`.
template <class R>
void add_thermostat_and_shear(Keywords<R>& k) {
  using A = AskedThermostatAndShear;
  k.field("thermostat", "thermostat", &R::asked, &A::thermostat)
      .field("thermostat_every", "thermostat_every", &R::asked, &A::thermostat_every)
      .field("thermostat_rate", "thermostat_rate", &R::asked, &A::thermostat_rate)
      .field("shear", "shear", &R::asked, &A::shear)
      .field("velocity_profile", "velocity_profile", &R::asked, &A::velocity_profile);
}

struct StartRequest {
  StartSpec spec;
  AskedThermostatAndShear asked;
};

// StartSpec's keywords are carom.read's.
Keywords<StartRequest> start_keywords() {
  using R = StartRequest;
  using S = StartSpec;
  Keywords<R> k;
  k.field("path", "path", &R::spec, &S::path)
      .field("rule", "rule", &R::spec, &S::rule)
      .field("boundary", "boundary", &R::spec, &S::boundary)
      .field("restitution", "restitution", &R::spec, &S::restitution)
      .field("tc", "tc", &R::spec, &S::tc)
      .field("engine", "engine", &R::spec, &S::engine)
      .field("kT", "temperature", &R::spec, &S::temperature)
      .field("seed", "seed", &R::spec, &S::seed)
      .field("sampler", "sampler", &R::spec, &S::sampler)
      .field("chain_length", "chain_length", &R::spec, &S::chain_length);
  add_thermostat_and_shear(k);
  return k;
}

// carom init's --species: its text, or a list of (name, fraction, diameter) tuples; None: none.
std::vector<Species> species_of(py::handle value) {
  if (value.is_none()) return {};
  std::string text;
  if (py::isinstance<py::str>(value)) {
    text = value.cast<std::string>();
  } else {
    for (const py::handle entry : py::iter(value)) {
      const py::tuple t = py::tuple(py::reinterpret_borrow<py::object>(entry));
      if (t.size() != 3 || !py::isinstance<py::str>(t[0])) {
        throw py::value_error(fmt::format(
            "species must be a text such as \"A:0.5:1.0,B:0.5:1.4\" or a list of (name, "
            "fraction, diameter), got {}",
            std::string(py::repr(value))));
      }
      text += fmt::format("{}{}:{}:{}", text.empty() ? "" : ",", t[0].cast<std::string>(),
                          number("species fraction", t[1]), number("species diameter", t[2]));
    }
  }
  try {
    return parse_species(text);
  } catch (const InitialError& e) {
    throw py::value_error(e.what());
  }
}

struct InitRequest {
  InitSpec spec;
  Settings settings;
  AskedThermostatAndShear asked;
};

// InitSpec's keywords are carom.init's.
Keywords<InitRequest> init_keywords() {
  using R = InitRequest;
  using O = InitialOptions;
  Keywords<R> k;
  k.custom(
       "n", "n", [](R& r, py::handle v) { r.spec.options.n = whole("n", v, 1); },
       [](R&) { return py::object(py::none()); })
      .field("phi", "packing_fraction", &R::spec, &InitSpec::options, &O::packing_fraction)
      .custom(
          "dim", "dimension",
          [](R& r, py::handle v) { r.spec.dimension = static_cast<int>(whole("dim", v, 2, 3)); },
          [](R& r) { return py::object(py::int_(r.spec.dimension)); })
      .field("box", "box", &R::spec, &InitSpec::options, &O::box)
      .field("aspect", "aspect", &R::spec, &InitSpec::options, &O::aspect)
      .field("radius", "radius", &R::spec, &InitSpec::options, &O::radius)
      .field("polydispersity", "polydispersity", &R::spec, &InitSpec::options, &O::polydispersity)
      .custom(
          "species", "species", [](R& r, py::handle v) { r.spec.options.species = species_of(v); },
          [](R& r) {
            const auto& species = r.spec.options.species;
            return species.empty() ? py::object(py::none()) : py::str(species_text(species));
          })
      .field("kT", "temperature", &R::spec, &InitSpec::options, &O::temperature)
      .field("seed", "seed", &R::spec, &InitSpec::options, &O::seed)
      .field("boundary", "boundary", &R::spec, &InitSpec::options, &O::boundary)
      .field("placement", "placement", &R::spec, &InitSpec::options, &O::placement)
      .field("rule", "rule", &R::spec, &InitSpec::rule)
      .field("restitution", "restitution", &R::settings, &Settings::rule,
             &CollisionRule::restitution)
      .field("tc", "tc", &R::settings, &Settings::rule, &CollisionRule::elastic_within)
      .field("engine", "engine", &R::settings, &Settings::engine)
      .field("sampler", "sampler", &R::settings, &Settings::sampler, &Sampler::kind)
      .field("chain_length", "chain_length", &R::settings, &Settings::sampler,
             &Sampler::chain_length);
  add_thermostat_and_shear(k);
  return k;
}

// A class for the request R, made from its keywords by `finish`; its keywords() are the
// keywords with their defaults.
template <class Bound, class R, class Finish>
void bind_request(py::module_& m, const char* name, Keywords<R> keywords, Finish finish) {
  const auto shared = std::make_shared<Keywords<R>>(std::move(keywords));
  py::class_<Bound>(m, name)
      .def(py::init([shared, name, finish](const py::kwargs& given) {
        return finish(shared->make(given, name));
      }))
      .def_static("keywords", [shared] { return shared->defaults(); });
}

}  // namespace

std::string python_keyword(std::string_view key, std::string_view value) {
  const auto& keywords = keywords_of_keys();
  const auto found = keywords.find(key);
  const std::string keyword = found != keywords.end() ? found->second : std::string(key);
  return value.empty() ? keyword + "=" : fmt::format("{}=\"{}\"", keyword, value);
}

void export_specs(py::module_& m) {
  bind_request<RunSpec>(m, "RunSpec", run_keywords(), [](RunSpec spec) { return spec; });
  bind_request<StartSpec>(m, "StartSpec", start_keywords(), [](StartRequest r) {
    r.spec.thermostat = r.asked.thermostat_at(r.spec.temperature, r.spec.seed, r.spec.sampler);
    r.spec.shear = r.asked.shear_request();
    return r.spec;
  });
  bind_request<InitStart>(m, "InitSpec", init_keywords(), [](InitRequest r) {
    r.settings.rule.rule = r.spec.rule;
    r.settings.thermostat = r.asked.thermostat_at(r.spec.options.temperature, r.spec.options.seed,
                                                  r.settings.sampler.kind);
    r.settings.sampler.seed = r.spec.options.seed;  // the chains' particles too
    return InitStart{r.spec, r.settings, r.asked.shear_request()};
  });
}

}  // namespace carom::python
