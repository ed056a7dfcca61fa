// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for mimo_pilot_mapper. */
#include <pybind11/complex.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/mimo_pilot_mapper.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)

namespace py = pybind11;

void bind_mimo_pilot_mapper(py::module& m)
{
    using gr::sems::mimo_pilot_mapper;
    py::class_<mimo_pilot_mapper, gr::block, gr::basic_block, std::shared_ptr<mimo_pilot_mapper>>(
        m, "mimo_pilot_mapper", D(mimo_pilot_mapper))
        .def(py::init(&mimo_pilot_mapper::make),
             py::arg("mimo_mask_file"),
             py::arg("n_transmit"),
             py::arg("pilot_power") = 1.0,
             py::arg("data_power") = 1.0,
             py::arg("guard_subcarriers") = std::vector<int>{},
             D(mimo_pilot_mapper, make))
        .def("set_pilot_power", &mimo_pilot_mapper::set_pilot_power, D(mimo_pilot_mapper, set_pilot_power),
             py::arg("energy"))
        .def("pilot_power", &mimo_pilot_mapper::pilot_power, D(mimo_pilot_mapper, pilot_power))
        .def("set_data_power", &mimo_pilot_mapper::set_data_power, D(mimo_pilot_mapper, set_data_power),
             py::arg("energy"))
        .def("data_power", &mimo_pilot_mapper::data_power, D(mimo_pilot_mapper, data_power))
        .def("mask", &mimo_pilot_mapper::mask, D(mimo_pilot_mapper, mask), py::return_value_policy::copy)
        .def("data_per_frame", &mimo_pilot_mapper::data_per_frame, D(mimo_pilot_mapper, data_per_frame))
        .def("frames", &mimo_pilot_mapper::frames, D(mimo_pilot_mapper, frames));
}
