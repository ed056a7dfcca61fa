// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief MUSIC delay estimation from sparse pilots.
 *
 * \details How the covariance is formed from sparse pilots (the difference co-array over
 * subcarriers, within symbols):
 *   Two pilots of the SAME OFDM symbol share the slow-time phase (Doppler and
 *   micro-Doppler included), so their product r_i r_j* = Σ |α_l|² exp(-j2π Δf τ_l (m_i - m_j))
 *   (+ cross terms, + σ² when i = j) depends on the subcarrier lag d = m_i - m_j only.
 *   Every same-symbol pair of every symbol is averaged into its lag, r̂[d] (with
 *   r̂[-d] = r̂[d]*). Let g be the greatest common divisor of the observed lags and
 *   L the length of the longest run 0, g, 2g, ..., (L-1)g of observed lags: the
 *   covariance is the L x L Hermitian Toeplitz matrix R[a,b] = r̂[(a-b)g] of a virtual
 *   uniform array with spacing g. Averaging many pairs of the same lag from different
 *   subcarriers acts as spatial smoothing (it decorrelates coherent paths); the symbols
 *   are the snapshots.
 * The pseudo-spectrum 1/‖E_nᴴ a(τ)‖² (E_n: the L - K eigenvectors of the smallest
 * eigenvalues, a(τ)[i] = exp(-j2π Δf τ i g)) is searched on the delay grid; it repeats
 * every M/g delay indices, so a lattice with pilot spacing g > 1 (uniform pilots) aliases.
 * The reported delay is the earliest of the K strongest local maxima.
 *
 * A mask whose co-array has L < K + 1 (e.g. one pilot per symbol) cannot be used:
 * the constructor throws std::invalid_argument saying so.
 */
#ifndef INCLUDED_SEMS_BASELINES_MUSIC_DELAY_ESTIMATOR_H
#define INCLUDED_SEMS_BASELINES_MUSIC_DELAY_ESTIMATOR_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/baselines/delay_search.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

/*! \brief MUSIC delay estimation from sparse pilots over the difference co-array (see the file's description). */
class SEMS_BASELINES_API music_delay_estimator
{
public:
    /*! \brief The estimator's settings. */
    struct settings {
        delay_search search{}; ///< the delay search window and grid
        int n_paths = 1; ///< K, the signal-subspace dimension
    };

    /*!
     * \brief An estimator for a frame and a pilot pattern.
     * \param fs the frame. \param mask the pilot pattern. \param s the settings.
     * \throws std::invalid_argument naming the bad setting or why the mask cannot be used.
     */
    music_delay_estimator(const frame_settings& fs, const pilot_mask& mask, settings s);
    /*!
     * \brief An estimator with default settings.
     * \param fs the frame. \param mask the pilot pattern.
     * \throws std::invalid_argument naming why the mask cannot be used.
     */
    music_delay_estimator(const frame_settings& fs, const pilot_mask& mask);
    ~music_delay_estimator(); ///< Destructor.
    /*! \brief Move constructor. */
    music_delay_estimator(music_delay_estimator&&) noexcept;

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
     * \brief The pseudo-spectrum 1/‖E_nᴴ a(τ)‖² on the grid (for plots and tests).
     * \param obs N_p observations in mask order.
     * \return one value per grid_index() point.
     * \throws std::invalid_argument on non-finite input.
     */
    std::vector<double> pseudo_spectrum(const gr_complex* obs) const;
    /*! \brief The delay grid. \return the grid in delay indices. */
    const std::vector<double>& grid_index() const;

    /*! \brief g, the co-array's lag spacing. \return g. */
    int coarray_spacing() const;
    /*! \brief L, the virtual array's length. \return L. */
    int coarray_length() const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_MUSIC_DELAY_ESTIMATOR_H */
