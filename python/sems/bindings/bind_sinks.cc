/* gr-sems: Python bindings for sinks (placeholder until the block lands). */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_sinks(py::module& m) {}
