// The requests Python makes of the library (export_specs.cpp binds them): RunSpec, StartSpec,
// and InitStart, carom.init's.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <string_view>

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

// The Python keyword that sets the field `key` (RequestError's keys), as messages spell it:
// "kT=" for "temperature", 'rule="elastic"' for "rule" set to "elastic".
std::string python_keyword(std::string_view key, std::string_view value);

}  // namespace carom::python
