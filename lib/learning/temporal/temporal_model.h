// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the causal temporal model over a track (temporal_settings.h has the equations).
 *
 * One module serves training and streaming: forward() runs a whole batch of tracks,
 * step() one frame of one or more tracks from their kept state, and both run the same GRU
 * cell, so a sink's per-frame answers are the training's, step for step.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_TEMPORAL_MODEL_H
#define INCLUDED_SEMS_LIB_LEARNING_TEMPORAL_MODEL_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/temporal/temporal_settings.h>
#include <torch/torch.h>

namespace gr {
namespace sems {
namespace nn {

class SEMS_LEARNING_API temporal_model_module : public torch::nn::Module
{
public:
    // evidence_size: the frame decoder's features + C; n_classes: C (the evidence's last C
    // values are the frame's class log-probabilities).
    temporal_model_module(int evidence_size, int n_classes, temporal_settings s);

    // A batch of tracks: evidence B x T x E -> logits B x T x C, the decision after each frame.
    torch::Tensor forward(const torch::Tensor& evidence);
    // One frame of B tracks: evidence B x E; hidden B x H and fused B x C (the running sum of
    // the frames' log-probabilities) are updated in place. Returns logits B x C.
    torch::Tensor step(const torch::Tensor& evidence, torch::Tensor& hidden, torch::Tensor& fused);

    int evidence_size() const { return d_e; }
    int n_classes() const { return d_c; }
    int hidden_size() const { return d_s.hidden; }
    const temporal_settings& settings() const { return d_s; }
    // The trainer's choice of temporal_settings::fusion_frames (from its validation tracks).
    void set_fusion_frames(int frames) { d_s.fusion_frames = frames; }
    // The decisions over tracks (B x T, long): the fusion's for the first fusion_frames frames
    // (the argmax of the summed log-probabilities in `evidence`), the GRU's `logits` after them.
    torch::Tensor decide(const torch::Tensor& logits, const torch::Tensor& evidence) const;
    // {"kind", "settings"} as bundle.json's track.temporal records it.
    nlohmann::json describe() const;

private:
    int d_e, d_c;
    temporal_settings d_s;
    torch::nn::LayerNorm d_norm{ nullptr }; // the evidence on one scale (embeddings and log-probabilities differ)
    torch::nn::Dropout d_drop{ nullptr };   // training only (identity in eval mode and in the streamed step)
    torch::nn::GRUCell d_cell{ nullptr };
    torch::nn::Linear d_head{ nullptr };
    torch::Tensor d_fusion_weight; // λ
};
TORCH_MODULE_IMPL(temporal_model, temporal_model_module);

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_TEMPORAL_MODEL_H */
