// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for classifier_sink, delay_estimator_sink and position_sink. */
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/learning/sinks/classifier_sink.h>
#include <gnuradio/sems/learning/sinks/delay_estimator_sink.h>
#include <gnuradio/sems/learning/sinks/position_sink.h>
#include <gnuradio/sems/learning/sinks/sink_defaults.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)

namespace py = pybind11;
using gr::sems::sink_defaults;

namespace {

// The constructor's arguments both sinks share, then the sink's own (`extra`, maybe none).
template <typename Sink, typename... Extra>
void bind_make(py::class_<Sink, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<Sink>>& c,
               const char* make_doc,
               Extra... extra)
{
    const gr::sems::frame_settings frame;
    c.def(py::init(&Sink::make),
          py::arg("bundle_dir"),
          py::arg("n_pilots"),
          py::arg("batch_size") = sink_defaults::batch_size,
          py::arg("threads") = sink_defaults::threads,
          py::arg("metrics_period") = sink_defaults::metrics_period,
          py::arg("n_symbols") = frame.n_symbols,
          py::arg("n_subcarriers") = frame.n_subcarriers,
          py::arg("frame") = std::string(),
          extra...,
          make_doc);
}

// The getters both sinks share; each adds its constructor and its own metrics.
template <typename Sink>
py::class_<Sink, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<Sink>>
bind_sink(py::module& m, const char* name, const char* doc)
{
    return py::class_<Sink, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<Sink>>(m, name, doc)
        // Both sink headers document these getters with the same text.
        .def("frames", &Sink::frames, D(classifier_sink, frames))
        .def("frames_scored", &Sink::frames_scored, D(classifier_sink, frames_scored))
        .def("frames_skipped", &Sink::frames_skipped, D(classifier_sink, frames_skipped))
        .def("frames_faulted", &Sink::frames_faulted, D(classifier_sink, frames_faulted))
        .def("reset_metrics", &Sink::reset_metrics, D(classifier_sink, reset_metrics))
        .def("batch_size", &Sink::batch_size, D(classifier_sink, batch_size))
        .def("metrics_period", &Sink::metrics_period, D(classifier_sink, metrics_period))
        .def("set_metrics_period", &Sink::set_metrics_period, D(classifier_sink, set_metrics_period), py::arg("k"));
}

} // namespace

void bind_sinks(py::module& m)
{
    using gr::sems::classifier_sink;
    using gr::sems::delay_estimator_sink;

    // The sinks' defaults, as GRC's blocks must spell them (python/sems/qa/qa_grc_defaults.py).
    py::class_<sink_defaults>(m, "sink_defaults", D(sink_defaults))
        .def_readonly_static("batch_size", &sink_defaults::batch_size, D(sink_defaults, batch_size))
        .def_readonly_static("threads", &sink_defaults::threads, D(sink_defaults, threads))
        .def_readonly_static("metrics_period", &sink_defaults::metrics_period, D(sink_defaults, metrics_period));

    auto classifier = bind_sink<classifier_sink>(m, "classifier_sink", D(classifier_sink));
    bind_make(classifier, D(classifier_sink, make), py::arg("track_idle_s") = 0.0, py::arg("super_frames") = 1,
              py::arg("n_elements") = 1, py::arg("array") = std::string());
    classifier.def("accuracy", &classifier_sink::accuracy, D(classifier_sink, accuracy))
        .def("confusion", &classifier_sink::confusion, D(classifier_sink, confusion))
        .def("class_names", &classifier_sink::class_names, D(classifier_sink, class_names))
        .def("track_mode", &classifier_sink::track_mode, D(classifier_sink, track_mode))
        .def("tracks_started", &classifier_sink::tracks_started, D(classifier_sink, tracks_started))
        .def("track_gaps", &classifier_sink::track_gaps, D(classifier_sink, track_gaps))
        .def("n_elements", &classifier_sink::n_elements, D(classifier_sink, n_elements));

    auto delay = bind_sink<delay_estimator_sink>(m, "delay_estimator_sink", D(delay_estimator_sink));
    bind_make(delay, D(delay_estimator_sink, make));
    delay.def("mae_index", &delay_estimator_sink::mae_index, D(delay_estimator_sink, mae_index))
        .def("mae_m", &delay_estimator_sink::mae_m, D(delay_estimator_sink, mae_m));

    using gr::sems::position_sink;
    auto position = bind_sink<position_sink>(m, "position_sink", D(position_sink));
    position
        .def(py::init(&position_sink::make),
             py::arg("bundle_dir"),
             py::arg("n_elements"),
             py::arg("n_pilots"),
             py::arg("batch_size") = sink_defaults::batch_size,
             py::arg("threads") = sink_defaults::threads,
             py::arg("metrics_period") = sink_defaults::metrics_period,
             py::arg("frame") = std::string(),
             D(position_sink, make))
        .def("mae_index", &position_sink::mae_index, D(position_sink, mae_index))
        .def("mae_m", &position_sink::mae_m, D(position_sink, mae_m))
        .def("frames_scored_azimuth", &position_sink::frames_scored_azimuth, D(position_sink, frames_scored_azimuth))
        .def("rmse_azimuth_rad", &position_sink::rmse_azimuth_rad, D(position_sink, rmse_azimuth_rad));
}
