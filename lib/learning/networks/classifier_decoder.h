// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the classifier decoder (docs/design.md §5, the paper's ResNet classifier).
 *
 *   sparse 2 x N x M grid -> per-frame normalisation -> stem conv2d with a 3 x M kernel
 *   (3 symbols by the whole band: a learned frequency projection, so the map becomes
 *   width x N x 1) -> `depth` basic residual blocks of 3 x 1 conv2d along slow time ->
 *   flatten -> MLP (hidden) -> 16-d features -> C logits.
 *
 * Why the stem spans the band: the class lives in slow time (Doppler, micro-Doppler),
 * the delay phase across subcarriers is a nuisance; collapsing M first makes the
 * network ~20x cheaper than 3 x 3 convolutions over the sparse 32 x 64 grid (which
 * matters on a CPU) and lets pilots that share subcarriers add up coherently.
 *
 * The 16-d features are exposed for the evaluation's t-SNE.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_CLASSIFIER_DECODER_H
#define INCLUDED_SEMS_LIB_LEARNING_CLASSIFIER_DECODER_H

#include "learning/networks/task_decoder.h"
#include <gnuradio/sems/learning/networks/network_settings.h>

namespace gr {
namespace sems {
namespace nn {

// Basic residual block: conv3x3-BN-ReLU-conv3x3-BN + (projected) shortcut, ReLU.
struct SEMS_LEARNING_API residual_block2d_module : torch::nn::Module {
    residual_block2d_module(int in, int out, int stride);
    torch::Tensor forward(const torch::Tensor& x);
    torch::nn::Conv2d conv1{ nullptr }, conv2{ nullptr }, shortcut{ nullptr };
    torch::nn::BatchNorm2d bn1{ nullptr }, bn2{ nullptr }, bn_sc{ nullptr };
};
TORCH_MODULE_IMPL(residual_block2d, residual_block2d_module);

class SEMS_LEARNING_API classifier_decoder_module : public task_decoder_module
{
public:
    classifier_decoder_module(int n_symbols, int n_subcarriers, int n_pilots, classifier_settings s);
    decoder_output forward(const torch::Tensor& grid) override;
    std::string kind() const override { return "classifier_resnet"; }
    nlohmann::json describe() const override;
    const classifier_settings& settings() const { return d_s; }

private:
    int d_n, d_m, d_np;
    classifier_settings d_s;
    torch::nn::Conv2d d_stem{ nullptr };
    torch::nn::BatchNorm2d d_stem_bn{ nullptr };
    torch::nn::Sequential d_stages{ nullptr };
    torch::nn::Linear d_fc1{ nullptr }, d_fc2{ nullptr }, d_out{ nullptr };
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_CLASSIFIER_DECODER_H */
