// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Decisions over a track from a track bundle (docs/design.md §5, decisions over a
 *        track): the frame decoder's evidence per frame, then one causal step per frame.
 */
#ifndef INCLUDED_SEMS_LEARNING_TRACK_CLASSIFIER_H
#define INCLUDED_SEMS_LEARNING_TRACK_CLASSIFIER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/temporal/temporal_settings.h>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Classifies a target from every frame of its track so far.
 *
 * \details A track bundle is a classifier bundle (its mask, frame decoder and weights) with a
 * `track` record in bundle.json: the temporal model (temporal_settings), its weights file and
 * how it was trained. Per frame, evidence() runs the frame decoder (batched over frames of any
 * tracks; for kind acf_tcn also the autocorrelation of the frame's pilots), and step() folds
 * one frame's evidence into its track's state and answers: one GRU step (gru_fusion) or the
 * newest output of the causal convolutions from the frames of their receptive field (acf_tcn),
 * never a pass over the track again. The state is the caller's, one per track, so a
 * caller can keep many tracks apart (classifier_sink follows one at a time). LibTorch stays behind this header.
 *
 * Beside the learned decision, step() gives the classical fusion of independent frames, the
 * normalised product of the frames' posteriors (softmax of the summed log-probabilities), from
 * the same state: the reference a decision over a track must beat.
 */
class SEMS_LEARNING_API track_classifier
{
public:
    /*! \brief One track's state: what its frames so far left. */
    struct state {
        /*!
         * \brief The model's state: the GRU's (temporal_settings::hidden values) for
         *        gru_fusion; for acf_tcn the inputs of the last receptive_field() frames, the
         *        running mean and maximum of the top layer (2 x channels) and the count.
         */
        std::vector<float> hidden;
        std::vector<float> fused;  ///< Σ log p(c | frame) over its frames (C values)
        uint64_t frames = 0;       ///< frames seen: the evidence time
    };

    /*!
     * \brief Loads a track bundle.
     * \param bundle a classifier bundle with a `track` record (model_bundle::track).
     * \param threads LibTorch intra-op threads, as bundle_decoder's.
     * \throws std::invalid_argument naming bundle.json or the weights file and the problem
     *         (a bundle without `track`, or of an unknown temporal model kind, included), or,
     *         for kind acf_tcn, the mask file when no subcarrier of the mask holds two pilots.
     */
    explicit track_classifier(const model_bundle& bundle, int threads = 1);
    /*!
     * \brief The same on an already loaded frame decoder (a sink's, checked against its stream).
     * \param frames the bundle's frame decoder.
     * \throws std::invalid_argument as the other constructor.
     */
    explicit track_classifier(std::unique_ptr<bundle_decoder> frames);
    ~track_classifier(); ///< Destructor.

    /*! \brief Whether a bundle decides over tracks. \param b the bundle. \return true when it has a `track` record. */
    static bool is_track_bundle(const model_bundle& b) { return !b.track.is_null(); }
    /*! \brief The track record's weights file name. */
    static constexpr const char* weights_file = "temporal.pt";

    /*! \brief The bundle. \return the bundle it was loaded from. */
    const model_bundle& bundle() const;
    /*! \brief N_p. \return the observations per frame. */
    int n_pilots() const;
    /*! \brief F. \return the frames the bundle's mask spans (1 for one frame's mask). */
    int super_frames() const;
    /*! \brief C. \return the classes. */
    int n_classes() const;
    /*!
     * \brief The evidence one frame gives.
     * \return its values per frame: for gru_fusion the features, the log Doppler profile when
     *         the settings' doppler_profile is on, and C; for acf_tcn the 2·(N−1) values of the
     *         pilots' autocorrelation and C (temporal_settings). The last C are the frame's
     *         class log-probabilities either way.
     */
    int evidence_size() const;
    /*! \brief The temporal model's settings. \return the settings. */
    const nn::temporal_settings& settings() const;

    /*! \brief A new track's state. \return the state before any frame. */
    state begin() const;
    /*!
     * \brief The frame decoder's evidence for frames of any tracks (bundle_decoder::evidence).
     * \param obs batch x N_p observations. \param batch the number of frames.
     * \param sets each frame's set of a super-frame mask, its frame index mod F (may be null when F = 1).
     * \return batch x evidence_size() values.
     * \throws std::invalid_argument on a frame with NaN or Inf, or sets missing or out of range for a super-frame.
     */
    std::vector<float> evidence(const gr_complex* obs, int batch, const int* sets = nullptr) const;
    /*!
     * \brief One frame of one track: folds its evidence into the state and answers.
     * \param s the track's state (updated). \param evidence evidence_size() values.
     * \param probs out: C probabilities of the decision over the track's frames so far.
     * \param fusion_probs out (may be null): C probabilities of the product of per-frame posteriors.
     */
    void step(state& s, const float* evidence, float* probs, float* fusion_probs = nullptr) const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_TRACK_CLASSIFIER_H */
