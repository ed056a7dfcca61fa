// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The periodogram (matched-filter) delay estimator, the classical reference.
 *
 * \details Input: pilot observations r_k = Y/x_k (x_k the pilot sent, pilot_mask::transmitted_pilot) at the mask positions (n_k, m_k), in mask order.
 * A single path gives r_k = α · exp(-j2π m_k Δf τ) · (slow-time phase of symbol n_k) + noise.
 * Two models of the slow-time phase:
 *   joint_doppler:  a constant Doppler ν:  P(τ) = max_ν |Σ_k r_k a_τ*(m_k) b_ν*(n_k)|²
 *                   with a_τ(m) = exp(-j2π m Δf τ), b_ν(n) = exp(j2π ν n T) on an
 *                   oversampled Doppler grid over ±1/(2T). This is the maximum-likelihood
 *                   estimator of (τ, ν) for one path with an unknown complex gain.
 *   per_symbol:     an unknown phase per OFDM symbol (any Doppler or micro-Doppler):
 *                   P(τ) = Σ_n |Σ_{k: n_k = n} r_k a_τ*(m_k)|², the non-coherent sum over
 *                   symbols (needs several pilots per symbol to say anything).
 * The peak of P on the delay grid is refined by a parabola through its neighbours.
 */
#ifndef INCLUDED_SEMS_BASELINES_PERIODOGRAM_DELAY_ESTIMATOR_H
#define INCLUDED_SEMS_BASELINES_PERIODOGRAM_DELAY_ESTIMATOR_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/baselines/delay_search.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

/*! \brief The periodogram's model of the slow-time phase: one Doppler, or a free phase per symbol. */
enum class slow_time_model { joint_doppler, per_symbol };

/*! \brief The periodogram (matched-filter) delay estimator, the classical reference (see the file's description). */
class SEMS_BASELINES_API periodogram_delay_estimator
{
public:
    /*! \brief The estimator's settings. */
    struct settings {
        delay_search search{}; ///< the delay search window and grid
        int doppler_oversample = 2; ///< Doppler grid points per 1/(N T)
        slow_time_model slow_time = slow_time_model::joint_doppler; ///< the slow-time model
        bool refine = true;         ///< parabolic interpolation of the peak
    };

    /*!
     * \brief An estimator for a frame and a pilot pattern.
     * \param fs the frame. \param mask the pilot pattern. \param s the settings.
     * \throws std::invalid_argument naming the bad setting or why the mask cannot be used.
     */
    periodogram_delay_estimator(const frame_settings& fs, const pilot_mask& mask, settings s);
    /*!
     * \brief An estimator with default settings.
     * \param fs the frame. \param mask the pilot pattern.
     * \throws std::invalid_argument naming why the mask cannot be used.
     */
    periodogram_delay_estimator(const frame_settings& fs, const pilot_mask& mask);
    ~periodogram_delay_estimator(); ///< Destructor.
    /*! \brief Move constructor. */
    periodogram_delay_estimator(periodogram_delay_estimator&&) noexcept;

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
     * \brief P(τ) on the grid (for plots and tests).
     * \param obs N_p observations in mask order.
     * \return one value per grid_index() point.
     * \throws std::invalid_argument on non-finite input.
     */
    std::vector<double> profile(const gr_complex* obs) const;
    /*! \brief The delay grid. \return the grid in delay indices. */
    const std::vector<double>& grid_index() const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_PERIODOGRAM_DELAY_ESTIMATOR_H */
