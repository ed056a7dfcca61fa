// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings of decisions over a track: track training and the track classifier. */
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <gnuradio/sems/learning/temporal/track_trainer.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <iostream>
#include <optional>

namespace py = pybind11;
using namespace gr::sems;

void bind_temporal(py::module& m)
{
    using obs_array = py::array_t<gr_complex, py::array::c_style | py::array::forcecast>;
    using ev_array = py::array_t<float, py::array::c_style | py::array::forcecast>;
    using sets_array = py::array_t<int, py::array::c_style | py::array::forcecast>;

    py::class_<track_training_settings>(m, "track_training_settings", D(track_training_settings))
        .def(py::init<>())
        .def_readwrite("frame_bundle", &track_training_settings::frame_bundle, D(track_training_settings, frame_bundle))
        .def_property(
            "scene", [](const track_training_settings& s) { return s.scene_spec; },
            [](track_training_settings& s, const std::optional<scene>& sc) { s.scene_spec = sc; },
            D(track_training_settings, scene_spec))
        .def_readwrite("scene_source", &track_training_settings::scene_source, D(track_training_settings, scene_source))
        .def_readwrite("track_frames", &track_training_settings::track_frames, D(track_training_settings, track_frames))
        .def_readwrite("tracks", &track_training_settings::tracks, D(track_training_settings, tracks))
        .def_readwrite("snr_min_db", &track_training_settings::snr_min_db, D(track_training_settings, snr_min_db))
        .def_readwrite("snr_max_db", &track_training_settings::snr_max_db, D(track_training_settings, snr_max_db))
        .def_readwrite("epochs", &track_training_settings::epochs, D(track_training_settings, epochs))
        .def_readwrite("batch", &track_training_settings::batch, D(track_training_settings, batch))
        .def_readwrite("lr", &track_training_settings::lr, D(track_training_settings, lr))
        .def_readwrite("acf_tcn_lr", &track_training_settings::acf_tcn_lr, D(track_training_settings, acf_tcn_lr))
        .def_readwrite("loss_ramp", &track_training_settings::loss_ramp, D(track_training_settings, loss_ramp))
        .def_readwrite("weight_decay", &track_training_settings::weight_decay, D(track_training_settings, weight_decay))
        .def_readwrite("patience", &track_training_settings::patience, D(track_training_settings, patience))
        .def_readwrite("seed", &track_training_settings::seed, D(track_training_settings, seed))
        .def_readwrite("threads", &track_training_settings::threads, D(track_training_settings, threads))
        .def_readwrite("eval_snr_db", &track_training_settings::eval_snr_db, D(track_training_settings, eval_snr_db))
        .def_readwrite("eval_frames", &track_training_settings::eval_frames, D(track_training_settings, eval_frames))
        .def_property(
            "temporal_json", [](const track_training_settings& s) { return s.temporal.to_json().dump(); },
            [](track_training_settings& s, const std::string& t) {
                s.temporal = nn::temporal_settings::from_json(nlohmann::json::parse(t), "temporal_json");
            },
            "the temporal model's settings as JSON text (keys as in bundle.json's track.temporal.settings: kind "
            "gru_fusion or acf_tcn, and that kind's own keys)")
        .def_readwrite("super_frames", &track_training_settings::super_frames, D(track_training_settings, super_frames))
        .def_readwrite("mask_epochs", &track_training_settings::mask_epochs, D(track_training_settings, mask_epochs))
        .def_readwrite("mask_tracks", &track_training_settings::mask_tracks, D(track_training_settings, mask_tracks))
        .def_readwrite("mask_start", &track_training_settings::mask_start, D(track_training_settings, mask_start))
        .def_readwrite("mask_lr", &track_training_settings::mask_lr, D(track_training_settings, mask_lr))
        .def_readwrite("mask_encoder_lr", &track_training_settings::mask_encoder_lr,
                       D(track_training_settings, mask_encoder_lr))
        .def_readwrite("out_dir", &track_training_settings::out_dir, D(track_training_settings, out_dir))
        .def_readwrite("command_line", &track_training_settings::command_line, D(track_training_settings, command_line))
        .def_readwrite("verbose", &track_training_settings::verbose, D(track_training_settings, verbose))
        .def("validate", &track_training_settings::validate, D(track_training_settings, validate));

    py::class_<track_training_result>(m, "track_training_result", D(track_training_result))
        .def_readonly("bundle", &track_training_result::bundle, D(track_training_result, bundle))
        .def_readonly("seconds", &track_training_result::seconds, D(track_training_result, seconds))
        .def_property_readonly("history_json", [](const track_training_result& r) { return r.history.dump(); })
        .def_property_readonly("metrics_json", [](const track_training_result& r) { return r.metrics.dump(); });

    m.def(
        "train_track",
        [](const track_training_settings& s) {
            py::gil_scoped_release nogil;
            return train_track(s, s.verbose ? &std::cout : nullptr);
        },
        py::arg("settings"), D(train_track));

    py::class_<track_classifier::state>(m, "track_state", D(track_classifier, state))
        .def_readonly("frames", &track_classifier::state::frames, D(track_classifier, state, frames));

    py::class_<track_classifier, std::shared_ptr<track_classifier>>(m, "track_classifier", D(track_classifier))
        .def(py::init([](const std::string& dir, int threads) {
                 return std::make_shared<track_classifier>(model_bundle::load(dir), threads);
             }),
             py::arg("bundle_dir"), py::arg("threads") = 1)
        .def_static("is_track_bundle", &track_classifier::is_track_bundle, D(track_classifier, is_track_bundle),
                    py::arg("bundle"))
        .def("bundle", &track_classifier::bundle, py::return_value_policy::reference_internal)
        .def("n_pilots", &track_classifier::n_pilots, D(track_classifier, n_pilots))
        .def("n_classes", &track_classifier::n_classes, D(track_classifier, n_classes))
        .def("super_frames", &track_classifier::super_frames, D(track_classifier, super_frames))
        .def("evidence_size", &track_classifier::evidence_size, D(track_classifier, evidence_size))
        .def("begin", &track_classifier::begin, D(track_classifier, begin))
        .def(
            "evidence",
            [](const track_classifier& tc, const obs_array& obs, const std::optional<sets_array>& sets) {
                if (obs.ndim() != 2 || obs.shape(1) != tc.n_pilots())
                    throw std::invalid_argument("track_classifier: observations must have shape (frames, " +
                                                std::to_string(tc.n_pilots()) + ")");
                const int b = static_cast<int>(obs.shape(0));
                if (sets && (sets->ndim() != 1 || sets->shape(0) != b))
                    throw std::invalid_argument("track_classifier: sets must have shape (" + std::to_string(b) +
                                                ",), one per frame (its frame index mod F)");
                const int* ps = sets ? sets->data() : nullptr;
                std::vector<float> e;
                {
                    py::gil_scoped_release nogil;
                    e = tc.evidence(obs.data(), b, ps);
                }
                py::array_t<float> a({ static_cast<py::ssize_t>(b), static_cast<py::ssize_t>(tc.evidence_size()) });
                std::copy(e.begin(), e.end(), a.mutable_data());
                return a;
            },
            py::arg("obs"), py::arg("sets") = py::none(),
            "(frames, N_p) complex -> (frames, evidence_size()) evidence; sets: each frame's set of a super-frame "
            "mask (its frame index mod F), needed when the bundle's mask spans F > 1 frames")
        .def(
            "step",
            [](const track_classifier& tc, track_classifier::state& s, const ev_array& ev) {
                if (ev.ndim() != 1 || ev.shape(0) != tc.evidence_size())
                    throw std::invalid_argument("track_classifier.step: one frame's evidence has " +
                                                std::to_string(tc.evidence_size()) + " values");
                py::array_t<float> p(tc.n_classes()), q(tc.n_classes());
                tc.step(s, ev.data(), p.mutable_data(), q.mutable_data());
                return py::make_tuple(p, q);
            },
            py::arg("state"), py::arg("evidence"),
            "one frame of a track: updates the state; returns (probabilities of the decision over the track, "
            "those of the product of per-frame posteriors)");
}
