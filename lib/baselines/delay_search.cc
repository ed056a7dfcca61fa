// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the delay search grid of the classical estimators. */
#include "core/common/checks.h"
#include <gnuradio/sems/baselines/delay_search.h>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {

void delay_search::validate(const frame_settings& fs, const std::string& who) const
{
    if (oversample < 1 || oversample > 1024)
        throw std::invalid_argument(who + ": delay oversample must be in [1, 1024], got " + std::to_string(oversample));
    // -1 (the default) is the one sentinel for "M"; any other negative is a mistake, not M.
    if (max_index < 0.0 && max_index != -1.0)
        throw std::invalid_argument(who + ": delay search max_index = " + std::to_string(max_index) +
                                    " is negative: give an index > min_index, or -1 for the whole window (M)");
    const double hi = max_index < 0.0 ? fs.n_subcarriers : max_index;
    if (!checks::finite(min_index) || !checks::finite(hi))
        throw std::invalid_argument(who + ": delay search window must be finite");
    if (!(hi > min_index))
        throw std::invalid_argument(who + ": delay search window [" + std::to_string(min_index) + ", " +
                                    std::to_string(hi) + ") is empty");
    if (hi - min_index > fs.n_subcarriers + 1e-9)
        throw std::invalid_argument(who + ": delay search window is wider than the unambiguous " +
                                    std::to_string(fs.n_subcarriers) + " delay indices");
}

std::vector<double> delay_search::grid(const frame_settings& fs) const
{
    validate(fs, "delay search");
    const double hi = max_index < 0.0 ? fs.n_subcarriers : max_index;
    const int q = static_cast<int>(std::ceil((hi - min_index) * oversample - 1e-9));
    std::vector<double> g(q);
    for (int i = 0; i < q; ++i)
        g[i] = min_index + double(i) / oversample;
    return g;
}

} // namespace sems
} // namespace gr
