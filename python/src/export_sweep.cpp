#include "exports.hpp"

namespace carom::python {

void export_sweep(pybind11::module_&) {}

}  // namespace carom::python
