/* gr-sems: the pybind11 module `gnuradio.sems.sems_python`.
 * Each bind_*.cc file binds one header; this file only calls them.
 */
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_core(py::module& m);
void bind_pilot_mapper(py::module& m);
void bind_target_channel(py::module& m);
void bind_pilot_extractor(py::module& m);
void bind_learning(py::module& m);
void bind_sinks(py::module& m);
void bind_baselines(py::module& m);

PYBIND11_MODULE(sems_python, m)
{
    m.doc() = "gr-sems: semantic sensing over OFDM";
    // Blocks derive from gr::sync_block etc.: make their base classes known first.
    py::module::import("gnuradio.gr");

    bind_core(m);
    bind_pilot_mapper(m);
    bind_target_channel(m);
    bind_pilot_extractor(m);
    bind_learning(m);
    bind_sinks(m);
    bind_baselines(m);
}
