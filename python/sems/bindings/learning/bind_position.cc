// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings of the learned position decoder: position training and the
 * position estimator. */
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/learning/array/position_estimator.h>
#include <gnuradio/sems/learning/array/position_trainer.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <iostream>
#include <optional>
#include <stdexcept>

namespace py = pybind11;
using namespace gr::sems;

void bind_position(py::module& m)
{
    using obs_array = py::array_t<gr_complex, py::array::c_style | py::array::forcecast>;
    using pts = position_training_settings;
    py::class_<pts>(m, "position_training_settings", D(position_training_settings))
        .def(py::init<>())
        .def_readwrite("delay_bundle", &pts::delay_bundle, D(position_training_settings, delay_bundle))
        .def_readwrite("array", &pts::array, D(position_training_settings, array))
        .def_property(
            "scene", [](const pts& s) { return s.scene_spec; },
            [](pts& s, const std::optional<scene>& sc) { s.scene_spec = sc; }, D(position_training_settings, scene_spec))
        .def_readwrite("scene_source", &pts::scene_source, D(position_training_settings, scene_source))
        .def_readwrite("frames", &pts::frames, D(position_training_settings, frames))
        .def_readwrite("epochs", &pts::epochs, D(position_training_settings, epochs))
        .def_readwrite("batch", &pts::batch, D(position_training_settings, batch))
        .def_readwrite("lr", &pts::lr, D(position_training_settings, lr))
        .def_readwrite("patience", &pts::patience, D(position_training_settings, patience))
        .def_readwrite("snr_min_db", &pts::snr_min_db, D(position_training_settings, snr_min_db))
        .def_readwrite("snr_max_db", &pts::snr_max_db, D(position_training_settings, snr_max_db))
        .def_readwrite("ce_weight", &pts::ce_weight, D(position_training_settings, ce_weight))
        .def_readwrite("seed", &pts::seed, D(position_training_settings, seed))
        .def_readwrite("threads", &pts::threads, D(position_training_settings, threads))
        .def_readwrite("eval_snr_db", &pts::eval_snr_db, D(position_training_settings, eval_snr_db))
        .def_property(
            "angle_json", [](const pts& s) { return s.angle.to_json().dump(); },
            [](pts& s, const std::string& t) {
                s.angle = nn::angle_settings::from_json(nlohmann::json::parse(t), "angle_json");
            },
            "the angle network's settings as JSON text (keys as in bundle.json's position.angle)")
        .def_readwrite("out_dir", &pts::out_dir, D(position_training_settings, out_dir))
        .def_readwrite("command_line", &pts::command_line, D(position_training_settings, command_line))
        .def_readwrite("verbose", &pts::verbose, D(position_training_settings, verbose))
        .def_static("default_scene", &pts::default_scene, D(position_training_settings, default_scene))
        .def("validate", &pts::validate, D(position_training_settings, validate));

    py::class_<position_training_result>(m, "position_training_result", D(position_training_result))
        .def_readonly("bundle", &position_training_result::bundle, D(position_training_result, bundle))
        .def_readonly("seconds", &position_training_result::seconds, D(position_training_result, seconds))
        .def_property_readonly("history_json", [](const position_training_result& r) { return r.history.dump(); })
        .def_property_readonly("metrics_json", [](const position_training_result& r) { return r.metrics.dump(); });

    m.def(
        "train_position",
        [](const pts& s) {
            py::gil_scoped_release nogil;
            return train_position(s, s.verbose ? &std::cout : nullptr);
        },
        py::arg("settings"), D(train_position));

    py::class_<position_estimate>(m, "position_estimate", D(position_estimate))
        .def_readonly("delay_s", &position_estimate::delay_s, D(position_estimate, delay_s))
        .def_readonly("delay_index", &position_estimate::delay_index, D(position_estimate, delay_index))
        .def_readonly("range_m", &position_estimate::range_m, D(position_estimate, range_m))
        .def_readonly("azimuth_rad", &position_estimate::azimuth_rad, D(position_estimate, azimuth_rad));

    // obs: frames x (N_r·N_p) complex64, or one frame of N_r·N_p.
    auto frames = [](const position_estimator& p, const obs_array& obs) {
        const ssize_t per = ssize_t(p.n_elements()) * p.n_pilots();
        if (obs.size() == 0 || obs.size() % per != 0)
            throw std::invalid_argument("position_estimator: expected frames of N_r·N_p = " + std::to_string(per) +
                                        " observations, got " + std::to_string(obs.size()) + " values");
        return int(obs.size() / per);
    };
    py::class_<position_estimator, std::shared_ptr<position_estimator>>(m, "position_estimator", D(position_estimator))
        .def(py::init([](const std::string& dir, int threads) {
                 return std::make_shared<position_estimator>(model_bundle::load(dir), threads);
             }),
             py::arg("bundle_dir"), py::arg("threads") = 1)
        .def("n_elements", &position_estimator::n_elements, D(position_estimator, n_elements))
        .def("n_pilots", &position_estimator::n_pilots, D(position_estimator, n_pilots))
        .def("array", &position_estimator::array, py::return_value_policy::reference_internal, D(position_estimator, array))
        .def(
            "estimate",
            [frames](const position_estimator& p, const obs_array& obs) {
                const int n = frames(p, obs);
                py::gil_scoped_release nogil;
                return p.estimate(obs.data(), n);
            },
            py::arg("obs"), D(position_estimator, estimate))
        .def(
            "estimate_azimuth",
            [frames](const position_estimator& p, const obs_array& obs, bool polish) {
                const int n = frames(p, obs);
                py::gil_scoped_release nogil;
                return p.estimate_azimuth(obs.data(), n, polish);
            },
            py::arg("obs"), py::arg("polish") = true, D(position_estimator, estimate_azimuth));
}
