/* gr-sems: Python bindings for pilot_mapper (placeholder until the block lands). */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_pilot_mapper(py::module& m) {}
