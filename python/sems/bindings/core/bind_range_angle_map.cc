// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for range_angle_map. */
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/range_angle_map.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)

namespace py = pybind11;

void bind_range_angle_map(py::module& m)
{
    using gr::sems::range_angle_map;
    const gr::sems::frame_settings defaults;
    py::class_<range_angle_map, gr::block, gr::basic_block, std::shared_ptr<range_angle_map>>(
        m, "range_angle_map", D(range_angle_map))
        .def(py::init(&range_angle_map::make),
             py::arg("array"),
             py::arg("mask_file") = "",
             py::arg("pilot_positions") = std::vector<int>{},
             py::arg("n_symbols") = defaults.n_symbols,
             py::arg("n_subcarriers") = defaults.n_subcarriers,
             py::arg("carrier_hz") = defaults.carrier_hz,
             py::arg("n_angles") = 64,
             py::arg("window") = "hann",
             D(range_angle_map, make))
        .def("n_elements", &range_angle_map::n_elements, D(range_angle_map, n_elements))
        .def("n_pilots", &range_angle_map::n_pilots, D(range_angle_map, n_pilots))
        .def("n_angles", &range_angle_map::n_angles, D(range_angle_map, n_angles))
        .def("frames_out", &range_angle_map::frames_out, D(range_angle_map, frames_out))
        .def("frames_skipped_nonfinite", &range_angle_map::frames_skipped_nonfinite,
             D(range_angle_map, frames_skipped_nonfinite));
}
