// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings of the MIMO mask learner (learning/array/mimo_mask_learner.h):
 * its settings, result and objective. JSON crosses as text, as the other learning bindings. */
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/learning/array/mimo_mask_learner.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <iostream>

namespace py = pybind11;
using namespace gr::sems;

void bind_mimo(py::module& m)
{
    using mms = mimo_mask_settings;
    py::class_<mms>(m, "mimo_mask_settings", D(mimo_mask_settings))
        .def(py::init<>())
        .def_readwrite("array", &mms::array, D(mimo_mask_settings, array))
        .def_readwrite("frame", &mms::frame, D(mimo_mask_settings, frame))
        .def_readwrite("n_pilots", &mms::n_pilots, D(mimo_mask_settings, n_pilots))
        .def_readwrite("azimuth_min_rad", &mms::azimuth_min_rad, D(mimo_mask_settings, azimuth_min_rad))
        .def_readwrite("azimuth_max_rad", &mms::azimuth_max_rad, D(mimo_mask_settings, azimuth_max_rad))
        .def_readwrite("elevation_rad", &mms::elevation_rad, D(mimo_mask_settings, elevation_rad))
        .def_readwrite("epochs", &mms::epochs, D(mimo_mask_settings, epochs))
        .def_readwrite("steps", &mms::steps, D(mimo_mask_settings, steps))
        .def_readwrite("draws", &mms::draws, D(mimo_mask_settings, draws))
        .def_readwrite("eval_azimuths", &mms::eval_azimuths, D(mimo_mask_settings, eval_azimuths))
        .def_readwrite("lr", &mms::lr, D(mimo_mask_settings, lr))
        .def_property(
            "encoder_json", [](const mms& s) { return s.encoder.to_json().dump(); },
            [](mms& s, const std::string& t) {
                s.encoder = nn::encoder_settings::from_json(nlohmann::json::parse(t), "encoder_json");
            },
            "the resource elements' selector and its temperature schedule as JSON text (keys as in "
            "training_settings.encoder_json)")
        .def_readwrite("seed", &mms::seed, D(mimo_mask_settings, seed))
        .def_readwrite("threads", &mms::threads, D(mimo_mask_settings, threads))
        .def_readwrite("command_line", &mms::command_line, D(mimo_mask_settings, command_line))
        .def_readwrite("verbose", &mms::verbose, D(mimo_mask_settings, verbose))
        .def("validate", &mms::validate, D(mimo_mask_settings, validate));

    py::class_<mimo_mask_result>(m, "mimo_mask_result", D(mimo_mask_result))
        .def_readonly("mask", &mimo_mask_result::mask, D(mimo_mask_result, mask))
        .def_property_readonly("history_json", [](const mimo_mask_result& r) { return r.history.dump(); },
                               D(mimo_mask_result, history))
        .def_readonly("mean_crb_rad2", &mimo_mask_result::mean_crb_rad2, D(mimo_mask_result, mean_crb_rad2))
        .def_readonly("seconds", &mimo_mask_result::seconds, D(mimo_mask_result, seconds));

    m.def("mimo_mean_crb_rad2", &mimo_mean_crb_rad2, D(mimo_mean_crb_rad2), py::arg("array"), py::arg("mask"),
          py::arg("fs"), py::arg("lo"), py::arg("hi"), py::arg("count"), py::arg("elevation_rad") = 0.0);

    m.def(
        "learn_mimo_mask",
        [](const mms& s) {
            py::gil_scoped_release nogil;
            return learn_mimo_mask(s, s.verbose ? &std::cout : nullptr);
        },
        py::arg("settings"), D(learn_mimo_mask));
}
