// Reading a json document field by field, checked: every reader names the field and says what
// is wrong through `fail` (which throws: an InputError naming the file, say), so a reader of a
// json format is a list of the fields it takes.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "carom/core/names.hpp"
#include "carom/engine/validation.hpp"
#include "json_text.hpp"

namespace carom {

// A json value as a message may show it: short.
inline std::string shown(const nlohmann::json& value) {
  std::string text = dump_json(value);
  if (text.size() > 40) text = text.substr(0, 40) + "...";
  return text;
}

template <class Fail>
class CheckedJson {
 public:
  explicit CheckedJson(const Fail& fail) : fail_(fail) {}

  const nlohmann::json& at(const nlohmann::json& object, const char* key,
                           const std::string& where = "") const {
    if (!object.is_object()) fail_(fmt::format("{} is not a json object", where));
    const auto found = object.find(key);
    if (found == object.end()) {
      fail_(fmt::format("no \"{}\" field{}", key, where.empty() ? "" : " in " + where));
    }
    return *found;
  }
  double number(const nlohmann::json& value, const std::string& what) const {
    if (!value.is_number()) fail_(fmt::format("{} must be a number, found {}", what, shown(value)));
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail_(fmt::format("{} is not a finite number: {}", what, shown(value)));
    return x;
  }
  // A position, speed or time: finite, and not so large that its square overflows.
  double coordinate(const nlohmann::json& value, const std::string& what) const {
    const double x = number(value, what);
    if (std::abs(x) > kLargestCoordinate) {
      fail_(fmt::format("{} is out of range: {} (carom takes magnitudes up to {})", what, x,
                        kLargestCoordinate));
    }
    return x;
  }
  // A box side, radius or mass, checked as the classic reader checks them.
  double size(const nlohmann::json& value, const std::string& what) const {
    const double x = number(value, what);
    try {
      check_number(x, what);
    } catch (const std::invalid_argument& e) {
      fail_(e.what());
    }
    if (!(x > 0.0)) fail_(fmt::format("{} must be greater than 0, found {}", what, x));
    return x;
  }
  std::uint64_t count(const nlohmann::json& value, const std::string& what) const {
    if (!value.is_number_unsigned()) {
      fail_(fmt::format("{} must be a whole number from 0 to {}, found {}", what,
                        std::numeric_limits<std::uint64_t>::max(), shown(value)));
    }
    return value.get<std::uint64_t>();
  }
  std::int32_t image(const nlohmann::json& value, const std::string& what) const {
    constexpr auto kLow = std::numeric_limits<std::int32_t>::min();
    constexpr auto kHigh = std::numeric_limits<std::int32_t>::max();
    if (!value.is_number_integer() || value.get<std::int64_t>() < kLow ||
        value.get<std::int64_t>() > kHigh ||
        (value.is_number_unsigned() && value.get<std::uint64_t>() > std::uint64_t{kHigh})) {
      fail_(fmt::format("{} must be a whole number from {} to {}, found {}", what, kLow, kHigh,
                        shown(value)));
    }
    return static_cast<std::int32_t>(value.get<std::int64_t>());
  }
  std::string text(const nlohmann::json& value, const std::string& what) const {
    if (!value.is_string()) fail_(fmt::format("{} must be a string, found {}", what, shown(value)));
    return value.get<std::string>();
  }
  bool flag(const nlohmann::json& value, const std::string& what) const {
    if (!value.is_boolean())
      fail_(fmt::format("{} must be true or false, found {}", what, shown(value)));
    return value.get<bool>();
  }
  template <class E>
  E choice(const nlohmann::json& object, const char* key) const {
    const std::string name = text(at(object, key), fmt::format("\"{}\"", key));
    const std::optional<E> value = from_name<E>(name);
    if (!value) fail_(fmt::format("unknown {} '{}' (expected {})", key, name, names_list<E>()));
    return *value;
  }

 protected:
  // Positions and speeds beyond this overflow when squared in predictions (the classic reader's
  // bound; tiny magnitudes, which an inelastic run may reach, are allowed).
  static constexpr double kLargestCoordinate = 1e100;
  const Fail& fail_;
};

}  // namespace carom
