// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the pybind11 module `gnuradio.sems.core_python` — the core (frame, mask, scene,
 * channel model, tag keys) and the streaming blocks. No LibTorch: a flowgraph of mapper,
 * channel and extractor never loads it. Each bind_*.cc binds one header.
 */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_core(py::module& m);
void bind_array(py::module& m);
void bind_mimo_mask(py::module& m);
void bind_pilot_mapper(py::module& m);
void bind_mimo_pilot_mapper(py::module& m);
void bind_target_channel(py::module& m);
void bind_target_channel_td(py::module& m);
void bind_frame_sync(py::module& m);
void bind_leakage_canceller(py::module& m);
void bind_cfo_corrector(py::module& m);
void bind_pilot_extractor(py::module& m);
void bind_range_doppler_map(py::module& m);
void bind_range_angle_map(py::module& m);
void bind_front_end(py::module& m);

PYBIND11_MODULE(core_python, m)
{
    m.doc() = "gr-sems core: frame settings, pilot masks, scenes, the channel model and the streaming blocks";
    // Blocks derive from gr::sync_block etc.: make their base classes known first.
    py::module::import("gnuradio.gr");

    bind_array(m); // before the scenes, which take an array
    bind_core(m);
    bind_mimo_mask(m); // after bind_core: its signatures name the core types
    bind_pilot_mapper(m);
    bind_mimo_pilot_mapper(m); // after bind_array: its mask() is a mimo_mask
    bind_target_channel(m);
    bind_target_channel_td(m);
    bind_frame_sync(m);
    bind_leakage_canceller(m);
    bind_cfo_corrector(m);
    bind_pilot_extractor(m);
    bind_range_doppler_map(m);
    bind_range_angle_map(m);
    bind_front_end(m);
}
