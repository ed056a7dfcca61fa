// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the correlation-driven delay decoder (DESIGN §5).
 *
 *   sparse grid (normalised per frame) -> learned complex projection along slow time,
 *   P outputs (P = 2 gives the paper's 4 x M) -> correlation with the dictionary
 *   D[m,q] = exp(-j2π m Δf τ_q) (r_p[q] = Σ_m x_p[m] conj(D[m,q]), Δf τ_q = τ_q·B / M)
 *   -> features per q: Re r_p, Im r_p and |r_p| (3P x Q) -> 1-D residual CNN -> Q scores
 *   -> soft-argmax τ̂ = Σ_q τ_q softmax(z)_q.
 *
 * The soft-argmax is local: a window of ±`window` grid points around the arg-max (so
 * the tails cannot bias the estimate); window = 0 means global. Both forms subtract the
 * maximum before exponentiating, so logits of ±1e4 are safe, and τ̂ is a convex
 * combination of grid delays: it always lies inside [τ_min, τ_max].
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_DELAY_DECODER_H
#define INCLUDED_SEMS_LIB_LEARNING_DELAY_DECODER_H

#include "learning/task_decoder.h"
#include <gnuradio/sems/learning/network_settings.h>

namespace gr {
namespace sems {
namespace nn {

// Soft-argmax of logits (B x Q) over grid values (Q); window as in the header comment.
SEMS_LEARNING_API torch::Tensor soft_argmax(const torch::Tensor& logits, const torch::Tensor& grid_values, int window);

struct SEMS_LEARNING_API residual_block1d_module : torch::nn::Module {
    residual_block1d_module(int channels, int kernel);
    torch::Tensor forward(const torch::Tensor& x);
    torch::nn::Conv1d conv1{ nullptr }, conv2{ nullptr };
    torch::nn::BatchNorm1d bn1{ nullptr }, bn2{ nullptr };
};
TORCH_MODULE_IMPL(residual_block1d, residual_block1d_module);

class SEMS_LEARNING_API delay_decoder_module : public task_decoder_module
{
public:
    delay_decoder_module(int n_symbols, int n_subcarriers, int n_pilots, delay_settings s);
    decoder_output forward(const torch::Tensor& grid) override;
    std::string kind() const override { return "delay_correlation"; }
    nlohmann::json describe() const override;
    const delay_settings& settings() const { return d_s; }
    // τ_q in delay indices (Q).
    const torch::Tensor& grid_delays() const { return d_tau; }

private:
    int d_n, d_m, d_np;
    delay_settings d_s;
    torch::Tensor d_proj_re, d_proj_im; // P x N
    torch::Tensor d_tau, d_dict_cos, d_dict_sin; // buffers: Q, M x Q, M x Q
    torch::nn::Conv1d d_stem{ nullptr }, d_head{ nullptr };
    torch::nn::BatchNorm1d d_stem_bn{ nullptr };
    torch::nn::Sequential d_blocks{ nullptr };
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_DELAY_DECODER_H */
