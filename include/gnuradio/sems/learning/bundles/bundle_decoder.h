// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Inference on a model bundle.
 */
#ifndef INCLUDED_SEMS_LEARNING_BUNDLE_DECODER_H
#define INCLUDED_SEMS_LEARNING_BUNDLE_DECODER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Inference on a model bundle, shared by the sinks, the evaluation app and the bindings.
 * \details Rebuilds the decoder network from bundle.json, loads its weights and maps pilot
 * observations (Y/x_k at the mask positions, x_k the pilot sent, in mask order) to answers. LibTorch stays
 * behind this header (pimpl), so blocks and bindings need no torch headers.
 *
 * Non-finite input: a frame holding NaN or Inf (real or imaginary part, any pilot) is never
 * decoded. classify(), estimate_delay(), estimate_delay_index() and features() refuse a
 * batch that holds one with std::invalid_argument (ValueError in Python) naming the
 * method (estimate_delay for both delay methods), the index of the first such frame in the batch and its pilot, and answer no
 * frame of that batch: the caller leaves the frame out. The sinks do so: they count such
 * a frame in `frames_skipped` and never hand it to the decoder (docs/reference/sinks.md).
 *
 * Super-frame masks: a classifier bundle whose mask spans F > 1 frames (model_bundle::super_frame)
 * decodes each frame at the pilots of its own set, frame index mod F, which classify(),
 * features() and evidence() take per frame (`sets`); the frames of one set go through the
 * network together. Without `sets` such a bundle refuses the batch, naming F. For F = 1
 * `sets` may be left out, and the answers are those of a one-frame mask bit for bit.
 */
class SEMS_LEARNING_API bundle_decoder
{
public:
    /*!
     * \brief Loads a bundle's decoder.
     * \param bundle the bundle (from model_bundle::load).
     * \param threads LibTorch intra-op threads; <= 0 leaves LibTorch's count alone; > 0 is
     *        applied in the thread that runs each inference (LibTorch's OpenMP count is per
     *        thread), so two decoders (two sinks) in one process each keep the count they
     *        were given.
     * \throws std::invalid_argument naming the weights file and the problem.
     */
    explicit bundle_decoder(const model_bundle& bundle, int threads = 1);
    ~bundle_decoder(); ///< Destructor.

    /*! \brief The bundle. \return the bundle the decoder was loaded from. */
    const model_bundle& bundle() const;
    /*! \brief N_p. \return the observations per frame. */
    int n_pilots() const;
    /*! \brief F. \return the frames the bundle's mask spans (1 for one frame's mask). */
    int super_frames() const;

    /*!
     * \brief Classifies frames.
     * \param obs batch x N_p observations, row-major. \param batch the number of frames.
     * \param sets each frame's set of a super-frame mask, in [0, F) (may be null when F = 1).
     * \return batch x C class probabilities, row-major.
     * \throws std::invalid_argument on a frame with NaN or Inf (see the class), a delay bundle,
     *         or sets missing or out of range for a super-frame.
     */
    std::vector<float> classify(const gr_complex* obs, int batch, const int* sets = nullptr) const;
    /*!
     * \brief Estimates the delay of the target of interest.
     * \param obs batch x N_p observations. \param batch the number of frames.
     * \return the delays in s.
     * \throws std::invalid_argument on a frame with NaN or Inf (see the class), or a classifier bundle.
     */
    std::vector<double> estimate_delay(const gr_complex* obs, int batch) const;
    /*!
     * \brief The same estimate as estimate_delay() as a delay index (τ·B).
     * \param obs batch x N_p observations. \param batch the number of frames.
     * \return the delay indices.
     * \throws std::invalid_argument on a frame with NaN or Inf (see the class), or a classifier bundle.
     */
    std::vector<double> estimate_delay_index(const gr_complex* obs, int batch) const;
    /*!
     * \brief Classifier only: the embeddings (for t-SNE).
     * \param obs batch x N_p observations. \param batch the number of frames.
     * \param sets each frame's set of a super-frame mask (as classify()).
     * \return batch x feature_size() values, row-major.
     * \throws std::invalid_argument on a frame with NaN or Inf (see the class), or a delay bundle.
     */
    std::vector<float> features(const gr_complex* obs, int batch, const int* sets = nullptr) const;
    /*! \brief The embedding size. \return the features per frame. */
    int feature_size() const;
    /*!
     * \brief Classifier only: what one frame tells a decision over a track: the embedding,
     *        optionally the frame's log Doppler profile, and the class log-probabilities.
     * \param obs batch x N_p observations. \param batch the number of frames.
     * \param doppler_profile add the spectral classifier's log Doppler profile (its
     *        doppler_bins values per channel, before its BatchNorm: what the network sees of the
     *        frame's slow time); refused for other decoders.
     * \param sets each frame's set of a super-frame mask (as classify()).
     * \return batch x evidence_size(doppler_profile) values, row-major: features, the profile
     *         when asked, then log p(c | frame) last.
     * \throws std::invalid_argument on a frame with NaN or Inf (see the class), a delay bundle,
     *         or a profile asked of a decoder without one.
     */
    std::vector<float>
    evidence(const gr_complex* obs, int batch, bool doppler_profile = false, const int* sets = nullptr) const;
    /*!
     * \brief The values per frame evidence() gives.
     * \param doppler_profile with the Doppler profile.
     * \return feature_size() + the profile's values (when asked) + C; 0 for a delay bundle.
     * \throws std::invalid_argument when a profile is asked of a decoder without one.
     */
    int evidence_size(bool doppler_profile = false) const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_BUNDLE_DECODER_H */
