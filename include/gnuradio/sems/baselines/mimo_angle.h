// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief A target's azimuth from a MIMO mask's pilots (core/array/mimo_mask.h): the Cramér–Rao
 *        bound with the target's delay, Doppler and complex gain unknown, and the
 *        maximum-likelihood estimator that reaches it.
 *
 * \details The model of one point target on one path, seen at elevation θ (known):
 *
 *     y[k, i] = α · g(u) · Σ_j amplitude(i, j) · exp(jψ_kj(φ)) · exp(−j2π m_i τ/M) · exp(j2π n_i ν/N) + w
 *
 * with ψ_kj(φ) = 2π f_i u(φ, θ)·(p_k + q_j)/c the steering phase of virtual element k·N_t + j at
 * the pilot's own frequency f_i = f_c + m_i Δf (the emulator's exact element delay: the carrier
 * phase of steering.h and the plane wave's delay on subcarrier m_i), g the element pattern's amplitude, τ the delay in delay indices and ν the
 * Doppler in Doppler bins (1/(N·T)), w ~ CN(0, σ²). Unlike angle_estimators.h, where every
 * snapshot's amplitude is free, the pilots here share one gain and differ only by the delay and
 * Doppler phases: that is what lets pilots of different transmit elements add coherently (a
 * virtual array), and also what couples the angle to the Doppler when the elements take turns
 * in time (time division), or to the delay when they share the band (frequency division).
 */
#ifndef INCLUDED_SEMS_BASELINES_MIMO_ANGLE_H
#define INCLUDED_SEMS_BASELINES_MIMO_ANGLE_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <complex>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief The Cramér–Rao bound of the azimuth φ from a MIMO mask's pilots, with (τ, ν, Re α,
 *        Im α) unknown: σ²/(2|α|²) · [J⁻¹]_φφ of the 5 × 5 Fisher information of the model above.
 * \details It does not depend on τ or ν (their phases have unit modulus) and falls as 1/SNR.
 * With the elements taking no part in the delay and Doppler (each element's pilots with the same
 * centroid and spread in n and m) it is the virtual array's: 6/(E (2π d cos φ cos θ/λ)² K(K²−1))
 * for a centred uniform virtual array of K elements, E the target's energy over the noise summed
 * over all pilots per element.
 * \param a the array (its N_t transmit elements the mask's). \param m the mask.
 * \param fs the frame (carrier and subcarrier spacing). \param azimuth_rad φ. \param elevation_rad θ.
 * \param snr |α|²/σ² per pilot and receive element (linear, > 0), a pilot of one element.
 * \return the bound in rad² (+inf where the angle is not identifiable: the element pattern's
 *         null, or a mask whose pilots cannot tell φ from the nuisances).
 * \throws std::invalid_argument for snr not finite and > 0, a mask off the frame, or element counts that differ.
 */
SEMS_BASELINES_API double mimo_angle_crb_rad2(const array_geometry& a, const mimo_mask& m, const frame_settings& fs,
                                              double azimuth_rad, double elevation_rad, double snr);

/*! \brief One estimate of mimo_ml_angle_estimator. */
struct SEMS_BASELINES_API mimo_ml_estimate {
    double azimuth_rad = 0.0;  ///< φ̂
    double delay_index = 0.0;  ///< τ̂ in [0, M)
    double doppler_bins = 0.0; ///< ν̂ in [−N/2, N/2)
};

/*!
 * \brief The maximum-likelihood estimate of (φ, τ, ν) for one point target:
 *        argmax |b(φ, τ, ν)ᴴ y|² / ‖b(φ, τ, ν)‖², b the model above without α.
 * \details A grid over φ (the search's), τ (M·oversample points over [0, M)) and ν (N·oversample
 * over [−N/2, N/2)), computed as one matrix product per frame; then the best point is polished by
 * a Nelder–Mead search over the three together (they are coupled: time division ties φ to ν).
 */
class SEMS_BASELINES_API mimo_ml_angle_estimator
{
public:
    /*!
     * \brief An estimator for a mask on an array.
     * \param a the array. \param m the mask (its N_t the array's). \param fs the frame.
     * \param elevation_rad θ, known. \param search the azimuth grid. \param oversample grid points per
     *        delay index and per Doppler bin, 1 to 16.
     * \throws std::invalid_argument naming a bad setting or both element counts.
     */
    mimo_ml_angle_estimator(const array_geometry& a, const mimo_mask& m, const frame_settings& fs, double elevation_rad,
                            angle_search search = {}, int oversample = 2);
    /*!
     * \brief The estimate from one frame.
     * \param y N_r·N_p observations, receive-element-major (mimo_pilots()).
     * \return φ̂, τ̂, ν̂.
     * \throws std::invalid_argument on non-finite input.
     */
    mimo_ml_estimate estimate(const gr_complex* y) const;
    /*!
     * \brief The concentrated likelihood |bᴴ y|²/‖b‖² at one point.
     * \param y as above. \param azimuth_rad φ. \param delay_index τ. \param doppler_bins ν.
     * \return its value.
     */
    double likelihood(const gr_complex* y, double azimuth_rad, double delay_index, double doppler_bins) const;

private:
    std::vector<std::complex<double>> steering(double azimuth_rad) const; // N_r·N_p: g·Σ_j amplitude·exp(jψ)
    array_geometry d_array;
    mimo_mask d_mask;
    frame_settings d_fs;
    double d_elevation;
    angle_search d_search;
    int d_over;
    struct tables;
    std::shared_ptr<const tables> d_t;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_MIMO_ANGLE_H */
