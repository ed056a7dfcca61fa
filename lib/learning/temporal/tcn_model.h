// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the temporal model of kind "acf_tcn" (temporal_settings.h has the equations):
 * causal dilated convolutions over a track's frames, the running mean and maximum of the
 * top layer, and a head, deciding after every frame.
 *
 * Two halves that give the same answers: tcn_model_module's forward() runs a whole batch of
 * tracks for training (convolutions padded on the left only, so frame t sees frames 1..t),
 * and tcn_stepper streams one frame of one track from its kept state, computing only the
 * newest top-layer output from the receptive field's frames (the track classifier's step).
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_TCN_MODEL_H
#define INCLUDED_SEMS_LIB_LEARNING_TCN_MODEL_H

#include "learning/temporal/temporal_model.h"
#include <memory>
#include <vector>

namespace gr {
namespace sems {
namespace nn {

class SEMS_LEARNING_API tcn_model_module : public track_model_module
{
public:
    // The settings' kind must be "acf_tcn" (validated, as temporal_settings::validate).
    tcn_model_module(int evidence_size, int n_classes, temporal_settings s);

    torch::Tensor forward(const torch::Tensor& evidence) override;
    // R·E inputs of the receptive field, the running mean and maximum (2 x channels) and the count.
    int hidden_size() const override;
    // What the convolutions read of evidence (... x E): the same with its last C values, the
    // log-probabilities, turned into probabilities (on the autocorrelation's scale).
    torch::Tensor inputs(const torch::Tensor& evidence) const;

    const std::vector<torch::nn::Conv1d>& convolutions() const { return d_conv; }
    const torch::nn::Linear& head_hidden() const { return d_head1; }
    const torch::nn::Linear& head_out() const { return d_head2; }

private:
    std::vector<torch::nn::Conv1d> d_conv;
    torch::nn::Dropout d_drop{ nullptr }; // training only: on the running mean and maximum
    torch::nn::Linear d_head1{ nullptr }, d_head2{ nullptr };
};
TORCH_MODULE_IMPL(tcn_model, tcn_model_module);

// One frame of one track at a time, on a copy of a module's weights (Eigen behind the pimpl:
// a step is a few small matrix-vector products, far below what building LibTorch tensors per
// frame costs).
class SEMS_LEARNING_API tcn_stepper
{
public:
    explicit tcn_stepper(const tcn_model_module& m);
    ~tcn_stepper();

    // The state's values (tcn_model_module::hidden_size()); a new track's state is all zero.
    int state_size() const;
    // Folds one frame's evidence (E values) into `state` and writes the decision after it
    // (C logits): forward()'s row for that frame.
    void step(float* state, const float* evidence, float* logits) const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_TCN_MODEL_H */
