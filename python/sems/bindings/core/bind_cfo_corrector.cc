// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for cfo_corrector. */
#include <pybind11/pybind11.h>

#include <gnuradio/sems/blocks/cfo_corrector.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)

namespace py = pybind11;

void bind_cfo_corrector(py::module& m)
{
    using gr::sems::cfo_corrector;
    const gr::sems::frame_settings fs;
    py::class_<cfo_corrector, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<cfo_corrector>>(
        m, "cfo_corrector", D(cfo_corrector))
        .def(py::init(&cfo_corrector::make),
             py::arg("n_subcarriers") = fs.n_subcarriers,
             py::arg("cp_len") = fs.cp_len,
             py::arg("symbols") = fs.n_symbols,
             py::arg("forgetting") = 0.5,
             py::arg("snr_db") = 10.0,
             D(cfo_corrector, make))
        .def("cfo", &cfo_corrector::cfo, D(cfo_corrector, cfo))
        .def("timing", &cfo_corrector::timing, D(cfo_corrector, timing))
        .def("windows", &cfo_corrector::windows, D(cfo_corrector, windows));
}
