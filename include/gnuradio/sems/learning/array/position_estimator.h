// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Where the target of interest is, from an array's pilots: its delay and its azimuth,
 *        from a position bundle (docs/reference/arrays.md, "The learned position decoder").
 */
#ifndef INCLUDED_SEMS_LEARNING_POSITION_ESTIMATOR_H
#define INCLUDED_SEMS_LEARNING_POSITION_ESTIMATOR_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

/*! \brief One frame's answer. */
struct SEMS_LEARNING_API position_estimate {
    double delay_s = 0.0;     ///< the target of interest's round-trip delay
    double delay_index = 0.0; ///< the same as τ·B
    double range_m = 0.0;     ///< cτ/2
    double azimuth_rad = 0.0; ///< its line of sight's azimuth (elevation 0), array_geometry.h's frame
};

/*!
 * \brief The learned position decoder of a position bundle.
 * \details A position bundle is a delay bundle (its mask, its delay decoder and weights) with a
 * `position` record in bundle.json: the array, the angle network's settings
 * (nn::angle_settings), its weights file and how it was trained. Per frame, of an array with
 * N_r receive elements and one transmit element, the observations are N_r·N_p values,
 * element-major (the pilot extractor's output):
 *  1. the angle network maps the beamforming spectrum of the frame's pilots to an azimuth, which
 *     the spectrum's own maximum nearby then polishes (beamforming_angle_estimator::refine,
 *     kept when it lies within ±polish_steps grid steps);
 *  2. the pilots beamformed towards that azimuth, z_p = a(φ̂)ᴴ y_p / ‖a(φ̂)‖² (the target's
 *     one-antenna pilots with the array's gain against noise), go through the bundle's delay
 *     decoder.
 * The steering vectors are the emulator's (steering.h), narrowband at the pilots' mean
 * frequency (pilot_wavelength_m). A frame with NaN or Inf is refused as bundle_decoder refuses
 * it. LibTorch stays behind this header.
 */
class SEMS_LEARNING_API position_estimator
{
public:
    static constexpr const char* weights_file = "angle.pt"; ///< the angle network's weights in a position bundle

    /*!
     * \brief Loads a position bundle.
     * \param bundle a delay bundle with a `position` record (model_bundle::position).
     * \param threads LibTorch intra-op threads, as bundle_decoder's.
     * \throws std::invalid_argument naming bundle.json or the weights file and the problem (a
     *         bundle without `position` included).
     */
    explicit position_estimator(const model_bundle& bundle, int threads = 1);
    /*!
     * \brief The same on an already loaded delay decoder (a sink's, checked against its stream).
     * \param delay the bundle's delay decoder. \param threads as above.
     * \throws std::invalid_argument as the other constructor.
     */
    explicit position_estimator(std::unique_ptr<bundle_decoder> delay, int threads = 1);
    ~position_estimator(); ///< Destructor.

    /*! \brief The bundle. \return the bundle the estimator was loaded from. */
    const model_bundle& bundle() const;
    /*! \brief The array. \return the array the bundle was trained for. */
    const array_geometry& array() const;
    /*! \brief N_r. \return the receive elements (the streams of a frame). */
    int n_elements() const;
    /*! \brief N_p. \return the pilots per element. */
    int n_pilots() const;

    /*!
     * \brief Delay and azimuth of the target of interest.
     * \param obs batch x (N_r·N_p) observations, each frame element-major.
     * \param batch the number of frames.
     * \return one estimate per frame.
     * \throws std::invalid_argument on a frame with NaN or Inf (naming the frame, its element and pilot).
     */
    std::vector<position_estimate> estimate(const gr_complex* obs, int batch) const;
    /*!
     * \brief The azimuth alone (step 1 above).
     * \param obs as estimate(). \param batch the number of frames.
     * \param polish false: the network's estimate without the polish (for comparison).
     * \return the azimuths in rad.
     * \throws std::invalid_argument as estimate().
     */
    std::vector<double> estimate_azimuth(const gr_complex* obs, int batch, bool polish = true) const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_POSITION_ESTIMATOR_H */
