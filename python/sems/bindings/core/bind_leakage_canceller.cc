// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for leakage_canceller. */
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/leakage_canceller.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)

namespace py = pybind11;

void bind_leakage_canceller(py::module& m)
{
    using gr::sems::leakage_canceller;
    const gr::sems::leakage_canceller_settings defaults;
    py::class_<leakage_canceller, gr::block, gr::basic_block, std::shared_ptr<leakage_canceller>>(
        m, "leakage_canceller", D(leakage_canceller))
        .def(py::init(&leakage_canceller::make),
             py::arg("taps") = defaults.taps,
             py::arg("window") = defaults.window,
             py::arg("forgetting") = defaults.forgetting,
             py::arg("widely_linear") = defaults.widely_linear,
             py::arg("dc") = defaults.dc,
             py::arg("clip_level") = defaults.clip_level,
             D(leakage_canceller, make))
        .def("taps", &leakage_canceller::taps, D(leakage_canceller, taps))
        .def("image_taps", &leakage_canceller::image_taps, D(leakage_canceller, image_taps))
        .def("dc", &leakage_canceller::dc, D(leakage_canceller, dc))
        .def("windows", &leakage_canceller::windows, D(leakage_canceller, windows))
        .def("held", &leakage_canceller::held, D(leakage_canceller, held))
        .def("stream_error", &leakage_canceller::stream_error, D(leakage_canceller, stream_error))
        .def_static("max_lead", &leakage_canceller::max_lead, py::arg("window"), D(leakage_canceller, max_lead));
}
