// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings of arrays (core/array/array_geometry.h), their steering
 * (core/array/steering.h) and MIMO masks (core/array/mimo_mask.h). Positions cross as
 * (x, y, z) tuples in metres; a MIMO mask's JSON as text (to_json_string / parse), the same
 * text its file holds. */
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/channel/mimo_pilots.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/channel_model.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <algorithm>

namespace py = pybind11;
using namespace gr::sems;

void bind_array(py::module& m)
{
    py::enum_<element_pattern>(m, "element_pattern", D(element_pattern))
        .value("isotropic", element_pattern::isotropic)
        .value("cosine", element_pattern::cosine);

    py::class_<array_geometry>(m, "array_geometry", D(array_geometry))
        .def(py::init<>(), "One receive and one transmit element at the origin: the single-antenna model")
        .def_static("ula", &array_geometry::ula, D(array_geometry, ula), py::arg("elements"), py::arg("spacing_m"),
                    py::arg("pattern") = element_pattern::isotropic)
        .def_static("ura", &array_geometry::ura, D(array_geometry, ura), py::arg("columns"), py::arg("rows"),
                    py::arg("spacing_y_m"), py::arg("spacing_z_m"), py::arg("pattern") = element_pattern::isotropic)
        .def_static("from_positions", &array_geometry::from_positions, D(array_geometry, from_positions),
                    py::arg("receive"), py::arg("transmit") = std::vector<position3>{ position3{ 0.0, 0.0, 0.0 } },
                    py::arg("pattern") = element_pattern::isotropic, py::arg("source") = "array")
        .def_static("load", &array_geometry::load, D(array_geometry, load), py::arg("path"))
        .def_static("find", &array_geometry::find, D(array_geometry, find), py::arg("name_or_path"))
        .def_static(
            "parse",
            [](const std::string& text, const std::string& source) {
                return array_geometry::from_json(nlohmann::json::parse(text), source);
            },
            "Reads an array from its file's JSON text", py::arg("json_text"), py::arg("source") = "array text")
        .def("to_json_string", [](const array_geometry& a) { return a.to_json().dump(); }, "The file's JSON text")
        .def("save", &array_geometry::save, D(array_geometry, save), py::arg("path"))
        .def("receive", &array_geometry::receive, D(array_geometry, receive))
        .def("transmit", &array_geometry::transmit, D(array_geometry, transmit))
        .def("pattern", &array_geometry::pattern, D(array_geometry, pattern))
        .def("n_receive", &array_geometry::n_receive, D(array_geometry, n_receive))
        .def("n_transmit", &array_geometry::n_transmit, D(array_geometry, n_transmit))
        .def("is_single_antenna", &array_geometry::is_single_antenna, D(array_geometry, is_single_antenna))
        .def("reach_m", &array_geometry::reach_m, D(array_geometry, reach_m))
        .def("virtual_offsets", &array_geometry::virtual_offsets, D(array_geometry, virtual_offsets))
        .def("__eq__", [](const array_geometry& a, const array_geometry& b) { return a == b; });

    m.def("direction_vector", &direction_vector, D(direction_vector), py::arg("azimuth_rad"), py::arg("elevation_rad"));
    m.def("steering_vector", &steering_vector, D(steering_vector), py::arg("array"), py::arg("azimuth_rad"),
          py::arg("elevation_rad"), py::arg("wavelength_m"));
    m.def("narrowband_phase_error_rad", &narrowband_phase_error_rad, D(narrowband_phase_error_rad), py::arg("array"),
          py::arg("fs"));

}

// After bind_core: pilot_mask, channel_model and frame_realization are known by their Python
// names in the signatures.
void bind_mimo_mask(py::module& m)
{
    py::class_<mimo_mask>(m, "mimo_mask", D(mimo_mask))
        .def(py::init<pilot_mask, int, std::vector<int>, const std::string&>(), D(mimo_mask, mimo_mask),
             py::arg("mask"), py::arg("n_transmit"), py::arg("transmit"), py::arg("source") = "MIMO mask")
        .def_readonly_static("format_name", &mimo_mask::format_name, D(mimo_mask, format_name))
        .def_readonly_static("format_version", &mimo_mask::format_version, D(mimo_mask, format_version))
        .def_readonly_static("every_element", &mimo_mask::every_element, D(mimo_mask, every_element))
        .def_static("same_pilots", &mimo_mask::same_pilots, D(mimo_mask, same_pilots), py::arg("mask"),
                    py::arg("n_transmit"))
        .def_static("time_division", &mimo_mask::time_division, D(mimo_mask, time_division), py::arg("mask"),
                    py::arg("n_transmit"))
        .def_static("frequency_division", &mimo_mask::frequency_division, D(mimo_mask, frequency_division),
                    py::arg("mask"), py::arg("n_transmit"))
        .def_static("load", &mimo_mask::load, D(mimo_mask, load), py::arg("path"))
        .def_static("parse", &mimo_mask::parse, D(mimo_mask, parse), py::arg("json_text"),
                    py::arg("source") = "MIMO mask text")
        .def("to_json_string", [](const mimo_mask& mk) { return mk.to_json().dump(); }, "The file's JSON text")
        .def("save", &mimo_mask::save, D(mimo_mask, save), py::arg("path"))
        .def("mask", &mimo_mask::mask, D(mimo_mask, mask))
        .def("n_transmit", &mimo_mask::n_transmit, D(mimo_mask, n_transmit))
        .def("transmit", &mimo_mask::transmit, D(mimo_mask, transmit))
        .def("amplitude", &mimo_mask::amplitude, D(mimo_mask, amplitude), py::arg("k"), py::arg("j"))
        .def("pilots_per_element", &mimo_mask::pilots_per_element, D(mimo_mask, pilots_per_element))
        .def("__len__", [](const mimo_mask& mk) { return mk.mask().size(); })
        .def("__eq__", [](const mimo_mask& a, const mimo_mask& b) { return a == b; });

    m.def(
        "mimo_pilots",
        [](const channel_model& cm, const frame_realization& r, uint64_t first_symbol, const mimo_mask& mk) {
            const auto y = mimo_pilots(cm, r, first_symbol, mk);
            py::array_t<gr_complex> out(static_cast<py::ssize_t>(y.size()));
            std::copy(y.begin(), y.end(), out.mutable_data());
            return out;
        },
        D(mimo_pilots), py::arg("model"), py::arg("realization"), py::arg("first_symbol"), py::arg("mask"));
}
