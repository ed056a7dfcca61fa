// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for classifier_sink and delay_estimator_sink. */
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/learning/classifier_sink.h>
#include <gnuradio/sems/learning/delay_estimator_sink.h>
#include <gnuradio/sems/learning/sink_defaults.h>

namespace py = pybind11;
using gr::sems::sink_defaults;

namespace {

// The constructor and the getters both sinks share; each adds its own metrics.
template <typename Sink>
py::class_<Sink, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<Sink>>
bind_sink(py::module& m, const char* name, const char* doc)
{
    const gr::sems::frame_settings frame;
    return py::class_<Sink, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<Sink>>(m, name, doc)
        .def(py::init(&Sink::make),
             py::arg("bundle_dir"),
             py::arg("n_pilots"),
             py::arg("batch_size") = sink_defaults::batch_size,
             py::arg("threads") = sink_defaults::threads,
             py::arg("metrics_period") = sink_defaults::metrics_period,
             py::arg("n_symbols") = frame.n_symbols,
             py::arg("n_subcarriers") = frame.n_subcarriers)
        .def("frames", &Sink::frames)
        .def("frames_scored", &Sink::frames_scored)
        .def("frames_skipped", &Sink::frames_skipped)
        .def("frames_faulted", &Sink::frames_faulted)
        .def("reset_metrics", &Sink::reset_metrics)
        .def("batch_size", &Sink::batch_size)
        .def("metrics_period", &Sink::metrics_period)
        .def("set_metrics_period", &Sink::set_metrics_period, py::arg("k"));
}

} // namespace

void bind_sinks(py::module& m)
{
    using gr::sems::classifier_sink;
    using gr::sems::delay_estimator_sink;

    bind_sink<classifier_sink>(
        m, "classifier_sink", "Classifies the target of each frame of pilot observations with a model bundle.")
        .def("accuracy", &classifier_sink::accuracy)
        .def("confusion", &classifier_sink::confusion, "confusion[truth][predicted] over class_names()")
        .def("class_names", &classifier_sink::class_names);

    bind_sink<delay_estimator_sink>(
        m,
        "delay_estimator_sink",
        "Estimates the delay of the target of interest of each frame of pilot observations with a model bundle.")
        .def("mae_index", &delay_estimator_sink::mae_index)
        .def("mae_m", &delay_estimator_sink::mae_m);
}
