/* gr-sems: Python bindings for target_channel (placeholder until the block lands). */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_target_channel(py::module& m) {}
