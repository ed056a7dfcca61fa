// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the correlation-driven delay decoder (docs/design.md §5).
 *
 *   sparse grid (normalised per frame) -> learned complex projection along slow time,
 *   P outputs (P = 2 gives the paper's 4 x M) -> correlation with the dictionary
 *   D[m,q] = exp(-j2π m Δf τ_q) (r_p[q] = Σ_m x_p[m] conj(D[m,q]), Δf τ_q = τ_q·B / M)
 *   -> (phase_reference) every r_p rotated by the phase of r_0 at the strongest q, so the
 *   features do not depend on the frame's common phase
 *   -> features per q: Re r_p, Im r_p and |r_p| (3P x Q), and `residual_maps` K more maps:
 *   |correlation| of what is left of projection 0 after orthogonal matching pursuit removed
 *   its 1..K strongest dictionary atoms (least squares on the pilots' subcarriers; no
 *   gradient) -> 1-D residual CNN whose block i
 *   dilates by dilation_growth^i -> Q scores -> soft-argmax τ̂ = Σ_q τ_q softmax(z)_q.
 *
 * Why dilated: the target of interest is the FIRST path, which is not always the strongest.
 * Later paths of the same target arrive up to the scene's largest excess delay after it, so
 * a score must see that far on both sides; the trainer refuses a network whose receptive
 * field (delay_settings::receptive_field_index) is below twice the scene's largest excess
 * delay. With 0.125-index spacing, kernel 3 and 6 blocks of growth 2 it spans ±31 indices.
 *
 * The soft-argmax is local: a window of ±`window` grid points around the arg-max (so
 * the tails cannot bias the estimate); window = 0 means global. Both forms subtract the
 * maximum before exponentiating, so logits of ±1e4 are safe, and τ̂ is a convex
 * combination of grid delays: it always lies inside [τ_min, τ_max].
 *
 * Refinement (refine_paths = L > 0; inference only, never in training, and only once the
 * pilot positions are known through set_pilot_positions): a model-based polish of the
 * network's estimate, multipath_fitter::refine_anchored of the baselines library — the
 * same least-squares fit the LS reference ends with. The first path starts at τ̂, L - 1
 * later paths at the grid delays in (τ̂ + 0.25, τ̂ + refine_span_index] that best explain
 * the residual, then Levenberg–Marquardt over all delays (and the shared Doppler). The
 * earliest fitted delay replaces τ̂ when it moved less than refine_trust_index. The
 * network decides which path is first; the fit only moves it inside that trust region.
 * With one path (refine_paths = 1) and refine_global_peak, a network estimate farther
 * than refine_trust_index from the strongest correlation of the first projection (the
 * matched filter's grid peak on a one-symbol mask) is checked against a second fit started
 * at that peak; the fit with the smaller residual wins — for one path with unknown gain
 * that is the larger likelihood, so the decoder never keeps a worse-fitting delay than the
 * grid search of the least-squares reference would find. refine_global_min_fraction > 0
 * skips that second fit when the one-path model at the peak explains less than that share
 * of the pilots' energy (a frame with no clear peak: the fast bundle's setting).
 * With L > 1 paths and refine_global_fit, the oracle-order least-squares reference
 * (ls_delay_estimator: L paths by grid search on the dictionary grid, then nonlinear least
 * squares) is the second start: its earliest delay replaces the refined one when its
 * residual is smaller by more than 20 noise variances and the two differ by more than a
 * quarter index; refine_global_min_fraction > 0 skips it on frames the decoder's own fit
 * explains less than that share of (low SNR, where the reference is far worse than the
 * network, and the cost is saved). Where the network
 * anchored the fit on a later path or a sidelobe of a merged pair, the reference's grid
 * search finds the better-fitting set of paths; where the reference's greedy search went
 * wrong, the network's start fits better and stays — on the shipped bundle's fresh frames
 * this halves the frames off by more than half an index (docs/results/notes/shipped_models.md).
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_DELAY_DECODER_H
#define INCLUDED_SEMS_LIB_LEARNING_DELAY_DECODER_H

#include "learning/networks/folded_conv1d.h"
#include "learning/networks/task_decoder.h"
#include <gnuradio/sems/baselines/ls_delay_estimator.h>
#include <gnuradio/sems/baselines/multipath_fit.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <memory>
#include <mutex>
#include <vector>

namespace gr {
namespace sems {
namespace nn {

// Soft-argmax of logits (B x Q) over grid values (Q); window as in the header comment.
SEMS_LEARNING_API torch::Tensor soft_argmax(const torch::Tensor& logits, const torch::Tensor& grid_values, int window);

struct SEMS_LEARNING_API residual_block1d_module : torch::nn::Module {
    residual_block1d_module(int channels, int kernel, int dilation = 1);
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
    // The frame and pilot positions (flat n·M + m, mask order) the refinement fits; until
    // they are given, forward() returns the network's estimate. Throws
    // std::invalid_argument when they do not fit the decoder's frame or pilot count.
    void set_pilot_positions(const frame_settings& fs, const std::vector<int64_t>& flat_indices);
    // The residual maps forward() feeds the network (B x residual_maps x Q) for a grid.
    torch::Tensor residual_maps_of(const torch::Tensor& grid);

private:
    int d_n, d_m, d_np;
    delay_settings d_s;
    torch::Tensor d_proj_re, d_proj_im; // P x N
    torch::Tensor d_tau, d_dict_cos, d_dict_sin; // buffers: Q, M x Q, M x Q
    torch::nn::Conv1d d_stem{ nullptr }, d_head{ nullptr };
    torch::nn::BatchNorm1d d_stem_bn{ nullptr };
    torch::nn::Sequential d_blocks{ nullptr };
    std::vector<int64_t> d_positions;
    std::shared_ptr<multipath_fitter> d_fitter;
    std::shared_ptr<ls_delay_estimator> d_global_fit; // refine_global_fit's second start, or null
    // The refined estimates (B); peak: the grid delay of each frame's strongest first-
    // projection correlation (B), the second start of refine_global_peak (may be undefined).
    torch::Tensor refine(const torch::Tensor& x, const torch::Tensor& estimate, const torch::Tensor& peak) const;
    // The network after the features (stem, blocks, head) at inference, when it is small:
    // its convolutions with their BatchNorms folded in, as plain loops (folded_conv1d.h),
    // rebuilt when a parameter or buffer changes. Returns an undefined tensor when the
    // LibTorch path applies (training, autograd on, or a network too large to gain).
    torch::Tensor folded_logits(const torch::Tensor& features);
    struct folded_network {
        std::mutex lock;
        std::shared_ptr<const std::vector<folded_conv1d>> layers; // stem, (conv1, conv2) per block, head
        std::vector<int64_t> versions;     // of every parameter and buffer it was built from
        std::vector<const void*> data;
    };
    folded_network d_folded;
    std::pair<torch::Tensor, torch::Tensor> project(const torch::Tensor& x) const;
    torch::Tensor residual_maps(const torch::Tensor& xr,
                                const torch::Tensor& xi,
                                const torch::Tensor& support,
                                double scale) const;
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_DELAY_DECODER_H */
