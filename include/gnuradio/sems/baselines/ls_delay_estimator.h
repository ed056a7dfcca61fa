// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The oracle-order least-squares reference for multipath delay: grid search, then
 *        nonlinear least squares over all delays and the shared Doppler.
 *
 * \details The model of multipath_fit.h with L = `n_paths` (the scene's true order: the
 * "oracle order"). Unknowns: L complex gains, L delays, one shared Doppler ν.
 *  1. Doppler: the strongest joint delay–Doppler atom on the grids (skipped when the
 *     pilots sit on one symbol, where ν is a common phase).
 *  2. Delays on the grid at that ν: greedy (each new path at the grid delay most
 *     correlated with the residual), then `sweeps` alternating-projection sweeps (each
 *     delay re-searched on the grid with the others projected out: the exact grid
 *     minimiser of the cost in that coordinate).
 *  3. multipath_fitter: Levenberg–Marquardt on the variable-projection cost over (τ, ν).
 * The delay reported for the target of interest is the earliest fitted delay (the direct
 * path arrives first; with the true order no power threshold is needed).
 */
#ifndef INCLUDED_SEMS_BASELINES_LS_DELAY_ESTIMATOR_H
#define INCLUDED_SEMS_BASELINES_LS_DELAY_ESTIMATOR_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/baselines/delay_search.h>
#include <gnuradio/sems/baselines/multipath_fit.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <memory>

namespace gr {
namespace sems {

/*! \brief Oracle-order least-squares multipath delay estimator (the reference). */
class SEMS_BASELINES_API ls_delay_estimator
{
public:
    /*! \brief Search grids, model order and iteration limits. */
    struct settings {
        delay_search search{};          //!< delay grid of the grid search
        int doppler_oversample = 2;     //!< Doppler grid points per bin, in [1, 64]
        int n_paths = 3;                //!< model order L (the scene's paths), in [1, N_p]
        int sweeps = 2;                 //!< alternating-projection sweeps on the grid, >= 0
        multipath_fitter::settings fit{}; //!< the nonlinear least-squares stage
    };

    /*!
     * \brief An estimator for one frame layout and mask.
     * \param fs the frame.
     * \param mask the pilot positions (mask order).
     * \param s settings.
     * \throws std::invalid_argument naming the bad setting or a mask that does not fit the frame.
     */
    ls_delay_estimator(const frame_settings& fs, const pilot_mask& mask, settings s);
    /*!
     * \brief The estimator with the default settings.
     * \param fs   frame settings (N, M)
     * \param mask the pilot positions
     * \throws std::invalid_argument if the mask does not fit the frame.
     */
    ls_delay_estimator(const frame_settings& fs, const pilot_mask& mask);
    ~ls_delay_estimator();
    /*! \brief Moves the estimator (its precomputed dictionaries). */
    ls_delay_estimator(ls_delay_estimator&&) noexcept;

    /*! \brief N_p. \return the observations per frame. */
    int n_pilots() const;
    /*!
     * \brief The grid-search start of one frame.
     * \param obs N_p observations in mask order.
     * \return the delays in the order found, with ν.
     */
    multipath_fit grid_search(const gr_complex* obs) const;
    /*!
     * \brief The full fit of one frame: grid search, then nonlinear least squares.
     * \param obs N_p observations in mask order.
     * \return the fitted paths.
     */
    multipath_fit fit(const gr_complex* obs) const;
    /*!
     * \brief The earliest fitted delay.
     * \param obs N_p observations in mask order.
     * \return the delay, in delay indices.
     */
    double estimate_index(const gr_complex* obs) const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_LS_DELAY_ESTIMATOR_H */
