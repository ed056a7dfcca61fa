// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The size of the temporal model that decides over a track (docs/design.md §5), the
 *        one place its defaults live. Torch-free, as the other network settings.
 */
#ifndef INCLUDED_SEMS_LEARNING_TEMPORAL_SETTINGS_H
#define INCLUDED_SEMS_LEARNING_TEMPORAL_SETTINGS_H

#include <gnuradio/sems/learning/api.h>
#include <nlohmann/json.hpp>
#include <string>

namespace gr {
namespace sems {
namespace nn {

/*!
 * \brief The causal temporal model over a track's frames (learning/temporal/temporal_model.h).
 *
 * \details Kind "gru_fusion": frame t's evidence e_t (the frame decoder's embedding, with
 * doppler_profile its log Doppler profile, and its class log-probabilities log p(c | y_t),
 * bundle_decoder::evidence) drives a GRU cell, h_t = GRU(LayerNorm(e_t), h_{t−1}), and the
 * decision after t frames is
 *
 *     logits_t = W·h_t + b + λ · Σ_{i≤t} log p(c | y_i)
 *
 * The second term is the classical fusion of independent frames (the product of per-frame
 * posteriors) with a learned weight λ, started at 1 with W at 0: training starts from the
 * fusion and learns what it misses (frames that are not independent, evidence that only
 * builds up over several frames). One GRU step per frame, whatever the track's length.
 */
struct SEMS_LEARNING_API temporal_settings {
    std::string kind = "gru_fusion"; ///< the only kind so far
    int hidden = 64;                 ///< GRU state size
    /*!
     * \brief Whether each frame's evidence carries its log Doppler profile (a spectral frame
     *        decoder's), so the GRU sees how the slow-time spectrum moves from frame to frame
     *        (a gait's cadence spans many 32 ms frames), not only the frame's 16-d summary.
     */
    bool doppler_profile = true;
    double dropout = 0.2; ///< training only: the share of the normalised evidence dropped (0 = none; [0, 1))
    /*!
     * \brief The first fusion_frames frames of a track are decided by the fusion alone, the
     *        later ones by the GRU: the trainer sets it to the leading frames over which the
     *        fusion decided better on the validation tracks (one frame is what the frame
     *        decoder was trained for; the GRU's learned term pays off as frames add up).
     */
    int fusion_frames = 0;

    /*! \brief The settings as JSON. \return the JSON object from_json() reads. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; missing keys keep their defaults.
     * \param j the JSON object. \param source names the file or context in errors.
     * \return the settings.
     * \throws std::invalid_argument naming `source` and the bad key.
     */
    static temporal_settings from_json(const nlohmann::json& j, const std::string& source);
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_TEMPORAL_SETTINGS_H */
