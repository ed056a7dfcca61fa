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
#include <vector>

namespace gr {
namespace sems {
namespace nn {

/*!
 * \brief The causal temporal model over a track's frames (learning/temporal/temporal_model.h).
 *
 * \details Two kinds, each deciding after every frame t from frames 1..t only, so a stream's
 * answers (track_classifier::step) are the training's.
 *
 * Kind "gru_fusion" (the default): frame t's evidence e_t (the frame decoder's embedding, with
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
 *
 * Kind "acf_tcn": frame t's evidence is the slow-time autocorrelation of its pilots on the
 * mask's subcarrier with the most pilots (the lowest such subcarrier on a tie), normalised by
 * their power, then the class log-probabilities:
 *
 *     r_k = Σ_{pilot pairs n, n+k} y(n+k)·y*(n) / Σ_n |y(n)|²,   k = 1 .. N−1
 *     e_t = (Re r_1 .. Re r_{N−1}, Im r_1 .. Im r_{N−1}, log p(c | y_t))
 *
 * (N the frame's symbols, r_k = 0 at a lag no pair of pilots spans: the Doppler spectrum's
 * shape, free of the frame's gain and phase; learning/temporal/track_evidence.h). The network
 * reads x_t = e_t with the log-probabilities turned into probabilities p(c | y_t) (all inputs
 * on one scale), through L = dilations.size() causal dilated convolutions of `kernel` taps,
 *
 *     a⁰_t = x_t,   aˡ_t = ReLU(bˡ + Σ_{j=0}^{kernel−1} Wˡ_j · aˡ⁻¹_{t − j·dˡ}),   aˡ⁻¹_s = 0 for s < 1
 *
 * and decides after t frames from the running mean and maximum of the top layer over frames
 * 1..t:
 *
 *     logits_t = V₂ · ReLU(V₁ · [ (1/t) Σ_{i≤t} aᴸ_i ; max_{i≤t} aᴸ_i ] + c₁) + c₂
 *
 * A streamed step keeps the last R = 1 + (kernel − 1)·Σ dˡ frames' inputs (the receptive
 * field), the running mean and maximum and the count (capped at 2^24 frames), and computes only the newest aᴸ_t.
 */
struct SEMS_LEARNING_API temporal_settings {
    /*! \brief The model: "gru_fusion" (the default) or "acf_tcn" (see the details). */
    std::string kind = "gru_fusion";
    int hidden = 64; ///< gru_fusion: the GRU's state size
    /*!
     * \brief gru_fusion: whether each frame's evidence carries its log Doppler profile (a
     *        spectral frame decoder's), so the GRU sees how the slow-time spectrum moves from
     *        frame to frame (a gait's cadence spans many 32 ms frames), not only the frame's
     *        16-d summary.
     */
    bool doppler_profile = true;
    /*!
     * \brief Training only: the share dropped (0 = none; [0, 1)): of the normalised evidence
     *        (gru_fusion), of the running mean and maximum before the head (acf_tcn).
     */
    double dropout = 0.2;
    /*!
     * \brief The first fusion_frames frames of a track are decided by the fusion alone, the
     *        later ones by the model: the trainer sets it to the leading frames over which the
     *        fusion decided better on the validation tracks (one frame is what the frame
     *        decoder was trained for; the model's learned term pays off as frames add up).
     */
    int fusion_frames = 0;
    int channels = 64; ///< acf_tcn: the channels of each convolution
    int kernel = 5;    ///< acf_tcn: the taps of each convolution (1 .. max_kernel)
    /*! \brief acf_tcn: one causal convolution per entry, bottom first, its dilation in frames. */
    std::vector<int> dilations{ 1, 2, 4 };
    int head = 64; ///< acf_tcn: the width of the head's hidden layer

    /*! \brief The kinds, in the order errors list them. \return "gru_fusion", "acf_tcn". */
    static std::vector<std::string> kinds();
    static constexpr int max_kernel = 64;            ///< acf_tcn: the most taps of a convolution
    static constexpr int max_layers = 16;            ///< acf_tcn: the most convolutions
    static constexpr int max_receptive_field = 4096; ///< acf_tcn: the most frames a streamed state keeps
    /*!
     * \brief acf_tcn: R = 1 + (kernel − 1)·Σ dilations, the frames a decision's newest
     *        convolution output reads (and a streamed state keeps).
     * \return R (1 for an empty list).
     */
    int receptive_field() const;

    /*!
     * \brief Checks every setting of the kind (keys of the other kind are left alone).
     * \param source names the settings in errors.
     * \throws std::invalid_argument "<source>: <key>: <problem>".
     */
    void validate(const std::string& source) const;
    /*!
     * \brief The settings as JSON: the kind's own keys, and dropout and fusion_frames.
     * \return the JSON object from_json() reads.
     */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads settings from JSON; missing keys keep their defaults, keys of the other
     *        kind are refused as unknown.
     * \param j the JSON object. \param source names the file or context in errors.
     * \return the settings.
     * \throws std::invalid_argument naming `source` and the bad key (an unknown kind lists the known ones).
     */
    static temporal_settings from_json(const nlohmann::json& j, const std::string& source);
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_TEMPORAL_SETTINGS_H */
