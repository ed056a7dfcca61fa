// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the Doppler search grid (the phasors are inline in core/array/steering.h). */
#include <gnuradio/sems/core/array/steering.h>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

std::vector<double> doppler_grid(const frame_settings& fs, int oversample)
{
    if (oversample < 1)
        throw std::invalid_argument("doppler_grid: oversample must be >= 1, got " + std::to_string(oversample));
    const int f = fs.n_symbols * oversample;
    std::vector<double> g(f);
    for (int q = 0; q < f; ++q)
        g[q] = (q - f / 2) / (f * fs.symbol_interval_s);
    return g;
}

} // namespace sems
} // namespace gr
