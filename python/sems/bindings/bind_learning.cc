/* gr-sems: Python bindings for learning (placeholder until the block lands). */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_learning(py::module& m) {}
