/* gr-sems: Python bindings for classifier_sink and delay_estimator_sink. */
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/classifier_sink.h>
#include <gnuradio/sems/delay_estimator_sink.h>
#include <gnuradio/sems/tags.h>

namespace py = pybind11;

namespace {
const gr::sems::frame_settings default_frame;
}

void bind_sinks(py::module& m)
{
    using gr::sems::classifier_sink;
    using gr::sems::delay_estimator_sink;

    py::class_<classifier_sink, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<classifier_sink>>(
        m, "classifier_sink", "Classifies the target of each frame of pilot observations with a model bundle.")
        .def(py::init(&classifier_sink::make),
             py::arg("bundle_dir"),
             py::arg("n_pilots"),
             py::arg("batch_size") = 32,
             py::arg("threads") = 1,
             py::arg("metrics_period") = 100,
             py::arg("n_symbols") = default_frame.n_symbols,
             py::arg("n_subcarriers") = default_frame.n_subcarriers)
        .def("frames", &classifier_sink::frames)
        .def("frames_scored", &classifier_sink::frames_scored)
        .def("frames_skipped", &classifier_sink::frames_skipped)
        .def("accuracy", &classifier_sink::accuracy)
        .def("confusion", &classifier_sink::confusion, "confusion[truth][predicted] over class_names()")
        .def("class_names", &classifier_sink::class_names)
        .def("reset_metrics", &classifier_sink::reset_metrics)
        .def("batch_size", &classifier_sink::batch_size)
        .def("metrics_period", &classifier_sink::metrics_period)
        .def("set_metrics_period", &classifier_sink::set_metrics_period, py::arg("k"));

    py::class_<delay_estimator_sink,
               gr::sync_block,
               gr::block,
               gr::basic_block,
               std::shared_ptr<delay_estimator_sink>>(
        m,
        "delay_estimator_sink",
        "Estimates the delay of the target of interest of each frame of pilot observations with a model bundle.")
        .def(py::init(&delay_estimator_sink::make),
             py::arg("bundle_dir"),
             py::arg("n_pilots"),
             py::arg("batch_size") = 32,
             py::arg("threads") = 1,
             py::arg("metrics_period") = 100,
             py::arg("n_symbols") = default_frame.n_symbols,
             py::arg("n_subcarriers") = default_frame.n_subcarriers)
        .def("frames", &delay_estimator_sink::frames)
        .def("frames_scored", &delay_estimator_sink::frames_scored)
        .def("frames_skipped", &delay_estimator_sink::frames_skipped)
        .def("mae_index", &delay_estimator_sink::mae_index)
        .def("mae_m", &delay_estimator_sink::mae_m)
        .def("reset_metrics", &delay_estimator_sink::reset_metrics)
        .def("batch_size", &delay_estimator_sink::batch_size)
        .def("metrics_period", &delay_estimator_sink::metrics_period)
        .def("set_metrics_period", &delay_estimator_sink::set_metrics_period, py::arg("k"));
}
