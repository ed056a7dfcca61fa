// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: orthogonal matching pursuit (OMP) delay estimator on an oversampled grid.
 *
 * Dictionary: joint delay–Doppler atoms d(τ,ν)_k = a_τ(m_k) · b_ν(n_k) at the pilot
 * positions (a_τ(m) = exp(-j2π m Δf τ), b_ν(n) = exp(j2π ν n T)), τ on the oversampled
 * delay grid and ν on an oversampled Doppler grid over ±1/(2T). Every symbol's pilots
 * share the delay support and the Doppler ties the symbols together, so any pilot
 * pattern (also one with a single pilot per symbol) is handled; micro-Doppler is
 * absorbed by extra atoms at the same delay.
 *
 * Greedy: pick the atom most correlated with the residual, re-fit all chosen atoms by
 * least squares, repeat `n_atoms` times (the model order). The delay reported for the
 * target of interest is the earliest chosen atom whose fitted power is at least
 * `relative_power` of the strongest (the direct path arrives first).
 *
 * With `refine` (OMP + LS refinement) the chosen atoms start multipath_fitter: one shared
 * Doppler (the strongest atom's), the atoms' delays, then Levenberg–Marquardt off the grid
 * over all delays and ν (multipath_fit.h); the power rule is applied to the refined gains.
 * Without it the grid-mismatch floor is part of the method.
 */
#ifndef INCLUDED_SEMS_BASELINE_OMP_H
#define INCLUDED_SEMS_BASELINE_OMP_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/baselines/delay_search.h>
#include <gnuradio/sems/core/frame_settings.h>
#include <gnuradio/sems/core/pilot_mask.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

struct SEMS_BASELINES_API omp_atom {
    double delay_index;
    double doppler_hz;
    gr_complex gain;
};

class SEMS_BASELINES_API omp_delay_estimator
{
public:
    struct settings {
        delay_search search{};
        int doppler_oversample = 2;
        int n_atoms = 1;             // sparsity (model order), >= 1 and <= N_p
        double relative_power = 0.25; // of the strongest atom, in (0, 1]
        bool refine = false;          // off-grid least-squares refinement of the chosen atoms
    };

    omp_delay_estimator(const frame_settings& fs, const pilot_mask& mask, settings s);
    omp_delay_estimator(const frame_settings& fs, const pilot_mask& mask);
    ~omp_delay_estimator();
    omp_delay_estimator(omp_delay_estimator&&) noexcept;

    int n_pilots() const; // N_p, the observations per frame
    double estimate_index(const gr_complex* obs) const;
    double estimate_delay_s(const gr_complex* obs) const;
    // The atoms in the order they were chosen, with least-squares gains.
    std::vector<omp_atom> decompose(const gr_complex* obs) const;
    // The atoms after the off-grid refinement (sorted by delay, one shared Doppler); the
    // grid atoms when `refine` is off.
    std::vector<omp_atom> refined_atoms(const gr_complex* obs) const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINE_OMP_H */
