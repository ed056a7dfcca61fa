// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the pybind11 module `gnuradio.sems.baselines_python` — the classical
 * references (periodogram, OMP, MUSIC, CRB, Doppler features, SVM). No LibTorch.
 */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_baselines(py::module& m);

PYBIND11_MODULE(baselines_python, m)
{
    m.doc() = "gr-sems baselines: classical delay estimators, the CRB, Doppler features and the SVM";
    py::module::import("gnuradio.sems.core_python");

    bind_baselines(m);
}
