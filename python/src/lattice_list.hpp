// Registers frnn._frnn._lattice_pairs (lattice_list.cpp).
#pragma once
#include <pybind11/pybind11.h>

namespace frnn::python {

void add_lattice_pairs(pybind11::module_& m);

}  // namespace frnn::python
