// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for frame_sync. */
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/frame_sync.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)

namespace py = pybind11;

void bind_frame_sync(py::module& m)
{
    using gr::sems::frame_sync;
    const gr::sems::frame_settings defaults;
    py::class_<frame_sync, gr::block, gr::basic_block, std::shared_ptr<frame_sync>>(
        m, "frame_sync", D(frame_sync))
        .def(py::init(&frame_sync::make),
             py::arg("mask_file") = "",
             py::arg("pilot_positions") = std::vector<int>{},
             py::arg("n_symbols") = defaults.n_symbols,
             py::arg("n_subcarriers") = defaults.n_subcarriers,
             py::arg("pilot_symbol") = gr_complex(1.0f, 0.0f),
             py::arg("pilot_power") = 1.0,
             py::arg("cp_len") = defaults.cp_len,
             py::arg("search_frames") = 4,
             py::arg("threshold") = 25.0,
             py::arg("noncoherent") = false,
             D(frame_sync, make))
        .def("locked", &frame_sync::locked, D(frame_sync, locked))
        .def("offset", &frame_sync::offset, D(frame_sync, offset))
        .def("metric", &frame_sync::metric, D(frame_sync, metric))
        .def("failures", &frame_sync::failures, D(frame_sync, failures))
        .def("frame_len", &frame_sync::frame_len, D(frame_sync, frame_len))
        .def("stream_error", &frame_sync::stream_error, D(frame_sync, stream_error));
}
