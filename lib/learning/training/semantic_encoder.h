// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the semantic encoder, which N_p resource elements carry pilots (docs/design.md §5).
 *
 * Two kinds (encoder_settings::kind), both trained jointly with the task decoder and
 * both hard in the forward pass from the first step (exact 0/1 masks; only the gradient
 * is relaxed) unless encoder_settings::soft_epochs asks for a soft warm-up:
 *
 * "gumbel_topk" (the default; deep probabilistic subsampling, Huijben et al. 2020).
 *   One score matrix with symbol x subcarrier structure,
 *       Z[n,m] = a[n] + b[m]   (+ F[n,m] with free_scores),
 *   a, b, F learned directly (zero at the start: the first masks are uniformly random).
 *   A step draws g ~ Gumbel(0,1) per element and takes the N_p largest of Z + g: N_p
 *   distinct elements by construction, a sample without replacement from softmax(Z).
 *   Backward: the i-th pick's relaxed one-hot is softmax((Z + g)/τ) over the elements the
 *   earlier picks left (Σ_i of them is the soft mask); the forward value is the exact
 *   hard mask (hard + (soft - soft.detach())). Because a[n] and b[m] collect the gradient
 *   of a whole row or column, a preference for one subcarrier (Doppler) or one symbol
 *   (delay) forms within an epoch. The final mask is the N_p largest of Z.
 *
 * "gumbel_heads" (the paper's form, for comparison). Head r has a learned embedding e_r;
 *   a small MLP maps it to scores Z_r over the grid (factorised a_r[n] + b_r[m] by
 *   default), and S_r = softmax((Z_r + g_r)/τ) with the straight-through exact one-hot.
 *   Heads may pick the same element during training (the mask then holds a 2); an
 *   optional collision penalty Σ_{r≠s} <p_r, p_s> (p = softmax(Z/τ), weight
 *   collision_weight, 0 by default: it forbids pilots from sharing a subcarrier while
 *   the heads still agree) pushes them apart; the final mask is a sequential greedy
 *   assignment (heads, most confident first, each take their best element no earlier
 *   head took): exactly N_p distinct positions whatever the scores.
 *
 * Pilot energy (learn_power): one more learned logit per resource element, w (zero at the
 * start: equal power). The selected pilots' energies are
 *     p = f + (1 - f)·N_p·softmax(w over the selected elements),
 * so mean(p) = 1 (the total pilot energy of equal power) and every p_k >= f, the floor.
 *
 * τ is annealed per epoch down to a floor (it shapes the gradient only; the scores'
 * scale, set by their learning rate lr_scale, decides how random the hard masks are).
 *
 * Guard subcarriers (frame_settings::guard_subcarriers) get a score of -inf in both kinds:
 * no Gumbel draw, relaxed row or final mask selects them.
 *
 * Numerics: the uniform draw is clamped to [1e-6, 1 - 1e-6] before g = -log(-log u), so
 * g is finite; every softmax is exp(log_softmax(.)), which subtracts the maximum, and
 * taken elements are masked with -inf while at least one element stays free, so scores
 * of ±1e4 at τ = 1e-3 give no NaN or Inf.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_SEMANTIC_ENCODER_H
#define INCLUDED_SEMS_LIB_LEARNING_SEMANTIC_ENCODER_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
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

/*!
 * \brief Gumbel top-k with a relaxed backward pass (deep probabilistic subsampling).
 * \param scores K scores (one row, e.g. the flat N x M grid).
 * \param k picks, 1 <= k <= K.
 * \param temperature τ > 0 of the relaxation (gradient only).
 * \param uniform optional K uniform draws in [0,1] (tests); clamped to [1e-6, 1-1e-6].
 * \param hard_forward false: return the relaxed rows themselves (soft warm-up).
 * \return k x K: row i is the exact one-hot of the i-th largest of scores + g (forward),
 *         with the gradient of softmax((scores + g)/τ) over the elements rows < i left.
 *         The rows pick k distinct elements.
 */
SEMS_LEARNING_API torch::Tensor gumbel_topk_st(const torch::Tensor& scores,
                                               int k,
                                               double temperature,
                                               const torch::Tensor& uniform = {},
                                               bool hard_forward = true);

/*!
 * \brief gumbel_topk_st(...).sum(0) computed in O(K + k) memory: the mask of the k picks
 *        (forward: exactly 1 on each pick, 0 elsewhere), with the relaxed rows' column sums
 *        as its gradient.
 * \details Row i's relaxation is e_j / Z_i over the elements j not picked before it, with
 * e = exp((scores + g)/τ) and Z_i = U + Σ_{t ≥ i} e_{pick t} (U: the sum over unpicked
 * elements), so column j sums to e_j·Σ_{i ≤ t} 1/Z_i when j is pick t and e_j·Σ_i 1/Z_i when
 * it is not picked. The dense k x K rows need 4·k·K bytes per temporary (4 GiB at
 * k = 1 024 pilots of a 256 x 4 096 grid); this needs a few K-vectors. Equal to the dense
 * column sums up to float rounding (same draws from `uniform` or the global generator).
 */
SEMS_LEARNING_API torch::Tensor gumbel_topk_mask_st(const torch::Tensor& scores,
                                                    int k,
                                                    double temperature,
                                                    const torch::Tensor& uniform = {},
                                                    bool hard_forward = true);

class SEMS_LEARNING_API semantic_encoder_module : public torch::nn::Module
{
public:
    // learn_power: also learn the pilots' energies (power logits; see the file comment).
    // guard_subcarriers: columns no pilot may take (the frame's guards); their scores are
    // -inf, so no draw, relaxation or final mask ever selects them.
    semantic_encoder_module(int n_pilots,
                            int n_symbols,
                            int n_subcarriers,
                            encoder_settings s = {},
                            bool learn_power = false,
                            const std::vector<int>& guard_subcarriers = {});

    //! Scores: gumbel_heads N_p x (N*M), one row per head; gumbel_topk 1 x (N*M).
    torch::Tensor scores();
    /*!
     * \brief One selection at temperature τ: N_p x (N*M), row i one pilot.
     * \param hard true: exact one-hot rows forward, relaxed gradient (straight-through);
     *        false: the relaxed rows themselves (soft warm-up).
     */
    torch::Tensor sample(double temperature, bool hard = true);
    //! The mask N x M seen by the decoder: Σ_r S_r (0/1; a 2 where two heads collide).
    static torch::Tensor mask_from_selection(const torch::Tensor& selection, int n_symbols, int n_subcarriers);
    /*!
     * \brief mask_from_selection(sample(τ, hard)) without the N_p x (N*M) selection when it
     *        would be large (gumbel_topk with N_p·N·M > 2^24: gumbel_topk_mask_st); the same
     *        draws, and the same bits below that size.
     */
    torch::Tensor sample_mask(double temperature, bool hard = true);
    //! gumbel_heads: Σ_{r≠s} <p_r, p_s> with p = softmax(Z/τ); gumbel_topk: 0 (no collisions).
    torch::Tensor collision_penalty(double temperature);
    //! The final mask: N_p distinct flat indices (top-k of Z, or the greedy assignment).
    std::vector<int64_t> final_indices();
    //! Distinct elements the current argmax picks (gumbel_heads; N_p for gumbel_topk).
    int distinct_argmax();

    //! Whether the encoder learns the pilots' energies.
    bool learns_power() const { return d_power_logits.defined(); }
    //! The energies of a selection (N_p x (N*M) rows): f + (1-f)·N_p·softmax(selection·w), N_p values.
    torch::Tensor pilot_power(const torch::Tensor& selection, double floor);
    //! The energies of the pilots at flat indices `idx` (in that order), normalised to mean 1 exactly.
    std::vector<double> final_power(const std::vector<int64_t>& idx, double floor);

    int n_pilots() const { return d_np; }
    const encoder_settings& settings() const { return d_s; }
    bool is_topk() const { return d_topk; }

private:
    int d_np, d_n, d_m;
    encoder_settings d_s;
    bool d_topk;
    // gumbel_topk
    torch::Tensor d_a, d_b, d_free;
    // learn_power: one logit per resource element
    torch::Tensor d_power_logits;
    // gumbel_heads
    torch::Tensor d_embedding;
    torch::nn::Linear d_fc1{ nullptr }, d_fc2{ nullptr };
    // 1 x (N*M): 0, or -inf on guard subcarriers (undefined without guards).
    torch::Tensor d_guard_bias;
};
TORCH_MODULE_IMPL(semantic_encoder, semantic_encoder_module);

// Greedy distinct assignment on a score matrix (R x K, R <= K), exposed for tests.
SEMS_LEARNING_API std::vector<int64_t> greedy_distinct_assignment(const torch::Tensor& scores);

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_SEMANTIC_ENCODER_H */
