// The requests Python makes of the library (export_specs.cpp binds them): RunSpec, StartSpec,
// and InitStart, carom.init's.
#pragma once

#include <fmt/format.h>
#include <pybind11/pybind11.h>

#include <string>
#include <string_view>

#include "carom/core/names.hpp"
#include "carom/run/run.hpp"
#include "carom/run/start.hpp"

namespace carom::python {

namespace py = pybind11;

// carom.init's request: `carom init`'s start, run with `settings` and `shear`.
struct InitStart {
  InitSpec spec;
  Settings settings;
  ShearRequest shear;
};

// The value of E named `value` (the library's names: "elastic"), or ValueError naming `keyword`.
template <class E>
E choice(const std::string& keyword, py::handle value) {
  if (py::isinstance<py::str>(value)) {
    if (const auto chosen = from_name<E>(value.cast<std::string>())) return *chosen;
  }
  throw py::value_error(
      fmt::format("{} must be {}, got {}", keyword, names_list<E>(), std::string(py::repr(value))));
}

// The Python keyword that sets the field `key` (RequestError's keys), as messages spell it:
// "kT=" for "temperature", 'rule="elastic"' for "rule" set to "elastic".
std::string python_keyword(std::string_view key, std::string_view value);

}  // namespace carom::python
