// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the pilot observations as the classical baselines see them (internal):
 * a checked double vector, pilots grouped by symbol, peak interpolation, mask checks.
 * The steering phasors and the Doppler grid come from core/array/steering.h. */
#ifndef INCLUDED_SEMS_LIB_BASELINES_PILOT_OBSERVATIONS_H
#define INCLUDED_SEMS_LIB_BASELINES_PILOT_OBSERVATIONS_H

#include "core/common/checks.h"
#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/array/steering.h>
#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace baseline {

using cd = std::complex<double>;

// The observations as a double-precision vector; a non-finite value is an error.
inline Eigen::VectorXcd observations(const gr_complex* obs, int n_pilots, const std::string& who)
{
    if (obs == nullptr)
        throw std::invalid_argument(who + ": observations: null pointer");
    Eigen::VectorXcd r(n_pilots);
    for (int k = 0; k < n_pilots; ++k) {
        if (!checks::finite(obs[k]))
            throw std::invalid_argument(who + ": observation " + std::to_string(k) + " is not finite");
        r[k] = cd(obs[k].real(), obs[k].imag());
    }
    return r;
}

// Symbols carrying pilots (sorted) and, per pilot, the index of its symbol in that list.
struct symbol_groups {
    std::vector<int> symbols;
    std::vector<int> of_pilot;
};
inline symbol_groups group_by_symbol(const pilot_mask& mask)
{
    symbol_groups g;
    for (const auto& p : mask.positions()) { // mask order: sorted by (n, m)
        if (g.symbols.empty() || g.symbols.back() != p.n)
            g.symbols.push_back(p.n);
        g.of_pilot.push_back(static_cast<int>(g.symbols.size()) - 1);
    }
    return g;
}

// Vertex of the parabola through (-1, a), (0, b), (1, c), in (-0.5, 0.5).
inline double parabolic_offset(double a, double b, double c)
{
    const double den = a - 2.0 * b + c;
    if (!(den < 0.0))
        return 0.0;
    const double off = 0.5 * (a - c) / den;
    return std::max(-0.5, std::min(0.5, off));
}

inline void check_mask(const frame_settings& fs, const pilot_mask& mask, const std::string& who)
{
    fs.validate();
    mask.check_frame(fs, who);
}

} // namespace baseline
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BASELINES_PILOT_OBSERVATIONS_H */
