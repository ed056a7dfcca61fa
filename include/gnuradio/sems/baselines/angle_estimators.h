// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The classical angle references: the Cramér–Rao bound of a target's azimuth, FFT
 *        (Bartlett) beamforming, Capon (MVDR) beamforming and MUSIC with forward–backward
 *        spatial smoothing.
 *
 * \details The observations are an array's pilots, element-major as the pilot extractor gives
 * them: y[k·L + t] is element k's observation of snapshot t (a pilot), k < K elements (the
 * array's virtual elements, steering.h), t < L. The model is narrowband, y_t = Σ_i a(φ_i) s_{i,t}
 * + w_t with a(φ) = steering_vector(array, φ, θ, λ) at a known elevation θ and w_t ~ CN(0, σ² I):
 * each snapshot's amplitudes s_{i,t} are unknown (they carry the pilot's delay and Doppler
 * phases and the fading), so the bound is the deterministic (conditional) one.
 */
#ifndef INCLUDED_SEMS_BASELINES_ANGLE_ESTIMATORS_H
#define INCLUDED_SEMS_BASELINES_ANGLE_ESTIMATORS_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief The deterministic Cramér–Rao bound of one target's azimuth (elevation known).
 * \details CRB(φ) = σ² / (2 Σ_t |s_t|² · ‖P⊥_a ȧ‖²), ȧ = ∂a/∂φ, P⊥_a the projection off a(φ).
 * For a ULA of K elements at spacing d, centred, it is 6 / (E·(2π d cos φ cos θ/λ)²·K(K² − 1)),
 * E = Σ_t |s_t|²/σ².
 * \param a the array. \param azimuth_rad φ. \param elevation_rad θ. \param wavelength_m λ.
 * \param energy_to_noise E = Σ_t |s_t|² / σ², the target's energy over all snapshots (per
 *        element) over the noise variance (linear, > 0).
 * \return the bound on the variance of φ in rad².
 * \throws std::invalid_argument for E ≤ 0 or not finite, λ ≤ 0, or an azimuth where the element pattern is null.
 */
SEMS_BASELINES_API double angle_crb_rad2(const array_geometry& a, double azimuth_rad, double elevation_rad,
                                         double wavelength_m, double energy_to_noise);

/*! \brief Where an angle estimator searches: an azimuth interval on a grid, then refines. */
struct SEMS_BASELINES_API angle_search {
    double min_rad = -1.5; ///< the search's first azimuth (≥ −π)
    double max_rad = 1.5;  ///< its last (≤ π, > min_rad)
    int grid = 1024;       ///< grid points (≥ 8); each peak is then refined between its neighbours
};

/*!
 * \brief FFT (Bartlett) beamforming: the azimuths of the n strongest peaks of
 *        P(φ) = Σ_t |a(φ)ᴴ y_t|² / ‖a(φ)‖². For one target this is its maximum-likelihood estimate.
 */
class SEMS_BASELINES_API beamforming_angle_estimator
{
public:
    /*!
     * \brief An estimator for an array.
     * \param a the array. \param elevation_rad θ, known. \param wavelength_m λ.
     * \param search where to search.
     * \throws std::invalid_argument naming a bad setting.
     */
    beamforming_angle_estimator(const array_geometry& a, double elevation_rad, double wavelength_m,
                                angle_search search = {});
    /*! \brief K, the streams. \return the elements. */
    int n_elements() const { return static_cast<int>(d_steer.size() / size_t(d_search.grid)); }
    /*!
     * \brief The azimuths of the n_targets strongest peaks.
     * \param y K·L observations, element-major. \param snapshots L ≥ 1. \param n_targets ≥ 1.
     * \return n_targets azimuths in rad, strongest first (fewer when the spectrum has fewer peaks).
     * \throws std::invalid_argument on non-finite input or bad counts.
     */
    std::vector<double> estimate(const gr_complex* y, int snapshots, int n_targets = 1) const;
    /*!
     * \brief The spectrum on the search grid.
     * \param y as above. \param snapshots L.
     * \return grid values of P(φ).
     */
    std::vector<double> spectrum(const gr_complex* y, int snapshots) const;
    /*!
     * \brief The maximum of P(φ) on [lo, hi], by golden-section search on the exact steering
     *        vectors (the search grid plays no part): the polish a learned estimate ends with.
     * \param y as above. \param snapshots L. \param lo first azimuth. \param hi last (> lo).
     * \return the azimuth of the largest P found, in [lo, hi]; an end of the interval when P
     *         rises towards it (no peak inside).
     * \throws std::invalid_argument on non-finite input, bad counts or lo >= hi.
     */
    double refine(const gr_complex* y, int snapshots, double lo, double hi) const;

private:
    array_geometry d_array;
    double d_elevation, d_lambda;
    angle_search d_search;
    std::vector<std::complex<double>> d_steer; // grid x K, each a(φ_g)/‖a(φ_g)‖, conjugated
};

