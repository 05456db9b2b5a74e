#pragma once
// The parts of the module `ggk`, one per concern of kernels/, each adding its
// functions and classes to the module (module.cpp calls them in this order).
#include <pybind11/pybind11.h>

namespace ggk::python {

void bind_graphs(pybind11::module_& module);                 // graphs.cpp
void bind_kernel_tables(pybind11::module_& module);          // kernel_tables.cpp
void bind_proto_value_functions(pybind11::module_& module);  // proto_value_functions.cpp
void bind_bases(pybind11::module_& module);                  // bases.cpp
void bind_som(pybind11::module_& module);                    // som.cpp
void bind_lspi(pybind11::module_& module);                   // lspi.cpp
void bind_environments(pybind11::module_& module);           // environments.cpp
void bind_sequential(pybind11::module_& module);             // sequential.cpp

}  // namespace ggk::python
