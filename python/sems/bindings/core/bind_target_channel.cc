// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for target_channel. */
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/target_channel.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <limits>

namespace py = pybind11;

void bind_target_channel(py::module& m)
{
    using gr::sems::target_channel;
    const gr::sems::frame_settings defaults;
    py::class_<target_channel, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<target_channel>>(
        m, "target_channel", D(target_channel))
        .def(py::init(&target_channel::make),
             py::arg("scene") = "",
             py::arg("classes") = std::vector<std::string>{},
             py::arg("n_targets") = 1,
             py::arg("paths_per_target") = 1,
             py::arg("micro_doppler") = true,
             py::arg("heading") = "approaching",
             py::arg("clutter_paths") = 0,
             py::arg("clutter_csr_db") = 0.0,
             py::arg("snr_db") = std::numeric_limits<double>::infinity(),
             py::arg("seed") = 0,
             py::arg("n_symbols") = defaults.n_symbols,
             py::arg("n_subcarriers") = defaults.n_subcarriers,
             py::arg("bandwidth_hz") = defaults.bandwidth_hz,
             py::arg("carrier_hz") = defaults.carrier_hz,
             py::arg("symbol_interval_s") = defaults.symbol_interval_s,
             py::arg("class_library") = "paper",
             py::arg("track_frames") = 0,
             py::arg("track_gains") = "frame",
             py::arg("track_coherence_time_s") = gr::sems::track_draw_spec{}.coherence_time_s,
             py::arg("n_receive") = 1,
             py::arg("n_transmit") = 1,
             py::arg("track_motion") = gr::sems::track_motion_name(gr::sems::track_draw_spec{}.motion),
             py::arg("array") = "",
             py::arg("azimuth_min_rad") = 0.0,
             py::arg("azimuth_max_rad") = 0.0,
             D(target_channel, make))
        .def("set_snr_db", &target_channel::set_snr_db, D(target_channel, set_snr_db), py::arg("snr_db"))
        .def("snr_db", &target_channel::snr_db, D(target_channel, snr_db))
        .def("settings", &target_channel::settings, D(target_channel, settings), py::return_value_policy::copy)
        .def("scene_json", &target_channel::scene_json, D(target_channel, scene_json))
        .def("frames", &target_channel::frames, D(target_channel, frames))
        .def("nonfinite_symbols", &target_channel::nonfinite_symbols, D(target_channel, nonfinite_symbols));
}
