// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for pilot_extractor. */
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/pilot_extractor.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)

namespace py = pybind11;

void bind_pilot_extractor(py::module& m)
{
    using gr::sems::pilot_extractor;
    const gr::sems::frame_settings defaults;
    py::class_<pilot_extractor, gr::block, gr::basic_block, std::shared_ptr<pilot_extractor>>(
        m, "pilot_extractor", D(pilot_extractor))
        .def(py::init(&pilot_extractor::make),
             py::arg("mask_file") = "",
             py::arg("pilot_positions") = std::vector<int>{},
             py::arg("n_symbols") = defaults.n_symbols,
             py::arg("n_subcarriers") = defaults.n_subcarriers,
             py::arg("pilot_symbol") = gr_complex(1.0f, 0.0f),
             py::arg("n_elements") = 1,
             D(pilot_extractor, make))
        .def("mask", &pilot_extractor::mask, D(pilot_extractor, mask), py::return_value_policy::copy)
        .def("super_frame", &pilot_extractor::super_frame, D(pilot_extractor, super_frame), py::return_value_policy::copy)
        .def("n_pilots", &pilot_extractor::n_pilots, D(pilot_extractor, n_pilots))
        .def("n_elements", &pilot_extractor::n_elements, D(pilot_extractor, n_elements))
        .def("frames_out", &pilot_extractor::frames_out, D(pilot_extractor, frames_out))
        .def("frames_dropped_partial", &pilot_extractor::frames_dropped_partial, D(pilot_extractor, frames_dropped_partial))
        .def("frames_skipped_nonfinite", &pilot_extractor::frames_skipped_nonfinite, D(pilot_extractor, frames_skipped_nonfinite));
}
