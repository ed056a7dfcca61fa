// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings of learning: model bundles, bundle_decoder inference on
 * numpy arrays, and the trainer (train(settings) -> result with the bundle and the
 * test frames it was scored on). JSON crosses the boundary as text.
 */
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <optional>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/training/trainer.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <iostream>
#include <stdexcept>

namespace py = pybind11;
using namespace gr::sems;

namespace {

using obs_array = py::array_t<gr_complex, py::array::c_style | py::array::forcecast>;

// obs: (batch, N_p) or (N_p,) complex64.
int check_obs(const bundle_decoder& d, const obs_array& obs)
{
    if (obs.ndim() == 1 && obs.shape(0) == d.n_pilots())
        return 1;
    if (obs.ndim() != 2 || obs.shape(1) != d.n_pilots())
        throw std::invalid_argument("bundle_decoder: observations must have shape (batch, " +
                                    std::to_string(d.n_pilots()) + ")");
    return static_cast<int>(obs.shape(0));
}

using sets_array = py::array_t<int, py::array::c_style | py::array::forcecast>;

// The set of each frame of a super-frame bundle (None: one frame's mask, every frame at set 0).
const int* check_sets(const std::optional<sets_array>& sets, int batch)
{
    if (!sets)
        return nullptr;
    if (sets->ndim() != 1 || sets->shape(0) != batch)
        throw std::invalid_argument("bundle_decoder: sets must have shape (" + std::to_string(batch) +
                                    ",), one set per frame (its frame index mod F)");
    return sets->data();
}

template <typename T>
py::array_t<T> to_array(const std::vector<T>& v, std::vector<py::ssize_t> shape)
{
    py::array_t<T> a(shape);
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

} // namespace

void bind_learning(py::module& m)
{
    py::enum_<task_kind>(m, "task_kind", D(task_kind)).value("classify", task_kind::classify).value("delay", task_kind::delay);
    m.def("task_name", &task_name, D(task_name), py::arg("task"));
    m.def("task_from_name", &task_from_name, D(task_from_name), py::arg("name"));

    py::class_<model_bundle>(m, "model_bundle", D(model_bundle))
        .def_static("load", &model_bundle::load, py::arg("dir"))
        .def_static("find", &model_bundle::find, D(model_bundle, find), py::arg("name"))
        .def_static("search_path", &model_bundle::search_path, D(model_bundle, search_path))
        .def_readonly("mask_name", &model_bundle::mask_name, D(model_bundle, mask_name))
        .def_readonly("weights_name", &model_bundle::weights_name, D(model_bundle, weights_name))
        .def("weights_path", &model_bundle::weights_path, D(model_bundle, weights_path))
        .def_readonly("directory", &model_bundle::directory)
        .def_readonly("task", &model_bundle::task)
        .def_readonly("class_names", &model_bundle::class_names)
        .def_property_readonly(
            "library",
            [](const model_bundle& b) { return std::const_pointer_cast<class_library>(b.library); },
            D(model_bundle, library))
        .def(
            "check_library",
            [](const model_bundle& b, const class_library& input, const std::string& who) {
                b.check_library(input, who);
            },
            D(model_bundle, check_library), py::arg("input"), py::arg("who") = "model_bundle")
        .def_readonly("frame", &model_bundle::frame)
        .def_readonly("mask", &model_bundle::mask)
        .def_property_readonly("super_frames", &model_bundle::super_frames, D(model_bundle, super_frames))
        .def("mask_of_set", &model_bundle::mask_of_set, D(model_bundle, mask_of_set), py::arg("f"))
        .def_property_readonly("n_pilots", [](const model_bundle& b) { return b.mask.size(); })
        .def_property_readonly("decoder_json", [](const model_bundle& b) { return b.decoder.dump(); })
        .def_property_readonly("training_json", [](const model_bundle& b) { return b.training.dump(); })
        .def_property_readonly("metrics_json", [](const model_bundle& b) { return b.metrics.dump(); })
        .def_property_readonly("track_json", [](const model_bundle& b) { return b.track.dump(); }, D(model_bundle, track))
        .def("to_json_string", [](const model_bundle& b) { return b.to_json().dump(2); })
        .def("check_compatible", &model_bundle::check_compatible, py::arg("frame"), py::arg("n_pilots"),
             py::arg("expected"), py::arg("who"));

    py::class_<bundle_decoder, std::shared_ptr<bundle_decoder>>(
        m, "bundle_decoder", D(bundle_decoder))
        .def(py::init([](const model_bundle& b, int threads) { return std::make_shared<bundle_decoder>(b, threads); }),
             py::arg("bundle"), py::arg("threads") = 1)
        .def(py::init([](const std::string& dir, int threads) {
                 return std::make_shared<bundle_decoder>(model_bundle::load(dir), threads);
             }),
             py::arg("bundle_dir"), py::arg("threads") = 1)
        .def("bundle", &bundle_decoder::bundle, py::return_value_policy::reference_internal)
        .def("n_pilots", &bundle_decoder::n_pilots)
        .def("super_frames", &bundle_decoder::super_frames, D(bundle_decoder, super_frames))
        .def("feature_size", &bundle_decoder::feature_size)
        .def(
            "classify",
            [](const bundle_decoder& d, const obs_array& obs, const std::optional<sets_array>& sets) {
                const int b = check_obs(d, obs);
                const int* s = check_sets(sets, b);
                std::vector<float> p;
                {
                    py::gil_scoped_release nogil;
                    p = d.classify(obs.data(), b, s);
                }
                const py::ssize_t c = b ? static_cast<py::ssize_t>(p.size() / b) : 0;
                return to_array(p, { b, c });
            },
            py::arg("obs"), py::arg("sets") = py::none(),
            "(batch, N_p) complex -> (batch, C) class probabilities; sets: each frame's set of a super-frame "
            "mask (its frame index mod F), needed when the bundle's mask spans F > 1 frames")
        .def(
            "features",
            [](const bundle_decoder& d, const obs_array& obs, const std::optional<sets_array>& sets) {
                const int b = check_obs(d, obs);
                const int* s = check_sets(sets, b);
                std::vector<float> f;
                {
                    py::gil_scoped_release nogil;
                    f = d.features(obs.data(), b, s);
                }
                const py::ssize_t c = b ? static_cast<py::ssize_t>(f.size() / b) : 0;
                return to_array(f, { b, c });
            },
            py::arg("obs"), py::arg("sets") = py::none(),
            "(batch, N_p) complex -> (batch, 16) decoder features; sets as classify()")
        .def(
            "estimate_delay",
            [](const bundle_decoder& d, const obs_array& obs) {
                const int b = check_obs(d, obs);
                std::vector<double> v;
                {
                    py::gil_scoped_release nogil;
                    v = d.estimate_delay(obs.data(), b);
                }
                return to_array(v, { b });
            },
            py::arg("obs"), "(batch, N_p) complex -> (batch,) delay in seconds")
        .def(
            "estimate_delay_index",
            [](const bundle_decoder& d, const obs_array& obs) {
                const int b = check_obs(d, obs);
                std::vector<double> v;
                {
                    py::gil_scoped_release nogil;
                    v = d.estimate_delay_index(obs.data(), b);
                }
                return to_array(v, { b });
            },
            py::arg("obs"), "(batch, N_p) complex -> (batch,) delay index τ·B");

    py::class_<training_settings>(m, "training_settings", D(training_settings))
        .def(py::init<>())
        .def_readwrite("task", &training_settings::task)
        .def_readwrite("objective", &training_settings::objective)
        .def_readwrite("n_pilots", &training_settings::n_pilots)
        .def_readwrite("mask_file", &training_settings::mask_file)
        .def_readwrite("mask_pattern", &training_settings::mask_pattern)
        .def_readwrite("frame", &training_settings::frame)
        .def_property(
            "scene", [](const training_settings& s) { return s.scene_spec; },
            [](training_settings& s, const std::optional<scene>& sc) { s.scene_spec = sc; })
        .def_readwrite("scene_source", &training_settings::scene_source)
        .def_readwrite("radio", &training_settings::radio)
        .def_readwrite("radio_source", &training_settings::radio_source)
        .def_readwrite("snr_min_db", &training_settings::snr_min_db)
        .def_readwrite("snr_max_db", &training_settings::snr_max_db)
        .def_readwrite("frames", &training_settings::frames)
        .def_readwrite("epochs", &training_settings::epochs)
        .def_readwrite("decoder_epochs", &training_settings::decoder_epochs)
        .def_readwrite("batch", &training_settings::batch)
        .def_readwrite("lr", &training_settings::lr)
        .def_readwrite("lr_final_scale", &training_settings::lr_final_scale)
        .def_readwrite("patience", &training_settings::patience)
        .def_readwrite("mask_settle_epochs", &training_settings::mask_settle_epochs)
        .def_readwrite("delay_ce_weight", &training_settings::delay_ce_weight)
        .def_readwrite("delay_ce_weight_final", &training_settings::delay_ce_weight_final)
        .def_readwrite("threads", &training_settings::threads)
        .def_readwrite("training_data", &training_settings::training_data)
        .def_readwrite("seed", &training_settings::seed)
        .def_readwrite("eval_snr_db", &training_settings::eval_snr_db)
        .def_readwrite("eval_frames", &training_settings::eval_frames)
        .def_readwrite("delay_spacing", &training_settings::delay_spacing)
        .def_readwrite("delay_margin", &training_settings::delay_margin)
        .def_readwrite("out_dir", &training_settings::out_dir)
        .def_readwrite("command_line", &training_settings::command_line)
        .def_readwrite("verbose", &training_settings::verbose)
        // Network sizes as JSON text (keys as in bundle.json's decoder settings).
        .def_property(
            "encoder_json", [](const training_settings& s) { return s.encoder.to_json().dump(); },
            [](training_settings& s, const std::string& t) {
                s.encoder = nn::encoder_settings::from_json(nlohmann::json::parse(t), "encoder_json");
            })
        .def_property(
            "classifier_json", [](const training_settings& s) { return s.classifier.to_json().dump(); },
            [](training_settings& s, const std::string& t) {
                s.classifier = nn::classifier_settings::from_json(nlohmann::json::parse(t), "classifier_json");
            })
        .def_property(
            "delay_json", [](const training_settings& s) { return s.delay.to_json().dump(); },
            [](training_settings& s, const std::string& t) {
                s.delay = nn::delay_settings::from_json(nlohmann::json::parse(t), "delay_json");
            })
        .def_property(
            "reconstruction_json", [](const training_settings& s) { return s.reconstruction.to_json().dump(); },
            [](training_settings& s, const std::string& t) {
                s.reconstruction =
                    nn::reconstruction_settings::from_json(nlohmann::json::parse(t), "reconstruction_json");
            })
        .def("validate", &training_settings::validate)
        .def("to_json_string", [](const training_settings& s) { return s.to_json().dump(); });

    // The tone/chirp fit's rates from a classifier's settings (bundle.json's decoder
    // settings as JSON text), so Python references and probes take them from the one C++
    // definition instead of writing the formula out again.
    m.def(
        "classifier_chirp_rates",
        [](const std::string& classifier_json, int n_symbols) {
            return nn::classifier_settings::from_json(nlohmann::json::parse(classifier_json), "classifier_json")
                .chirp_rates(n_symbols);
        },
        py::arg("classifier_json"), py::arg("n_symbols"),
        "The tone/chirp fit's chirp rates (cycles per symbol^2, ascending, chirp_bins of them) of a "
        "classifier's settings given as JSON text (bundle.json's decoder settings; missing keys take "
        "their defaults)");

    py::class_<training_result>(m, "training_result", D(training_result))
        .def_readonly("bundle", &training_result::bundle)
        .def_readonly("seconds", &training_result::seconds)
        .def_property_readonly("history_json", [](const training_result& r) { return r.history.dump(); })
        .def_readonly("n_test", &training_result::n_test)
        .def_property_readonly("test_obs",
                               [](const training_result& r) {
                                   const py::ssize_t np = r.n_test ? r.test_obs.size() / r.n_test : 0;
                                   return to_array(r.test_obs, { r.n_test, np });
                               })
        .def_property_readonly("test_probs",
                               [](const training_result& r) {
                                   const py::ssize_t c = r.n_test ? r.test_probs.size() / r.n_test : 0;
                                   return to_array(r.test_probs, { r.n_test, c });
                               })
        .def_property_readonly("test_labels",
                               [](const training_result& r) {
                                   return to_array(r.test_labels, { static_cast<py::ssize_t>(r.test_labels.size()) });
                               })
        .def_property_readonly(
            "test_delay_index",
            [](const training_result& r) {
                return to_array(r.test_delay_index, { static_cast<py::ssize_t>(r.test_delay_index.size()) });
            })
        .def_property_readonly(
            "test_truth_index", [](const training_result& r) {
                return to_array(r.test_truth_index, { static_cast<py::ssize_t>(r.test_truth_index.size()) });
            });

    m.def(
        "train",
        [](const training_settings& s) {
            py::gil_scoped_release nogil;
            return train(s, s.verbose ? &std::cout : nullptr);
        },
        py::arg("settings"), "Train pilots and a decoder; writes a bundle when settings.out_dir is set");
}
