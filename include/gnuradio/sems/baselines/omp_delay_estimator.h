// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Orthogonal matching pursuit (OMP) delay estimator on an oversampled grid.
 *
 * \details Dictionary: joint delay–Doppler atoms d(τ,ν)_k = a_τ(m_k) · b_ν(n_k) at the pilot
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
#ifndef INCLUDED_SEMS_BASELINES_OMP_DELAY_ESTIMATOR_H
#define INCLUDED_SEMS_BASELINES_OMP_DELAY_ESTIMATOR_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/baselines/delay_search.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

/*! \brief One atom chosen by OMP. */
struct SEMS_BASELINES_API omp_atom {
    double delay_index; ///< τ·B
    double doppler_hz;  ///< ν in Hz
    gr_complex gain;    ///< least-squares gain
};

/*! \brief Orthogonal matching pursuit (OMP) delay estimator on an oversampled delay–Doppler grid (see the file's description). */
class SEMS_BASELINES_API omp_delay_estimator
{
public:
    /*! \brief The estimator's settings. */
    struct settings {
        delay_search search{}; ///< the delay search window and grid
        int doppler_oversample = 2;  ///< Doppler grid points per 1/(N T)
        int n_atoms = 1;             ///< sparsity (model order), >= 1 and <= N_p
        double relative_power = 0.25; ///< reporting threshold: fraction of the strongest atom, in (0, 1]
        bool refine = false;          ///< off-grid least-squares refinement of the chosen atoms
    };

    /*!
     * \brief An estimator for a frame and a pilot pattern.
     * \param fs the frame. \param mask the pilot pattern. \param s the settings.
     * \throws std::invalid_argument naming the bad setting or why the mask cannot be used.
     */
    omp_delay_estimator(const frame_settings& fs, const pilot_mask& mask, settings s);
    /*!
     * \brief An estimator with default settings.
     * \param fs the frame. \param mask the pilot pattern.
     * \throws std::invalid_argument naming why the mask cannot be used.
     */
    omp_delay_estimator(const frame_settings& fs, const pilot_mask& mask);
    ~omp_delay_estimator(); ///< Destructor.
    /*! \brief Move constructor. */
    omp_delay_estimator(omp_delay_estimator&&) noexcept;

    /*! \brief N_p. \return the observations per frame. */
    int n_pilots() const;
    /*!
     * \brief Estimates the delay of the target of interest.
     * \param obs N_p observations Y/x_k in mask order (x_k the pilot sent, pilot_mask::transmitted_pilot).
     * \return the delay index τ·B.
     * \throws std::invalid_argument on non-finite input.
     */
    double estimate_index(const gr_complex* obs) const;
    /*!
     * \brief Estimates the delay of the target of interest.
     * \param obs N_p observations Y/x_k in mask order (x_k the pilot sent, pilot_mask::transmitted_pilot).
     * \return the delay in s.
     * \throws std::invalid_argument on non-finite input.
     */
    double estimate_delay_s(const gr_complex* obs) const;
    /*!
     * \brief The atoms in the order they were chosen, with least-squares gains.
     * \param obs N_p observations in mask order.
     * \return the atoms.
     * \throws std::invalid_argument on non-finite input.
     */
    std::vector<omp_atom> decompose(const gr_complex* obs) const;
    /*!
     * \brief The atoms after the off-grid refinement (sorted by delay, one shared Doppler).
     * \param obs N_p observations in mask order.
     * \return the refined atoms; the grid atoms when `refine` is off.
     * \throws std::invalid_argument on non-finite input.
     */
    std::vector<omp_atom> refined_atoms(const gr_complex* obs) const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_OMP_DELAY_ESTIMATOR_H */
