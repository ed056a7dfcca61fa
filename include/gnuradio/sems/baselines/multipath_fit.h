// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Off-grid least-squares fit of a multipath frame: the refinement stage of
 *        "OMP + LS refinement" and of the oracle-order least-squares reference.
 *
 * \details Model (one target, its L paths share the slow-time factor):
 *
 *     y_k = b(n_k; ν) · Σ_l α_l · a(m_k; τ_l) + w_k,
 *     a(m; τ) = delay_phasor(m, τ, M),  b(n; ν) = doppler_phasor(n, ν, T)   (core/array/steering.h)
 *
 * over the N_p pilots k of the mask. Unknowns: the delays τ_l (delay indices), the complex
 * gains α_l and the shared Doppler ν. When every pilot sits on one OFDM symbol ν is not
 * identifiable (it is a common phase) and is not fitted.
 *
 * The gains are eliminated (variable projection): for given (τ, ν) they are the least-squares
 * α̂ = Φ⁺y, and the cost is ‖P⊥_Φ y‖². The delays and ν are refined by Levenberg–Marquardt with
 * Kaufman's Jacobian G = P⊥_Φ · ∂(Φα̂)/∂θ, Marquardt's diagonal scaling, and a step accepted
 * only when it lowers the cost. A noiseless frame is fitted to round-off from any start inside
 * the cost's basin.
 */
#ifndef INCLUDED_SEMS_BASELINES_MULTIPATH_FIT_H
#define INCLUDED_SEMS_BASELINES_MULTIPATH_FIT_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

/*! \brief The result of a multipath fit: paths sorted by delay (earliest first). */
struct SEMS_BASELINES_API multipath_fit {
    std::vector<double> delay_index; //!< τ_l·B, ascending
    std::vector<gr_complex> gain;    //!< α̂_l, in the same order
    double doppler_hz = 0.0;         //!< ν̂ (the start value when not identifiable)
    double residual = 0.0;           //!< ‖y − model‖²
    int iterations = 0;              //!< Levenberg–Marquardt iterations taken
};

/*! \brief Variable-projection Levenberg–Marquardt fit of L paths with a shared Doppler. */
class SEMS_BASELINES_API multipath_fitter
{
public:
    /*! \brief Iteration limits. */
    struct settings {
        int max_iterations = 50;  //!< Levenberg–Marquardt iterations, >= 1
        double tolerance = 1e-10; //!< stop when no parameter moves more than this (index / Hz·T)
    };

    /*!
     * \brief A fitter for one frame layout and pilot mask.
     * \param fs the frame (M, T).
     * \param mask the pilot positions the observations come from (mask order).
     * \param s iteration limits.
     * \throws std::invalid_argument if the mask does not fit the frame or a setting is out of range.
     */
    multipath_fitter(const frame_settings& fs, const pilot_mask& mask, settings s);
    /*!
     * \brief A fitter with the default iteration limits.
     * \param fs the frame (M, T).
     * \param mask the pilot positions the observations come from (mask order).
     * \throws std::invalid_argument if the mask does not fit the frame.
     */
    multipath_fitter(const frame_settings& fs, const pilot_mask& mask);
    ~multipath_fitter();
    /*! \brief Moves the fitter (its precomputed pilot positions). */
    multipath_fitter(multipath_fitter&&) noexcept;

    /*! \brief Whether ν is fitted. \return true when the pilots span at least two symbols. */
    bool doppler_identifiable() const;
    /*! \brief N_p. \return the observations per frame. */
    int n_pilots() const;

    /*!
     * \brief Refines delays (and ν) from a start.
     * \param obs N_p observations Y/x_k in mask order (x_k the pilot sent, pilot_mask::transmitted_pilot).
     * \param delay_index start delays (delay indices), 1 <= L <= N_p.
     * \param doppler_hz start Doppler.
     * \return the refined fit.
     * \throws std::invalid_argument on a null or non-finite observation or a bad number of delays.
     */
    multipath_fit refine(const gr_complex* obs, const std::vector<double>& delay_index, double doppler_hz) const;

    /*!
     * \brief A fit anchored at an estimate of the first path (the hybrid decoder's stage).
     * \details The first path starts at `first_delay_index`; ν at the Doppler grid point
     * (2× oversampled) that best explains that path alone (when identifiable); each of the
     * n_paths − 1 later paths at the delay on a 1/8-index grid over (first + 0.25,
     * first + span_index] most correlated with the residual of the paths so far. Then
     * refine() from there.
     * \param obs N_p observations in mask order.
     * \param first_delay_index the first path's start delay.
     * \param n_paths L, in [1, N_p].
     * \param span_index how far after the first path later paths are searched (> 0.25).
     * \return the refined fit.
     * \throws std::invalid_argument on bad observations or arguments.
     */
    multipath_fit refine_anchored(const gr_complex* obs, double first_delay_index, int n_paths, double span_index) const;

    /*!
     * \brief ‖P⊥ y‖² and the least-squares gains for given delays and Doppler (no refinement).
     * \param obs N_p observations in mask order.
     * \param delay_index the delays (delay indices).
     * \param doppler_hz the Doppler.
     * \return the residual and gains.
     */
    multipath_fit evaluate(const gr_complex* obs, const std::vector<double>& delay_index, double doppler_hz) const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_MULTIPATH_FIT_H */
