// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the causal temporal model over a track (temporal_settings.h has the equations).
 *
 * track_model_module is what the trainer and the track classifier need of any kind:
 * forward() runs a whole batch of tracks and gives the decision after every frame.
 * make_temporal_model() builds the kind the settings name. Kind "gru_fusion" is
 * temporal_model_module below: its step() runs one frame of one or more tracks from their
 * kept state with the same GRU cell forward() runs, so a sink's per-frame answers are the
 * training's, step for step. Kind "acf_tcn" is in tcn_model.h.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_TEMPORAL_MODEL_H
#define INCLUDED_SEMS_LIB_LEARNING_TEMPORAL_MODEL_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/temporal/temporal_settings.h>
#include <torch/torch.h>
#include <memory>

namespace gr {
namespace sems {
namespace nn {

// Any kind of temporal model.
class SEMS_LEARNING_API track_model_module : public torch::nn::Module
{
public:
    // evidence_size: the evidence per frame, whose last C values are the frame's class
    // log-probabilities; n_classes: C. Refuses fewer than 2 classes or an evidence shorter than C.
    track_model_module(int evidence_size, int n_classes, temporal_settings s);
    ~track_model_module() override = default;

    // A batch of tracks: evidence B x T x E -> logits B x T x C, the decision after each frame
    // from that frame and the ones before it only.
    virtual torch::Tensor forward(const torch::Tensor& evidence) = 0;
    // The values of one track's streamed state (track_classifier::state::hidden).
    virtual int hidden_size() const = 0;

    int evidence_size() const { return d_e; }
    int n_classes() const { return d_c; }
    const temporal_settings& settings() const { return d_s; }
    // The trainer's choice of temporal_settings::fusion_frames (from its validation tracks).
    void set_fusion_frames(int frames) { d_s.fusion_frames = frames; }
    // The decisions over tracks (B x T, long): the fusion's for the first fusion_frames frames
    // (the argmax of the summed log-probabilities in `evidence`), the model's `logits` after them.
    torch::Tensor decide(const torch::Tensor& logits, const torch::Tensor& evidence) const;
    // {"kind", "settings"} as bundle.json's track.temporal records it.
    nlohmann::json describe() const;

protected:
    int d_e, d_c;
    temporal_settings d_s;
};

// Kind "gru_fusion".
class SEMS_LEARNING_API temporal_model_module : public track_model_module
{
public:
    temporal_model_module(int evidence_size, int n_classes, temporal_settings s);

    torch::Tensor forward(const torch::Tensor& evidence) override;
    // One frame of B tracks: evidence B x E; hidden B x H and fused B x C (the running sum of
    // the frames' log-probabilities) are updated in place. Returns logits B x C.
    torch::Tensor step(const torch::Tensor& evidence, torch::Tensor& hidden, torch::Tensor& fused);
    int hidden_size() const override { return d_s.hidden; }

private:
    torch::nn::LayerNorm d_norm{ nullptr }; // the evidence on one scale (embeddings and log-probabilities differ)
    torch::nn::Dropout d_drop{ nullptr };   // training only (identity in eval mode and in the streamed step)
    torch::nn::GRUCell d_cell{ nullptr };
    torch::nn::Linear d_head{ nullptr };
    torch::Tensor d_fusion_weight; // λ
};
TORCH_MODULE_IMPL(temporal_model, temporal_model_module);

// The model of the settings' kind (refused by name when unknown).
SEMS_LEARNING_API std::shared_ptr<track_model_module>
make_temporal_model(int evidence_size, int n_classes, const temporal_settings& s);

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_TEMPORAL_MODEL_H */
