// The one table of names for each enum the user chooses from (rule, boundary, engine, format):
// the command line, json results and checkpoints all spell them from it. Each enum's header
// specialises EnumNames with a `table` of {name, value} pairs, the default first.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace carom {

template <class E>
struct EnumNames;

template <class E>
constexpr std::string_view name_of(E value) {
  for (const auto& [name, v] : EnumNames<E>::table) {
    if (v == value) return name;
  }
  return "unknown";
}

// The value named `name` (exactly, lower case), or nullopt.
template <class E>
constexpr std::optional<E> from_name(std::string_view name) {
  for (const auto& [n, v] : EnumNames<E>::table) {
    if (n == name) return v;
  }
  return std::nullopt;
}

// "a, b or c": the names, for messages.
template <class E>
std::string names_list() {
  std::string list;
  const auto& table = EnumNames<E>::table;
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (i > 0) list += i + 1 == table.size() ? " or " : ", ";
    list += table[i].first;
  }
  return list;
}

}  // namespace carom
