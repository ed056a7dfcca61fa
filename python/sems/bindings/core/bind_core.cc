// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Python bindings of the core library: keys, frame settings, pilot masks,
 * target classes, scenes and the channel model (H as numpy arrays). JSON crosses the
 * boundary as text (to_json_string / parse), the same text the files hold.
 */
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/frame/super_frame_mask.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sems/core/common/tags.h>
#include <gnuradio/sems/core/scene/target_class.h>

#include "sems_pydoc.h" // D(...): docstrings from the headers' Doxygen (docs/doxygen_pydoc.py)
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <cmath>

namespace py = pybind11;
using namespace gr::sems;

namespace {

py::dict truth_dict(const frame_truth& t)
{
    py::dict d;
    d[keys::frame] = t.frame;
    d[keys::class_id] = t.class_id;
    d[keys::class_name] = t.class_name;
    d[keys::delay_s] = t.delay_s;
    d[keys::delay_index] = t.delay_index;
    d[keys::range_m] = t.range_m;
    d[keys::velocity_mps] = t.velocity_mps;
    d[keys::snr_db] = t.snr_db;
    if (!std::isnan(t.link_snr_db)) // a scene with a link budget: the radar equation's SNR (frame_truth::link_snr_db)
        d[keys::link_snr_db] = t.link_snr_db;
    if (!std::isnan(t.azimuth_rad)) { // a scene with an array: the line of sight's direction
        d[keys::azimuth_rad] = t.azimuth_rad;
        d[keys::elevation_rad] = t.elevation_rad;
    }
    d[keys::n_paths] = t.n_paths;
    d[keys::micro_motion] = t.micro_motion;
    d[keys::track_id] = t.track_id;
    d[keys::frame_in_track] = t.frame_in_track;
    return d;
}

void bind_keys(py::module& m)
{
    auto k = m.def_submodule("keys", "Tag, dictionary and port keys (include/gnuradio/sems/core/common/tags.h)");
    k.attr("frame_tag") = keys::frame_tag;
    k.attr("truth_tag") = keys::truth_tag;
    k.attr("frame") = keys::frame;
    k.attr("class_id") = keys::class_id;
    k.attr("class_name") = keys::class_name;
    k.attr("delay_s") = keys::delay_s;
    k.attr("delay_index") = keys::delay_index;
    k.attr("range_m") = keys::range_m;
    k.attr("velocity_mps") = keys::velocity_mps;
    k.attr("snr_db") = keys::snr_db;
    k.attr("link_snr_db") = keys::link_snr_db;
    k.attr("azimuth_rad") = keys::azimuth_rad;
    k.attr("elevation_rad") = keys::elevation_rad;
    k.attr("n_paths") = keys::n_paths;
    k.attr("micro_motion") = keys::micro_motion;
    k.attr("micro_motion_params") = keys::micro_motion_params;
    k.attr("class_library") = keys::class_library;
    k.attr("track_id") = keys::track_id;
    k.attr("frame_in_track") = keys::frame_in_track;
    k.attr("track_frames") = keys::track_frames;
    k.attr("tracks_started") = keys::tracks_started;
    k.attr("track_gaps") = keys::track_gaps;
    k.attr("track_idle_resets") = keys::track_idle_resets;
    k.attr("label") = keys::label;
    k.attr("probs") = keys::probs;
    k.attr("truth") = keys::truth;
    k.attr("correct") = keys::correct;
    k.attr("abs_error_index") = keys::abs_error_index;
    k.attr("abs_error_azimuth_rad") = keys::abs_error_azimuth_rad;
    k.attr("frames") = keys::frames;
    k.attr("frames_scored") = keys::frames_scored;
    k.attr("frames_skipped") = keys::frames_skipped;
    k.attr("frames_faulted") = keys::frames_faulted;
    k.attr("accuracy") = keys::accuracy;
    k.attr("mae_index") = keys::mae_index;
    k.attr("mae_m") = keys::mae_m;
    k.attr("rmse_azimuth_rad") = keys::rmse_azimuth_rad;
    k.attr("frames_scored_azimuth") = keys::frames_scored_azimuth;
    k.attr("confusion") = keys::confusion;
    k.attr("result_port") = keys::result_port;
    k.attr("metrics_port") = keys::metrics_port;
    k.attr("sync_offset") = keys::sync_offset;
    k.attr("sync_metric") = keys::sync_metric;
    k.attr("sync_failures") = keys::sync_failures;
    k.attr("sync_port") = keys::sync_port;
}

void bind_frame_settings(py::module& m)
{
    py::class_<frame_settings>(m, "frame_settings", D(frame_settings))
        .def(py::init([](int n_symbols, int n_subcarriers, double bandwidth_hz, double carrier_hz,
                         double symbol_interval_s, int cp_len, const std::vector<int>& guard_subcarriers) {
                 frame_settings fs{ n_symbols,  n_subcarriers,     bandwidth_hz, carrier_hz,
                                    symbol_interval_s, cp_len, guard_subcarriers };
                 fs.validate();
                 return fs;
             }),
             py::arg("n_symbols") = frame_settings{}.n_symbols,
             py::arg("n_subcarriers") = frame_settings{}.n_subcarriers,
             py::arg("bandwidth_hz") = frame_settings{}.bandwidth_hz,
             py::arg("carrier_hz") = frame_settings{}.carrier_hz,
             py::arg("symbol_interval_s") = frame_settings{}.symbol_interval_s,
             py::arg("cp_len") = frame_settings{}.cp_len,
             py::arg("guard_subcarriers") = std::vector<int>{})
        .def_readwrite("n_symbols", &frame_settings::n_symbols)
        .def_readwrite("n_subcarriers", &frame_settings::n_subcarriers)
        .def_readwrite("bandwidth_hz", &frame_settings::bandwidth_hz)
        .def_readwrite("carrier_hz", &frame_settings::carrier_hz)
        .def_readwrite("symbol_interval_s", &frame_settings::symbol_interval_s)
        .def_readwrite("cp_len", &frame_settings::cp_len)
        .def_readwrite("guard_subcarriers", &frame_settings::guard_subcarriers)
        .def("subcarrier_spacing_hz", &frame_settings::subcarrier_spacing_hz)
        .def("wavelength_m", &frame_settings::wavelength_m)
        .def("grid_size", &frame_settings::grid_size)
        .def("delay_resolution_s", &frame_settings::delay_resolution_s)
        .def("range_per_delay_index_m", &frame_settings::range_per_delay_index_m)
        .def("max_delay_s", &frame_settings::max_delay_s)
        .def("max_range_m", &frame_settings::max_range_m)
        .def("doppler_resolution_hz", &frame_settings::doppler_resolution_hz)
        .def("max_doppler_hz", &frame_settings::max_doppler_hz)
        .def("max_speed_mps", &frame_settings::max_speed_mps)
        .def("delay_from_range", &frame_settings::delay_from_range)
        .def("delay_index", &frame_settings::delay_index)
        .def("doppler_from_velocity", &frame_settings::doppler_from_velocity)
        .def("validate", &frame_settings::validate)
        .def("to_json_string", [](const frame_settings& fs) { return fs.to_json().dump(); })
        .def("is_guard", &frame_settings::is_guard, py::arg("m"))
        .def("usable_subcarriers", &frame_settings::usable_subcarriers)
        .def("usable_elements", &frame_settings::usable_elements)
        .def(
            "first_difference",
            [](const frame_settings& a, const frame_settings& b) -> py::object {
                const auto d = a.first_difference(b);
                if (!d)
                    return py::none();
                return py::make_tuple(d->field, d->first, d->second);
            },
            py::arg("other"),
            "The first field in which two frames differ, as (field, this value, other value); None when equal.")
        .def("__eq__", &frame_settings::operator==);

    py::class_<frame_file>(m, "frame_file", D(frame_file))
        .def_readwrite("name", &frame_file::name)
        .def_readwrite("description", &frame_file::description)
        .def_readwrite("classes", &frame_file::classes)
        .def_readwrite("array", &frame_file::array)
        .def_readwrite("frame", &frame_file::frame)
        .def_static("find", &frame_file::find, py::arg("name_or_path"), D(frame_file, find))
        .def_static("load", &frame_file::load, py::arg("path"), D(frame_file, load))
        .def_static(
            "from_json_string",
            [](const std::string& text, const std::string& source) {
                return frame_file::from_json(nlohmann::json::parse(text), source);
            },
            py::arg("text"),
            py::arg("source") = "frame file text",
            "Reads a frame file from its JSON text (`source` names it in errors).")
        .def("to_json_string", [](const frame_file& f) { return f.to_json().dump(); });
}

void bind_pilot_mask(py::module& m)
{
    py::class_<pilot_mask>(m, "pilot_mask", D(pilot_mask))
        .def(py::init([](int n_symbols, int n_subcarriers, const std::vector<std::pair<int, int>>& pilots,
                         gr_complex pilot_symbol, std::vector<double> power, std::vector<double> phases) {
                 std::vector<pilot_position> pos;
                 for (const auto& p : pilots)
                     pos.push_back({ p.first, p.second });
                 return pilot_mask(n_symbols, n_subcarriers, pos, pilot_symbol, { { "kind", "explicit" } },
                                   "pilot mask", std::move(power), std::move(phases));
             }),
             py::arg("n_symbols"), py::arg("n_subcarriers"), py::arg("pilots"),
             py::arg("pilot_symbol") = gr_complex(1.0f, 0.0f), py::arg("power") = std::vector<double>{},
             py::arg("phases") = std::vector<double>{})
        .def_static("uniform", &pilot_mask::uniform, py::arg("n_symbols"), py::arg("n_subcarriers"), py::arg("count"))
        .def_static("random", &pilot_mask::random, py::arg("n_symbols"), py::arg("n_subcarriers"), py::arg("count"),
                    py::arg("seed"))
        .def_static("doppler", &pilot_mask::doppler, py::arg("n_symbols"), py::arg("n_subcarriers"), py::arg("count"))
        .def_static("from_pattern",
                    py::overload_cast<const std::string&, int, int, int, uint64_t>(&pilot_mask::from_pattern),
                    py::arg("pattern"), py::arg("n_symbols"), py::arg("n_subcarriers"), py::arg("count"),
                    py::arg("seed") = 0)
        .def_static("from_pattern",
                    py::overload_cast<const std::string&, const frame_settings&, int, uint64_t>(
                        &pilot_mask::from_pattern),
                    py::arg("pattern"), py::arg("frame"), py::arg("count"), py::arg("seed") = 0)
        .def("check_frame", &pilot_mask::check_frame, py::arg("frame"), py::arg("who") = "pilot mask")
        .def_static("load", &pilot_mask::load, py::arg("path"))
        .def_static("parse", &pilot_mask::parse, py::arg("json_text"), py::arg("source") = "pilot mask text")
        .def("save", &pilot_mask::save, py::arg("path"))
        .def("to_json_string", &pilot_mask::to_json_string)
        .def("n_symbols", &pilot_mask::n_symbols)
        .def("n_subcarriers", &pilot_mask::n_subcarriers)
        .def("size", &pilot_mask::size)
        .def("__len__", &pilot_mask::size)
        .def("pilot_symbol", &pilot_mask::pilot_symbol)
        .def("power", &pilot_mask::power)
        .def("equal_power", &pilot_mask::equal_power)
        .def("phases", &pilot_mask::phases)
        .def("zero_phases", &pilot_mask::zero_phases)
        .def("phase_sequence", &pilot_mask::phase_sequence)
        .def("with_phases",
             py::overload_cast<const std::string&, const std::string&>(&pilot_mask::with_phases, py::const_),
             py::arg("sequence"), py::arg("source") = "pilot phases")
        .def("with_phases",
             py::overload_cast<std::vector<double>, const std::string&>(&pilot_mask::with_phases, py::const_),
             py::arg("phases"), py::arg("source") = "pilot phases")
        .def_static("phase_sequence_names", &pilot_mask::phase_sequence_names)
        .def_static("newman_phases", &pilot_mask::newman_phases, py::arg("count"))
        .def("transmitted_pilot", &pilot_mask::transmitted_pilot, py::arg("k"))
        .def("noise_scale", &pilot_mask::noise_scale, py::arg("k"))
        .def("positions",
             [](const pilot_mask& mk) {
                 std::vector<std::pair<int, int>> out;
                 for (const auto& p : mk.positions())
                     out.emplace_back(p.n, p.m);
                 return out;
             })
        .def("flat_indices", &pilot_mask::flat_indices)
        .def("dense",
             [](const pilot_mask& mk) {
                 py::array_t<uint8_t> a({ mk.n_symbols(), mk.n_subcarriers() });
                 auto d = mk.dense();
                 std::copy(d.begin(), d.end(), a.mutable_data());
                 return a;
             })
        .def("carrier_lists", &pilot_mask::carrier_lists)
        .def("pilot_symbol_lists", &pilot_mask::pilot_symbol_lists)
        .def("__eq__", &pilot_mask::operator==);

    py::class_<super_frame_mask>(m, "super_frame_mask", D(super_frame_mask))
        .def(py::init<pilot_mask>(), py::arg("mask"))
        .def(py::init([](std::vector<pilot_mask> sets, const std::string& origin_json, const std::string& source) {
                 return super_frame_mask(std::move(sets), nlohmann::json::parse(origin_json), source);
             }),
             py::arg("sets"), py::arg("origin_json") = R"({"kind": "explicit"})",
             py::arg("source") = "super-frame mask")
        .def_static("repeated", &super_frame_mask::repeated, D(super_frame_mask, repeated), py::arg("mask"),
                    py::arg("n_frames"))
        .def_static("load", &super_frame_mask::load, D(super_frame_mask, load), py::arg("path"))
        .def_static("parse", &super_frame_mask::parse, D(super_frame_mask, parse), py::arg("json_text"),
                    py::arg("source") = "pilot mask text")
        .def("save", &super_frame_mask::save, D(super_frame_mask, save), py::arg("path"))
        .def("to_json_string", &super_frame_mask::to_json_string, D(super_frame_mask, to_json_string))
        .def("n_frames", &super_frame_mask::n_frames, D(super_frame_mask, n_frames))
        .def("n_symbols", &super_frame_mask::n_symbols, D(super_frame_mask, n_symbols))
        .def("n_subcarriers", &super_frame_mask::n_subcarriers, D(super_frame_mask, n_subcarriers))
        .def("pilots_per_frame", &super_frame_mask::pilots_per_frame, D(super_frame_mask, pilots_per_frame))
        .def("sets", &super_frame_mask::sets, D(super_frame_mask, sets))
        .def("set", &super_frame_mask::set, D(super_frame_mask, set), py::arg("f"), py::return_value_policy::copy)
        .def("for_frame", &super_frame_mask::for_frame, D(super_frame_mask, for_frame), py::arg("frame_index"),
             py::return_value_policy::copy)
        .def("check_frame", &super_frame_mask::check_frame, D(super_frame_mask, check_frame), py::arg("frame"),
             py::arg("who") = "super-frame mask")
        .def("check_shape", &super_frame_mask::check_shape, D(super_frame_mask, check_shape), py::arg("n_frames"),
             py::arg("pilots_per_frame"), py::arg("who"), py::arg("expected"))
        .def("__len__", &super_frame_mask::n_frames)
        .def("__eq__", &super_frame_mask::operator==);
}

void bind_scene(py::module& m)
{
    py::enum_<target_class>(m, "target_class", D(target_class))
        .value("pedestrian", target_class::pedestrian)
        .value("car", target_class::car)
        .value("drone", target_class::drone);
    // Class ids beyond the paper's three (another library's classes) pass as ints.
    py::implicitly_convertible<int, target_class>();
    m.def("class_names", &class_names, D(class_names));
    m.def("class_from_name", &class_from_name, D(class_from_name), py::arg("name"));

    py::enum_<fading_kind>(m, "fading_kind", D(fading_kind)).value("rayleigh", fading_kind::rayleigh).value("none", fading_kind::none);

    py::class_<micro_doppler>(m, "micro_doppler", D(micro_doppler))
        .def(py::init([](double rate_hz, double amplitude_m, double phase_rad) {
                 return micro_doppler{ rate_hz, amplitude_m, phase_rad };
             }),
             py::arg("rate_hz"), py::arg("amplitude_m"), py::arg("phase_rad") = 0.0)
        .def_readwrite("rate_hz", &micro_doppler::rate_hz)
        .def_readwrite("amplitude_m", &micro_doppler::amplitude_m)
        .def_readwrite("phase_rad", &micro_doppler::phase_rad);

    py::class_<path_spec>(m, "path_spec", D(path_spec))
        .def(py::init([](double excess_range_m, double power) { return path_spec{ excess_range_m, power }; }),
             py::arg("excess_range_m") = 0.0, py::arg("power") = 1.0)
        .def_readwrite("excess_range_m", &path_spec::excess_range_m)
        .def_readwrite("power", &path_spec::power);

    py::class_<target_spec>(m, "target_spec", D(target_spec))
        .def(py::init([](target_class cls, double range_m, double velocity_mps, std::optional<micro_doppler> md,
                         double power, std::vector<path_spec> paths, double speed_mps, double heading_rad,
                         std::optional<micro_motion> motion, double rcs_dbsm, double azimuth_rad, double elevation_rad) {
                 return target_spec{ cls,    range_m, velocity_mps, speed_mps, heading_rad, md,
                                     motion, power,   paths,        rcs_dbsm,  azimuth_rad, elevation_rad };
             }),
             py::arg("cls"), py::arg("range_m"), py::arg("velocity_mps"), py::arg("md") = py::none(),
             py::arg("power") = 1.0, py::arg("paths") = std::vector<path_spec>{ path_spec{} },
             py::arg("speed_mps") = target_spec{}.speed_mps, py::arg("heading_rad") = target_spec{}.heading_rad,
             py::arg("motion") = py::none(), py::arg("rcs_dbsm") = target_spec{}.rcs_dbsm,
             py::arg("azimuth_rad") = 0.0, py::arg("elevation_rad") = 0.0)
        .def_readwrite("cls", &target_spec::cls)
        .def_readwrite("range_m", &target_spec::range_m)
        .def_readwrite("velocity_mps", &target_spec::velocity_mps)
        .def_readwrite("speed_mps", &target_spec::speed_mps, D(target_spec, speed_mps))
        .def_readwrite("heading_rad", &target_spec::heading_rad, D(target_spec, heading_rad))
        .def_readwrite("md", &target_spec::md)
        .def_readwrite("motion", &target_spec::motion, D(target_spec, motion))
        .def_readwrite("power", &target_spec::power)
        .def_readwrite("paths", &target_spec::paths)
        .def_readwrite("rcs_dbsm", &target_spec::rcs_dbsm, D(target_spec, rcs_dbsm))
        .def_readwrite("azimuth_rad", &target_spec::azimuth_rad, D(target_spec, azimuth_rad))
        .def_readwrite("elevation_rad", &target_spec::elevation_rad, D(target_spec, elevation_rad));

    py::class_<link_budget>(m, "link_budget", D(link_budget))
        .def(py::init<>())
        .def_readwrite("tx_power_dbm", &link_budget::tx_power_dbm, D(link_budget, tx_power_dbm))
        .def_readwrite("tx_gain_dbi", &link_budget::tx_gain_dbi, D(link_budget, tx_gain_dbi))
        .def_readwrite("rx_gain_dbi", &link_budget::rx_gain_dbi, D(link_budget, rx_gain_dbi))
        .def_readwrite("noise_figure_db", &link_budget::noise_figure_db, D(link_budget, noise_figure_db))
        .def_readwrite("system_loss_db", &link_budget::system_loss_db, D(link_budget, system_loss_db))
        .def_readwrite("noise_temperature_k", &link_budget::noise_temperature_k, D(link_budget, noise_temperature_k))
        .def("snr_db", &link_budget::snr_db, D(link_budget, snr_db), py::arg("fs"), py::arg("range_m"), py::arg("rcs_dbsm"));
    m.def("target_speed_heading", &target_speed_heading, D(target_speed_heading), py::arg("t"));

    py::enum_<track_bound>(m, "track_bound", D(track_bound))
        .value("restart", track_bound::restart)
        .value("reflect", track_bound::reflect);
    py::class_<track_spec>(m, "track_spec", D(track_spec))
        .def(py::init([](double range_min_m, double range_max_m, track_bound at_bound) {
                 return track_spec{ range_min_m, range_max_m, at_bound };
             }),
             py::arg("range_min_m") = track_spec{}.range_min_m, py::arg("range_max_m") = track_spec{}.range_max_m,
             py::arg("at_bound") = track_spec{}.at_bound)
        .def_readwrite("range_min_m", &track_spec::range_min_m, D(track_spec, range_min_m))
        .def_readwrite("range_max_m", &track_spec::range_max_m, D(track_spec, range_max_m))
        .def_readwrite("at_bound", &track_spec::at_bound, D(track_spec, at_bound));

    py::class_<clutter_spec>(m, "clutter_spec", D(clutter_spec))
        .def(py::init([](double csr_db, int n_paths, double range_min_m, double range_max_m,
                         std::vector<double> ranges_m, std::vector<double> azimuths_rad) {
                 return clutter_spec{ csr_db, n_paths, range_min_m, range_max_m, ranges_m, azimuths_rad };
             }),
             py::arg("csr_db"), py::arg("n_paths") = clutter_spec{}.n_paths,
             py::arg("range_min_m") = clutter_spec{}.range_min_m, py::arg("range_max_m") = clutter_spec{}.range_max_m,
             py::arg("ranges_m") = std::vector<double>{}, py::arg("azimuths_rad") = std::vector<double>{})
        .def_readwrite("csr_db", &clutter_spec::csr_db)
        .def_readwrite("n_paths", &clutter_spec::n_paths)
        .def_readwrite("azimuths_rad", &clutter_spec::azimuths_rad, D(clutter_spec, azimuths_rad));

    py::enum_<heading_kind>(m, "heading_kind")
        .value("approaching", heading_kind::approaching)
        .value("any", heading_kind::any);
    m.def("heading_name", &heading_name, py::arg("heading"));
    m.def("heading_from_name", &heading_from_name, py::arg("name"));

    py::enum_<gain_coherence>(m, "gain_coherence", D(gain_coherence))
        .value("frame", gain_coherence::frame)
        .value("track", gain_coherence::track)
        .value("gauss_markov", gain_coherence::gauss_markov);
    m.def("gain_coherence_name", &gain_coherence_name, D(gain_coherence_name), py::arg("c"));
    m.def("gain_coherence_from_name", &gain_coherence_from_name, D(gain_coherence_from_name), py::arg("name"));

    py::enum_<track_motion>(m, "track_motion", D(track_motion))
        .value("radial", track_motion::radial)
        .value("straight", track_motion::straight);
    m.def("track_motion_name", &track_motion_name, D(track_motion_name), py::arg("m"));
    m.def("track_motion_from_name", &track_motion_from_name, D(track_motion_from_name), py::arg("name"));

    py::class_<track_draw_spec>(m, "track_draw_spec", D(track_draw_spec))
        .def(py::init([](int frames_min, int frames_max, gain_coherence gains, double coherence_time_s,
                         track_motion motion) {
                 return track_draw_spec{ frames_min, frames_max, gains, coherence_time_s, motion };
             }),
             py::arg("frames_min") = track_draw_spec{}.frames_min, py::arg("frames_max") = track_draw_spec{}.frames_max,
             py::arg("gains") = track_draw_spec{}.gains,
             py::arg("coherence_time_s") = track_draw_spec{}.coherence_time_s,
             py::arg("motion") = track_draw_spec{}.motion)
        .def_readwrite("frames_min", &track_draw_spec::frames_min, D(track_draw_spec, frames_min))
        .def_readwrite("frames_max", &track_draw_spec::frames_max, D(track_draw_spec, frames_max))
        .def_readwrite("gains", &track_draw_spec::gains, D(track_draw_spec, gains))
        .def_readwrite("coherence_time_s", &track_draw_spec::coherence_time_s, D(track_draw_spec, coherence_time_s))
        .def_readwrite("motion", &track_draw_spec::motion, D(track_draw_spec, motion));

    py::class_<random_spec>(m, "random_spec", D(random_spec))
        .def(py::init([](std::vector<target_class> classes, int n_targets, int paths_per_target,
                         double excess_min, double excess_max, double decay_db, bool md, heading_kind heading,
                         std::optional<track_draw_spec> tracks) {
                 return random_spec{ classes, n_targets, paths_per_target, excess_min, excess_max, decay_db, md,
                                     heading, tracks };
             }),
             py::arg("classes") = random_spec{}.classes, py::arg("n_targets") = random_spec{}.n_targets,
             py::arg("paths_per_target") = random_spec{}.paths_per_target,
             py::arg("excess_range_min_m") = random_spec{}.excess_range_min_m,
             py::arg("excess_range_max_m") = random_spec{}.excess_range_max_m,
             py::arg("path_power_decay_db") = random_spec{}.path_power_decay_db,
             py::arg("micro_doppler") = random_spec{}.micro_doppler,
             py::arg("heading") = random_spec{}.heading, py::arg("tracks") = py::none())
        .def_readwrite("classes", &random_spec::classes)
        .def_readwrite("n_targets", &random_spec::n_targets)
        .def_readwrite("paths_per_target", &random_spec::paths_per_target)
        .def_readwrite("micro_doppler", &random_spec::micro_doppler)
        .def_readwrite("heading", &random_spec::heading)
        .def_readwrite("tracks", &random_spec::tracks, D(random_spec, tracks))
        .def_readwrite("azimuth_min_rad", &random_spec::azimuth_min_rad, D(random_spec, azimuth_min_rad))
        .def_readwrite("azimuth_max_rad", &random_spec::azimuth_max_rad, D(random_spec, azimuth_max_rad));

    py::class_<scene>(m, "scene", D(scene))
        .def_static(
            "fixed",
            [](std::vector<target_spec> targets, std::optional<clutter_spec> clutter, int toi, fading_kind fading,
               std::shared_ptr<class_library> library) { return scene::fixed(targets, clutter, toi, fading, library); },
            D(scene, fixed), py::arg("targets"), py::arg("clutter") = py::none(), py::arg("target_of_interest") = 0,
            py::arg("fading") = fading_kind::rayleigh, py::arg("library") = py::none())
        .def_static(
            "random",
            [](random_spec spec, std::optional<clutter_spec> clutter, fading_kind fading,
               std::shared_ptr<class_library> library) { return scene::random(spec, clutter, fading, library); },
            D(scene, random), py::arg("spec") = random_spec{}, py::arg("clutter") = py::none(),
            py::arg("fading") = fading_kind::rayleigh, py::arg("library") = py::none())
        .def_static("load", &scene::load, py::arg("path"))
        .def_static("parse", &scene::parse, py::arg("json_text"), py::arg("source") = "scene text")
        .def("save", &scene::save, py::arg("path"))
        .def("to_json_string", &scene::to_json_string)
        .def("is_random", &scene::is_random)
        .def("targets", &scene::targets)
        .def("target_of_interest", &scene::target_of_interest)
        .def("label_classes", &scene::label_classes)
        .def(
            "library", [](const scene& sc) { return std::const_pointer_cast<class_library>(sc.library_ptr()); },
            D(scene, library))
        .def(
            "with_library",
            [](const scene& sc, std::shared_ptr<class_library> lib) { return sc.with_library(lib); },
            D(scene, with_library), py::arg("lib"))
        .def("track", &scene::track, D(scene, track))
        .def("with_track", &scene::with_track, D(scene, with_track), py::arg("t"))
        .def("budget", &scene::budget, D(scene, budget))
        .def("with_budget", &scene::with_budget, D(scene, with_budget), py::arg("b"))
        .def("array", &scene::array, D(scene, array))
        .def("with_array", &scene::with_array, D(scene, with_array), py::arg("a"))
        .def("class_name", &scene::class_name, D(scene, class_name), py::arg("c"));
}

void bind_channel_model(py::module& m)
{
    using cplx_array = py::array_t<gr_complex, py::array::c_style | py::array::forcecast>;

    py::class_<channel_path>(m, "channel_path", D(channel_path))
        .def_readonly("delay_s", &channel_path::delay_s)
        .def_readonly("doppler_hz", &channel_path::doppler_hz)
        .def_readonly("md_rate_hz", &channel_path::md_rate_hz)
        .def_readonly("md_amplitude_m", &channel_path::md_amplitude_m)
        .def_readonly("md_phase_rad", &channel_path::md_phase_rad)
        .def_readonly("gain", &channel_path::gain)
        .def_readonly("mean_power", &channel_path::mean_power)
        .def_readonly("body", &channel_path::body, D(channel_path, body))
        .def_readonly("azimuth_rad", &channel_path::azimuth_rad, D(channel_path, azimuth_rad))
        .def_readonly("elevation_rad", &channel_path::elevation_rad, D(channel_path, elevation_rad));

    py::class_<scatterer_body>(m, "scatterer_body", D(scatterer_body))
        .def_readonly("motion", &scatterer_body::motion, D(scatterer_body, motion))
        .def_readonly("speed_mps", &scatterer_body::speed_mps, D(scatterer_body, speed_mps))
        .def_readonly("heading_rad", &scatterer_body::heading_rad, D(scatterer_body, heading_rad));

    py::class_<frame_realization>(m, "frame_realization", D(frame_realization))
        .def_readonly("paths", &frame_realization::paths)
        .def_readonly("bodies", &frame_realization::bodies, D(frame_realization, bodies))
        .def_readonly("truth_body", &frame_realization::truth_body, D(frame_realization, truth_body))
        .def_readonly("clock_symbol", &frame_realization::clock_symbol, D(frame_realization, clock_symbol))
        .def_property_readonly("truth", [](const frame_realization& r) { return truth_dict(r.truth); });

    py::class_<channel_model>(m, "channel_model", D(channel_model))
        .def(py::init<const frame_settings&, const scene&, uint64_t>(), py::arg("settings"), py::arg("scene"),
             py::arg("seed") = 0)
        .def_static("noise_variance", &channel_model::noise_variance, py::arg("snr_db"))
        .def("settings", &channel_model::settings)
        .def("draw", py::overload_cast<uint64_t>(&channel_model::draw), py::arg("frame_index"))
        .def(
            "channel",
            [](const channel_model& cm, const frame_realization& r, uint64_t first_symbol) {
                const auto& fs = cm.settings();
                cplx_array h({ fs.n_symbols, fs.n_subcarriers });
                cm.factors(r, first_symbol).fill(h.mutable_data());
                return h;
            },
            py::arg("realization"), py::arg("first_symbol"), "H (N x M) of a drawn frame")
        .def(
            "channel",
            [](const channel_model& cm, const frame_realization& r, uint64_t first_symbol, int element) {
                const auto& fs = cm.settings();
                cplx_array h({ fs.n_symbols, fs.n_subcarriers });
                cm.factors(r, first_symbol, element).fill(h.mutable_data());
                return h;
            },
            py::arg("realization"), py::arg("first_symbol"), py::arg("element"),
            "H (N x M) of a drawn frame at one stream of the scene's array (channel_model::factors)")
        .def("n_elements", &channel_model::n_elements, D(channel_model, n_elements))
        .def(
            "generate",
            [](channel_model& cm, size_t count, uint64_t first_frame) {
                const auto& fs = cm.settings();
                cplx_array h({ static_cast<py::ssize_t>(count), static_cast<py::ssize_t>(fs.n_symbols),
                               static_cast<py::ssize_t>(fs.n_subcarriers) });
                std::vector<frame_truth> truths;
                {
                    py::gil_scoped_release release;
                    truths = cm.generate(count, h.mutable_data(), first_frame);
                }
                py::list tl;
                for (const auto& t : truths)
                    tl.append(truth_dict(t));
                return py::make_tuple(h, tl);
            },
            py::arg("count"), py::arg("first_frame") = 0,
            "(H, truths): count x N x M noiseless channels (complex64) and a truth dict per frame")
        .def(
            "add_noise",
            [](channel_model& cm, py::array_t<gr_complex, py::array::c_style> y, double snr_db) {
                cm.add_noise(y.mutable_data(), static_cast<size_t>(y.size()), snr_db);
            },
            py::arg("y"), py::arg("snr_db"), "Adds CN(0, σ²) in place to a complex64 array")
        .def("begin_track", &channel_model::begin_track, D(channel_model, begin_track), py::arg("track_index"))
        .def("reseed", &channel_model::reseed, py::arg("seed"));
}

} // namespace

void bind_micro_motion(py::module& m); // bind_micro_motion.cc

void bind_core(py::module& m)
{
    bind_keys(m);
    bind_micro_motion(m);
    bind_frame_settings(m);
    bind_pilot_mask(m);
    bind_scene(m);
    bind_channel_model(m);
}
