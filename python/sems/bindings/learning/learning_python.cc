// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the pybind11 module `gnuradio.sems.learning_python` — model bundles, the
 * bundle decoder, the trainer and the LibTorch sinks. Importing it loads LibTorch;
 * `gnuradio.sems` imports it only when one of its names is first used.
 */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_learning(py::module& m);
void bind_sinks(py::module& m);
void bind_temporal(py::module& m);
void bind_position(py::module& m);
void bind_mimo(py::module& m);

PYBIND11_MODULE(learning_python, m)
{
    m.doc() = "gr-sems learning: model bundles, bundle_decoder, train() and the sinks (LibTorch)";
    py::module::import("gnuradio.gr");
    // frame_settings, pilot_mask, scene, ... are registered by the core module.
    py::module::import("gnuradio.sems.core_python");

    bind_learning(m);
    bind_sinks(m);
    bind_temporal(m);
    bind_position(m);
    bind_mimo(m);
}
