// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings for the radio front end's settings (core/radio/front_end.h), the
 * oscillator's phase noise (core/radio/phase_noise.h) and the phase_noise_source block. */
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <gnuradio/sems/blocks/phase_noise_source.h>
#include <gnuradio/sems/core/radio/front_end.h>
#include <gnuradio/sems/core/radio/front_end_frame.h>
#include <gnuradio/sems/core/radio/phase_noise.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)

namespace py = pybind11;
using namespace gr::sems;

void bind_front_end(py::module& m)
{
    py::enum_<oscillator_kind>(m, "oscillator_kind", D(oscillator_kind))
        .value("shared", oscillator_kind::shared)
        .value("separate", oscillator_kind::separate);
    m.def("oscillator_name", &oscillator_name, py::arg("kind"), D(oscillator_name));
    m.def("oscillator_from_name", &oscillator_from_name, py::arg("name"), D(oscillator_from_name));
    py::enum_<element_oscillator_kind>(m, "element_oscillator_kind", D(element_oscillator_kind))
        .value("shared", element_oscillator_kind::shared)
        .value("own", element_oscillator_kind::own);
    m.def("element_oscillator_name", &element_oscillator_name, py::arg("kind"), D(element_oscillator_name));
    m.def("element_oscillator_from_name", &element_oscillator_from_name, py::arg("name"),
          D(element_oscillator_from_name));

    using fe = front_end_settings;
    py::class_<fe>(m, "front_end_settings", D(front_end_settings))
        .def(py::init<>())
        .def_readwrite("leakage_db", &fe::leakage_db)
        .def_readwrite("leakage_taps", &fe::leakage_taps)
        .def_readwrite("leakage_decay_samples", &fe::leakage_decay_samples)
        .def_readwrite("phase_noise_dbc_hz", &fe::phase_noise_dbc_hz)
        .def_readwrite("phase_noise_offset_hz", &fe::phase_noise_offset_hz)
        .def_readwrite("oscillator", &fe::oscillator)
        .def_readwrite("element_oscillators", &fe::element_oscillators)
        .def_readwrite("iq_gain_db", &fe::iq_gain_db)
        .def_readwrite("iq_phase_deg", &fe::iq_phase_deg)
        .def_readwrite("dc_offset_db", &fe::dc_offset_db)
        .def_readwrite("adc_enob", &fe::adc_enob)
        .def_readwrite("adc_full_scale_rms", &fe::adc_full_scale_rms)
        .def_readwrite("cfo_hz", &fe::cfo_hz)
        .def_readwrite("sfo_ppm", &fe::sfo_ppm)
        .def("validate", &fe::validate, D(front_end_settings, validate))
        .def("is_ideal", &fe::is_ideal, D(front_end_settings, is_ideal))
        .def("phase_diffusion", &fe::phase_diffusion, D(front_end_settings, phase_diffusion))
        .def("leakage_response", &fe::leakage_response, D(front_end_settings, leakage_response))
        .def("iq_mu", &fe::iq_mu, D(front_end_settings, iq_mu))
        .def("iq_nu", &fe::iq_nu, D(front_end_settings, iq_nu))
        .def("dc_amplitude", &fe::dc_amplitude, py::arg("tx_power"), py::arg("noise_variance"),
             D(front_end_settings, dc_amplitude))
        .def("expected_rms", &fe::expected_rms, py::arg("tx_power"), py::arg("noise_variance"),
             D(front_end_settings, expected_rms))
        .def("full_scale", &fe::full_scale, py::arg("tx_power"), py::arg("noise_variance"),
             D(front_end_settings, full_scale))
        .def("to_json_string", &fe::to_json_string, D(front_end_settings, to_json_string))
        .def_static("parse", &fe::parse, py::arg("json_text"), py::arg("source") = "radio text",
                    D(front_end_settings, parse))
        .def_static("load", &fe::load, py::arg("path"), D(front_end_settings, load))
        .def("save", &fe::save, py::arg("path"), D(front_end_settings, save))
        .def("__eq__", &fe::operator==);

    py::class_<front_end_frame>(m, "front_end_frame", D(front_end_frame))
        .def(py::init<const frame_settings&, const front_end_settings&>(), py::arg("frame"), py::arg("radio"),
             D(front_end_frame, front_end_frame))
        .def(
            "observe",
            [](front_end_frame& f,
               py::array_t<gr_complex, py::array::c_style | py::array::forcecast> h,
               double delay_index,
               double noise_variance,
               uint64_t seed) {
                const auto& fs = f.frame();
                if (h.ndim() != 2 || h.shape(0) != fs.n_symbols || h.shape(1) != fs.n_subcarriers)
                    throw std::invalid_argument("front_end_frame.observe: h must be the frame's " +
                                                std::to_string(fs.n_symbols) + " x " +
                                                std::to_string(fs.n_subcarriers) + " grid");
                py::array_t<gr_complex> out({ h.shape(0), h.shape(1) });
                f.observe(h.data(), delay_index, noise_variance, seed, out.mutable_data());
                return out;
            },
            py::arg("h"), py::arg("delay_index"), py::arg("noise_variance"), py::arg("seed"),
            D(front_end_frame, observe))
        .def("tx_power", &front_end_frame::tx_power, D(front_end_frame, tx_power))
        .def("cancels", &front_end_frame::cancels, D(front_end_frame, cancels))
        .def("frame", &front_end_frame::frame, D(front_end_frame, frame));

    m.def("phase_diffusion_from_dbc", &phase_diffusion_from_dbc, py::arg("dbc_hz"), py::arg("offset_hz"),
          D(phase_diffusion_from_dbc));
    m.def("phase_noise_dbc", &phase_noise_dbc, py::arg("diffusion_rad2_per_s"), py::arg("offset_hz"),
          D(phase_noise_dbc));

    py::class_<phase_noise_process>(m, "phase_noise_process", D(phase_noise_process))
        .def(py::init<double, double, uint64_t>(), py::arg("diffusion_rad2_per_s"), py::arg("sample_rate_hz"),
             py::arg("seed") = 0, D(phase_noise_process, phase_noise_process))
        .def("next", &phase_noise_process::next, D(phase_noise_process, next))
        .def(
            "phases",
            [](phase_noise_process& p, size_t count) {
                py::array_t<double> out(count);
                auto* o = out.mutable_data();
                for (size_t i = 0; i < count; ++i)
                    o[i] = p.next();
                return out;
            },
            py::arg("count"),
            "The next `count` phases φ[n] in rad (float64), as next() draws them.")
        .def(
            "generate",
            [](phase_noise_process& p, size_t count) {
                py::array_t<gr_complex> out(count);
                p.generate(out.mutable_data(), count);
                return out;
            },
            py::arg("count"),
            D(phase_noise_process, generate))
        .def("increment_variance", &phase_noise_process::increment_variance,
             D(phase_noise_process, increment_variance))
        .def("diffusion", &phase_noise_process::diffusion, D(phase_noise_process, diffusion))
        .def("samples", &phase_noise_process::samples, D(phase_noise_process, samples));

    py::class_<phase_noise_source, gr::sync_block, gr::block, gr::basic_block, std::shared_ptr<phase_noise_source>>(
        m, "phase_noise_source", D(phase_noise_source))
        .def(py::init(&phase_noise_source::make),
             py::arg("sample_rate_hz") = 30e6,
             py::arg("dbc_hz") = -90.0,
             py::arg("offset_hz") = 100e3,
             py::arg("seed") = 0,
             D(phase_noise_source, make))
        .def("diffusion", &phase_noise_source::diffusion, D(phase_noise_source, diffusion))
        .def("samples", &phase_noise_source::samples, D(phase_noise_source, samples));
}
