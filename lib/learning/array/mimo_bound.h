// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the azimuth's Cramér–Rao bound of a MIMO mask as a differentiable function of the
 * grid's weights (internal; learning/array/mimo_mask_learner.h).
 *
 * The Fisher information of (φ, τ, ν, Re α, Im α) from the pilots, in the closed form of
 * baselines/mimo_angle.cc written over the whole grid with a weight W[j, n, m] per transmit
 * element and resource element (the amplitude element j sends there): with
 * s0[k,n,m] = Σ_j W[j,n,m]·a_kj(f_m) (a_kj the steering of virtual element k·N_t + j at
 * subcarrier m's own frequency) and s1 its φ-derivative, P0 = Σ_k |s0|², X + jY = Σ_k conj(s1)·s0,
 * c_m = 2πm/M, c_n = 2πn/N,
 *   J_φφ = Σ|s1|²,   J_φ(τ, ν, Re α, Im α) = (Σ c_m Y, −Σ c_n Y, Σ X, −Σ Y),
 *   J_(τ,ν,Re α,Im α) = [[Σc_m²P0, −Σc_m c_n P0, 0, −Σc_m P0], [·, Σc_n²P0, 0, Σc_n P0],
 *                        [0, 0, ΣP0, 0], [·, ·, 0, ΣP0]],
 * each times 2·SNR; the bound is 1/(J_φφ − J_φr J_rr⁻¹ J_rφ). qa_mimo_learner.cc checks it
 * against mimo_angle_crb_rad2 (a per-pilot sum, written independently).
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_MIMO_BOUND_H
#define INCLUDED_SEMS_LIB_LEARNING_MIMO_BOUND_H

#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/learning/api.h>
#include <torch/torch.h>
#include <vector>

namespace gr {
namespace sems {
namespace nn {

// The steering of every virtual element at every subcarrier's own frequency, per azimuth:
// D x N_r x N_t x M, real and imaginary parts, and the same for its φ-derivative (double).
struct mimo_steering {
    torch::Tensor ar, ai, dr, di;
};

SEMS_LEARNING_API mimo_steering mimo_steering_tables(const array_geometry& a, const frame_settings& fs,
                                                     const std::vector<double>& azimuth_rad, double elevation_rad);

// The bound in rad² at an SNR of 1 per pilot, for each azimuth of the tables (D values), from
// weights W (N_t x N x M, double); differentiable in W.
SEMS_LEARNING_API torch::Tensor mimo_crb_of_weights(const mimo_steering& t, const torch::Tensor& w);

// A mask's weights: W[j, n, m] = m.amplitude(pilot at (n, m), j), 0 off its pilots.
SEMS_LEARNING_API torch::Tensor mimo_weights(const mimo_mask& m);

} // namespace nn
} // namespace sems
} // namespace gr

#endif
