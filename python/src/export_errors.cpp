// carom's errors in Python: bad input and bad arguments are ValueErrors (InputError names the
// file and line), a run that cannot go on is a RuntimeError (JamError).
#include "carom/classic_input.hpp"
#include "carom/engine.hpp"
#include "exports.hpp"

namespace carom::python {

void export_errors(pybind11::module_& m) {
  pybind11::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  pybind11::register_exception<JamError>(m, "JamError", PyExc_RuntimeError);
}

}  // namespace carom::python
