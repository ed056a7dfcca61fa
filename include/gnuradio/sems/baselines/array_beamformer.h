// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief An array's pilots combined into one antenna's: beamformed towards a direction, or
 *        towards the strongest one the array sees.
 *
 * \details What a one-antenna decoder (a classifier, the delay decoder) reads when the stream
 * comes from an array. The observations are element-major as the pilot extractor gives them:
 * y[k·L + t] is stream k's observation of pilot t, k < K (the array's virtual elements,
 * steering.h), t < L. Combined, z_t = a(φ)ᴴ y_t / ‖a(φ)‖²: a plane wave from φ keeps its
 * amplitude, white noise of variance σ² per element leaves σ²/‖a(φ)‖² (σ²/K with isotropic
 * elements), so the combined pilots are one antenna's at K times the SNR.
 */
#ifndef INCLUDED_SEMS_BASELINES_ARRAY_BEAMFORMER_H
#define INCLUDED_SEMS_BASELINES_ARRAY_BEAMFORMER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/baselines/api.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <memory>

namespace gr {
namespace sems {

/*!
 * \brief Beamforms pilots towards one direction: z_t = a(φ, θ)ᴴ y_t / ‖a(φ, θ)‖², a the
 *        array's steering vector (steering_vector()).
 * \param a the array. \param azimuth_rad φ. \param elevation_rad θ. \param wavelength_m λ.
 * \param y K·L observations, element-major. \param snapshots L ≥ 1. \param z L outputs.
 * \throws std::invalid_argument for L < 1 or a steering vector of zero norm (every element's
 *         pattern null towards φ).
 */
SEMS_BASELINES_API void beamform_pilots(const array_geometry& a, double azimuth_rad, double elevation_rad,
                                        double wavelength_m, const gr_complex* y, int snapshots, gr_complex* z);

/*!
 * \brief Combines each frame of an array's pilots into one antenna's, beamformed towards the
 *        azimuth where the frame's FFT (Bartlett) beamforming spectrum peaks, at elevation 0.
 *
 * \details The peak is found on a grid over [−π/2, π/2] (at least 256 points, 8 per element)
 * and refined between its neighbours (beamforming_angle_estimator): the one-target
 * maximum-likelihood azimuth. At elevation 0 a ULA's scan finds the cone angle, so a target off
 * the horizontal plane is still in the beam; a planar array's beam stays in the horizontal
 * plane. With several targets the strongest is kept. One stream (K = 1) passes its pilots
 * through, divided by the element's gain towards boresight, with no azimuth.
 */
class SEMS_BASELINES_API array_beamformer
{
public:
    /*!
     * \brief A combiner for an array.
     * \param a the array (its virtual elements are the streams). \param wavelength_m λ > 0 (the
     *        pilots' mean frequency's: pilot_wavelength_m()).
     * \throws std::invalid_argument naming a bad setting.
     */
    array_beamformer(const array_geometry& a, double wavelength_m);
    ~array_beamformer(); ///< Destructor.
    /*! \brief K, the streams. \return the array's virtual elements. */
    int n_elements() const { return d_k; }
    /*!
     * \brief Combines one frame.
     * \param y K·L observations, element-major, finite. \param snapshots L ≥ 1. \param z L outputs.
     * \return the azimuth beamformed towards in rad (NaN for one stream: no direction).
     * \throws std::invalid_argument on non-finite input or bad counts.
     */
    double combine(const gr_complex* y, int snapshots, gr_complex* z) const;

private:
    array_geometry d_array;
    double d_lambda;
    int d_k;
    std::unique_ptr<beamforming_angle_estimator> d_search; // empty for one stream
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINES_ARRAY_BEAMFORMER_H */
