// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for target_channel_td and the core td_channel. */
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/target_channel_td.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <limits>

namespace py = pybind11;

void bind_target_channel_td(py::module& m)
{
    using gr::sems::target_channel_td;
    const gr::sems::frame_settings defaults;
    py::class_<target_channel_td,
               gr::sync_block,
               gr::block,
               gr::basic_block,
               std::shared_ptr<target_channel_td>>(
        m, "target_channel_td", D(target_channel_td))
        .def(py::init(&target_channel_td::make),
             py::arg("scene") = "",
             py::arg("classes") = std::vector<std::string>{},
             py::arg("n_targets") = 1,
             py::arg("paths_per_target") = 1,
             py::arg("micro_doppler") = true,
             py::arg("clutter_paths") = 0,
             py::arg("clutter_csr_db") = 0.0,
             py::arg("snr_db") = std::numeric_limits<double>::infinity(),
             py::arg("seed") = 0,
             py::arg("n_symbols") = defaults.n_symbols,
             py::arg("n_subcarriers") = defaults.n_subcarriers,
             py::arg("bandwidth_hz") = defaults.bandwidth_hz,
             py::arg("carrier_hz") = defaults.carrier_hz,
             py::arg("symbol_interval_s") = defaults.symbol_interval_s,
             py::arg("cp_len") = defaults.cp_len,
             py::arg("class_library") = "paper",
             py::arg("n_receive") = 1,
             py::arg("n_transmit") = 1,
             py::arg("array") = "",
             py::arg("azimuth_min_rad") = 0.0,
             py::arg("azimuth_max_rad") = 0.0,
             D(target_channel_td, make))
        .def("set_snr_db", &target_channel_td::set_snr_db, D(target_channel_td, set_snr_db), py::arg("snr_db"))
        .def("snr_db", &target_channel_td::snr_db, D(target_channel_td, snr_db))
        .def("settings", &target_channel_td::settings, D(target_channel_td, settings), py::return_value_policy::copy)
        .def("scene_json", &target_channel_td::scene_json, D(target_channel_td, scene_json))
        .def("frames", &target_channel_td::frames, D(target_channel_td, frames))
        .def("nonfinite_symbols", &target_channel_td::nonfinite_symbols, D(target_channel_td, nonfinite_symbols))
        .def("misaligned_tags", &target_channel_td::misaligned_tags, D(target_channel_td, misaligned_tags))
        .def("stream_error", &target_channel_td::stream_error, D(target_channel_td, stream_error));
}
