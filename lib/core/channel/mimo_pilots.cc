// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a MIMO mask's observations of a drawn frame (see mimo_pilots.h). */
#include <gnuradio/sems/core/channel/mimo_pilots.h>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

std::vector<gr_complex>
mimo_pilots(const channel_model& cm, const frame_realization& r, uint64_t first_symbol, const mimo_mask& m)
{
    const int n_t = cm.scene_spec().array() ? cm.scene_spec().array()->n_transmit() : 1;
    if (n_t != m.n_transmit())
        throw std::invalid_argument("mimo_pilots: the scene's array has " + std::to_string(n_t) +
                                    " transmit elements and the MIMO mask " + std::to_string(m.n_transmit()));
    m.mask().check_frame(cm.settings(), "mimo_pilots"); // names both grids
    const int n_r = cm.n_elements() / n_t, np = m.mask().size();
    const auto flat = m.mask().flat_indices();
    std::vector<gr_complex> y(size_t(n_r) * size_t(np), gr_complex(0.0f, 0.0f));
    std::vector<gr_complex> h(size_t(cm.settings().grid_size()));
    for (int k = 0; k < n_r; ++k)
        for (int j = 0; j < n_t; ++j) {
            cm.factors(r, first_symbol, k * n_t + j).fill(h.data());
            for (int i = 0; i < np; ++i) {
                const double a = m.amplitude(i, j);
                if (a != 0.0)
                    y[size_t(k) * np + size_t(i)] += float(a) * h[size_t(flat[size_t(i)])];
            }
        }
    return y;
}

} // namespace sems
} // namespace gr
