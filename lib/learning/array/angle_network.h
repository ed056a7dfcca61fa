// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the angle network of a position bundle (internal; docs/reference/arrays.md).
 *
 *   an array's pilots y (K elements x N_p pilots, element-major)
 *   -> the beamforming spectrum on Q grid azimuths φ_q:
 *        P_q = Σ_p |w_qᴴ y_p|²,  w_q = a(φ_q)/‖a(φ_q)‖ (the emulator's steering vectors, steering.h)
 *   -> two feature rows, P/max P and log10(P/max P + 1e-4)/4 + 1 (scale-free: the frame's gain
 *      and the SNR leave only the spectrum's shape)
 *   -> 1-D residual CNN (block i dilates by 2^i) -> Q scores
 *   -> local soft-argmax over the grid (delay_decoder.h's): φ̂, a convex combination of grid
 *      azimuths, so it always lies inside the grid.
 *
 * For one target, argmax P is the maximum-likelihood azimuth. The network learns where the
 * spectrum of a noisy frame puts a target of the training scene: at low SNR its estimate weighs
 * the peaks (the posterior's mean rather than the largest peak). position_estimator then polishes
 * φ̂ on the spectrum itself (beamforming_angle_estimator::refine) within ±polish_steps grid steps,
 * which takes a confident estimate to the maximum-likelihood one to well below the grid step.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_ANGLE_NETWORK_H
#define INCLUDED_SEMS_LIB_LEARNING_ANGLE_NETWORK_H

#include "learning/networks/delay_decoder.h"
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <torch/torch.h>
#include <vector>

namespace gr {
namespace sems {
namespace nn {

struct angle_output {
    torch::Tensor logits;  // B x Q
    torch::Tensor azimuth; // B, rad
};

class SEMS_LEARNING_API angle_network_module : public torch::nn::Module
{
public:
    // The array's virtual elements at elevation 0, steered at wavelength_m.
    angle_network_module(const array_geometry& array, double wavelength_m, const angle_settings& s);
    // obs: B x K x N_p x 2 (float, real and imaginary parts).
    angle_output forward(const torch::Tensor& obs);
    // The CNN's input: B x 2 x Q.
    torch::Tensor features(const torch::Tensor& obs) const;
    // The grid's azimuths (Q, rad) and its step.
    const torch::Tensor& grid() const { return d_grid; }
    double step_rad() const { return (d_s.azimuth_max_rad - d_s.azimuth_min_rad) / (d_s.grid - 1); }
    int elements() const { return d_k; }
    const angle_settings& settings() const { return d_s; }

private:
    angle_settings d_s;
    int d_k;
    torch::Tensor d_grid;     // Q azimuths
    torch::Tensor d_wr, d_wi; // K x Q: conj(a(φ_q))/‖a‖, real and imaginary parts (not weights)
    torch::nn::Conv1d input{ nullptr }, head{ nullptr };
    torch::nn::BatchNorm1d input_bn{ nullptr };
    std::vector<residual_block1d> blocks;
};
TORCH_MODULE_IMPL(angle_network, angle_network_module);

} // namespace nn
} // namespace sems
} // namespace gr

#endif
