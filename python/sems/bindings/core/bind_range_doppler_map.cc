// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for range_doppler_map. */
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/range_doppler_map.h>

namespace py = pybind11;

void bind_range_doppler_map(py::module& m)
{
    using gr::sems::range_doppler_map;
    const gr::sems::frame_settings defaults;
    py::class_<range_doppler_map, gr::block, gr::basic_block, std::shared_ptr<range_doppler_map>>(
        m, "range_doppler_map",
        "gr_complex[N_p] pilot observations in, the frame's range-Doppler map float[N*M] (dB) out")
        .def(py::init(&range_doppler_map::make),
             py::arg("mask_file") = "",
             py::arg("pilot_positions") = std::vector<int>{},
             py::arg("n_symbols") = defaults.n_symbols,
             py::arg("n_subcarriers") = defaults.n_subcarriers,
             py::arg("window") = "hann")
        .def("n_pilots", &range_doppler_map::n_pilots)
        .def("frames_out", &range_doppler_map::frames_out)
        .def("frames_skipped_nonfinite", &range_doppler_map::frames_skipped_nonfinite);
}
