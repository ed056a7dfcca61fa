/* gr-sems: Python bindings for pilot_extractor (placeholder until the block lands). */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_pilot_extractor(py::module& m) {}
