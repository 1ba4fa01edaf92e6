// One export function per bound class (HOOMD-blue's layout); module.cpp calls them all.
#pragma once

#include <pybind11/pybind11.h>

namespace carom::python {

void export_errors(pybind11::module_& m);
void export_specs(pybind11::module_& m);
void export_simulation(pybind11::module_& m);
void export_analysis(pybind11::module_& m);
void export_sweep(pybind11::module_& m);

}  // namespace carom::python
