/* gr-sems: Python bindings for baselines (placeholder until the block lands). */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_baselines(py::module& m) {}
