// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for pilot_mapper. */
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/pilot_mapper.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)

namespace py = pybind11;

void bind_pilot_mapper(py::module& m)
{
    using gr::sems::pilot_mapper;
    const gr::sems::frame_settings defaults;
    py::class_<pilot_mapper, gr::block, gr::basic_block, std::shared_ptr<pilot_mapper>>(
        m, "pilot_mapper", D(pilot_mapper))
        .def(py::init(&pilot_mapper::make),
             py::arg("mask_file") = "",
             py::arg("pilot_positions") = std::vector<int>{},
             py::arg("n_symbols") = defaults.n_symbols,
             py::arg("n_subcarriers") = defaults.n_subcarriers,
             py::arg("pilot_symbol") = gr_complex(1.0f, 0.0f),
             py::arg("pilot_power") = 1.0,
             py::arg("data_power") = 1.0,
             py::arg("guard_subcarriers") = std::vector<int>{},
             D(pilot_mapper, make))
        .def("set_pilot_power", &pilot_mapper::set_pilot_power, D(pilot_mapper, set_pilot_power), py::arg("energy"))
        .def("pilot_power", &pilot_mapper::pilot_power, D(pilot_mapper, pilot_power))
        .def("set_data_power", &pilot_mapper::set_data_power, D(pilot_mapper, set_data_power), py::arg("energy"))
        .def("data_power", &pilot_mapper::data_power, D(pilot_mapper, data_power))
        .def("mask", &pilot_mapper::mask, D(pilot_mapper, mask), py::return_value_policy::copy)
        .def("super_frame", &pilot_mapper::super_frame, D(pilot_mapper, super_frame), py::return_value_policy::copy)
        .def("n_pilots", &pilot_mapper::n_pilots, D(pilot_mapper, n_pilots))
        .def("data_per_frame", &pilot_mapper::data_per_frame, D(pilot_mapper, data_per_frame))
        .def("frames", &pilot_mapper::frames, D(pilot_mapper, frames));
}