/*!
 * \brief Capon (minimum-variance distortionless response) beamforming: the azimuths of the n
 *        strongest peaks of P(φ) = ‖a‖² / (a(φ)ᴴ (R + δI)⁻¹ a(φ)), R the sample covariance, δ
 *        its diagonal loading. Its beam adapts to the data, so it resolves incoherent targets
 *        closer than a beamwidth, where beamforming sees one; coherent ones (the same snapshot
 *        phases) cancel in it, as in MUSIC, unless spatially smoothed.
 */
class SEMS_BASELINES_API capon_angle_estimator
{
public:
    /*!
     * \brief An estimator for an array.
     * \param a the array. \param elevation_rad θ, known. \param wavelength_m λ.
     * \param loading δ relative to the mean eigenvalue, tr(R)/K (≥ 0; 0: none, which needs at
     *        least K snapshots).
     * \param subarray 0: no smoothing; m: forward–backward smoothing over a ULA's subarrays of m
     *        elements, as music_angle_estimator.
     * \param search where to search.
     * \throws std::invalid_argument naming a bad setting.
     */
    capon_angle_estimator(const array_geometry& a, double elevation_rad, double wavelength_m, double loading = 1e-3,
                          int subarray = 0, angle_search search = {});
    /*!
     * \brief The azimuths of the n_targets strongest peaks.
     * \param y K·L observations, element-major. \param snapshots L ≥ 1. \param n_targets ≥ 1.
     * \return up to n_targets azimuths in rad, strongest first.
     * \throws std::invalid_argument on non-finite input or bad counts.
     */
    std::vector<double> estimate(const gr_complex* y, int snapshots, int n_targets = 1) const;
    /*! \brief K, the streams. \return the elements. */
    int n_elements() const { return d_array.n_receive() * d_array.n_transmit(); }

private:
    array_geometry d_array;
    double d_elevation, d_lambda, d_loading;
    int d_sub;
    angle_search d_search;
};

/*!
 * \brief MUSIC: the peaks of 1/‖E_nᴴ a(φ)‖² over the noise subspace of the sample covariance;
 *        with forward–backward spatial smoothing on a ULA (subarrays of `subarray` elements), so
 *        coherent targets (the same delay and Doppler: the same snapshot phases) are resolved.
 */
class SEMS_BASELINES_API music_angle_estimator
{
public:
    /*!
     * \brief An estimator for an array.
     * \param a the array. \param elevation_rad θ, known. \param wavelength_m λ.
     * \param n_targets the signal subspace's dimension (≥ 1, < the subarray's elements).
     * \param subarray 0: no smoothing (any array); m: forward–backward smoothing over the ULA's
     *        K − m + 1 subarrays of m elements (the virtual array, receive × transmit offsets
     *        in order, must be equally spaced along y).
     * \param search where to search.
     * \throws std::invalid_argument naming a bad setting.
     */
    music_angle_estimator(const array_geometry& a, double elevation_rad, double wavelength_m, int n_targets,
                          int subarray = 0, angle_search search = {});
    /*!
     * \brief The azimuths of the n_targets strongest peaks.
     * \param y K·L observations, element-major. \param snapshots L ≥ 1.
     * \return up to n_targets azimuths in rad, strongest first.
     * \throws std::invalid_argument on non-finite input or bad counts.
     */
    std::vector<double> estimate(const gr_complex* y, int snapshots) const;
    /*! \brief K, the streams. \return the elements. */
    int n_elements() const { return d_array.n_receive() * d_array.n_transmit(); }

private:
    double pseudo_spectrum(const std::vector<std::complex<double>>& noise, int dim, double azimuth) const;
    array_geometry d_array;
    double d_elevation, d_lambda;
    int d_targets, d_sub;
    angle_search d_search;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_ANGLE_ESTIMATORS_H */
