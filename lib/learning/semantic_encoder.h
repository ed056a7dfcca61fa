// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the semantic encoder, N_p Gumbel-Softmax pilot heads (DESIGN §5).
 *
 * Each head r has a learned embedding e_r; a small MLP maps it to a score matrix
 * Z_r over the N x M grid (by default factorised, Z_r[n,m] = a_r[n] + b_r[m]; see
 * encoder_settings::factorized). Training draws a relaxed one-hot
 *     S_r = softmax((Z_r + g_r) / τ),   g_r ~ Gumbel(0, 1),
 * and uses the straight-through estimator: the forward value is the exact hard one-hot
 * of argmax S_r (hard + (soft - soft.detach()), which adds an exact zero), the
 * gradient is that of the soft S_r. τ is annealed per epoch down to a floor. While
 * τ is above `soft_above` the forward pass uses the soft S_r itself (a warm-up: the
 * decoder first learns from a dense, weighted grid, and the scores learn which
 * elements it uses); from then on the forward pass is the exact one-hot.
 *
 * Numerics: the uniform draw is clamped to [1e-6, 1 - 1e-6] before g = -log(-log u),
 * so g is finite; the softmax is computed as exp(log_softmax(.)), which subtracts the
 * row maximum, so logits of ±1e4 at the floor temperature give no NaN or Inf.
 *
 * No two heads end on the same resource element, guaranteed in two layers:
 *  - during training a collision penalty Σ_{r≠s} <p_r, p_s> (p = softmax(Z/τ)) pushes
 *    heads apart, and
 *  - the final mask is a sequential greedy assignment: heads, most confident first
 *    (largest max score), each take their best-scoring element that no earlier head
 *    took. This yields exactly N_p distinct positions whatever the scores are.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_SEMANTIC_ENCODER_H
#define INCLUDED_SEMS_LIB_LEARNING_SEMANTIC_ENCODER_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/network_settings.h>
#include <gnuradio/sems/core/pilot_mask.h>
#include <torch/torch.h>
#include <vector>

namespace gr {
namespace sems {
namespace nn {

// The Gumbel-Softmax straight-through sample of score rows (R x K): exact one-hot
// forward, soft gradient. `uniform` (R x K, values in [0,1]) may be given for tests;
// it is clamped to [1e-6, 1-1e-6]. hard = false returns the relaxed (soft) sample.
SEMS_LEARNING_API torch::Tensor gumbel_softmax_st(const torch::Tensor& scores,
                                         double temperature,
                                         const torch::Tensor& uniform = {},
                                         bool hard = true);

class SEMS_LEARNING_API semantic_encoder_module : public torch::nn::Module
{
public:
    semantic_encoder_module(int n_pilots, int n_symbols, int n_subcarriers, encoder_settings s = {});

    // Z: N_p x (N*M) scores.
    torch::Tensor scores();
    // One selection S (N_p x N*M) at temperature τ: straight-through exact one-hot rows,
    // or the soft sample while τ > settings().soft_above.
    torch::Tensor sample(double temperature);
    // The 0/1 (or, on a collision, >1) mask N x M seen by the decoder: Σ_r S_r.
    static torch::Tensor mask_from_selection(const torch::Tensor& selection, int n_symbols, int n_subcarriers);
    // Σ_{r≠s} <p_r, p_s> with p = softmax(Z/τ): zero when heads want distinct elements.
    torch::Tensor collision_penalty(double temperature);
    // Greedy distinct assignment (see the header comment): N_p distinct flat indices.
    std::vector<int64_t> final_indices();
    // Number of distinct elements the heads' arg-max currently picks (progress display).
    int distinct_argmax();

    int n_pilots() const { return d_np; }
    const encoder_settings& settings() const { return d_s; }

private:
    int d_np, d_n, d_m;
    encoder_settings d_s;
    torch::Tensor d_embedding;
    torch::nn::Linear d_fc1{ nullptr }, d_fc2{ nullptr };
};
TORCH_MODULE_IMPL(semantic_encoder, semantic_encoder_module);

// Greedy distinct assignment on a score matrix (R x K, R <= K), exposed for tests.
SEMS_LEARNING_API std::vector<int64_t> greedy_distinct_assignment(const torch::Tensor& scores);

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_SEMANTIC_ENCODER_H */
