// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the angle network of a position bundle (see angle_network.h). */
#include "learning/array/angle_network.h"
#include <gnuradio/sems/core/array/steering.h>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {
namespace nn {

angle_network_module::angle_network_module(const array_geometry& array, double wavelength_m, const angle_settings& s)
    : d_s(s), d_k(array.n_receive() * array.n_transmit())
{
    s.validate("angle network");
    const int q = s.grid;
    d_grid = torch::linspace(s.azimuth_min_rad, s.azimuth_max_rad, q, torch::kDouble).to(torch::kFloat);
    d_wr = torch::zeros({ d_k, q }, torch::kFloat);
    d_wi = torch::zeros({ d_k, q }, torch::kFloat);
    auto wr = d_wr.accessor<float, 2>();
    auto wi = d_wi.accessor<float, 2>();
    for (int i = 0; i < q; ++i) {
        const double az = s.azimuth_min_rad + (s.azimuth_max_rad - s.azimuth_min_rad) * i / (q - 1);
        const auto a = steering_vector(array, az, 0.0, wavelength_m);
        double norm = 0.0;
        for (const auto& x : a)
            norm += std::norm(x);
        if (!(norm > 0.0))
            throw std::invalid_argument("angle network: the array's pattern sees nothing at azimuth " +
                                        std::to_string(az) + " rad of the grid");
        for (int k = 0; k < d_k; ++k) {
            const auto w = std::conj(a[size_t(k)]) / std::sqrt(norm);
            wr[k][i] = static_cast<float>(w.real());
            wi[k][i] = static_cast<float>(w.imag());
        }
    }
    const int c = s.channels;
    input = register_module("input", torch::nn::Conv1d(torch::nn::Conv1dOptions(2, c, s.kernel).padding(s.kernel / 2).bias(false)));
    input_bn = register_module("input_bn", torch::nn::BatchNorm1d(c));
    for (int b = 0; b < s.blocks; ++b)
        blocks.push_back(register_module("block" + std::to_string(b), residual_block1d(c, s.kernel, 1 << b)));
    head = register_module("head", torch::nn::Conv1d(torch::nn::Conv1dOptions(c, 1, 1)));
}

torch::Tensor angle_network_module::features(const torch::Tensor& obs) const
{
    if (obs.dim() != 4 || obs.size(1) != d_k || obs.size(3) != 2)
        throw std::invalid_argument("angle network: expected observations B x " + std::to_string(d_k) +
                                    " x N_p x 2, got " + c10::str(obs.sizes()));
    const auto yr = obs.select(3, 0), yi = obs.select(3, 1); // B x K x P
    // z_qp = Σ_k w_kq y_kp (w already conjugated)
    const auto zr = torch::einsum("kq,bkp->bqp", { d_wr, yr }) - torch::einsum("kq,bkp->bqp", { d_wi, yi });
    const auto zi = torch::einsum("kq,bkp->bqp", { d_wr, yi }) + torch::einsum("kq,bkp->bqp", { d_wi, yr });
    const auto power = (zr * zr + zi * zi).sum(2);                          // B x Q
    const auto shape = power / power.amax(1, true).clamp_min(1e-30);       // scale-free, peak 1
    const auto log_shape = torch::log10(shape + 1e-4) / 4.0 + 1.0;        // 0 .. 1
    return torch::stack({ shape, log_shape }, 1);                         // B x 2 x Q
}

angle_output angle_network_module::forward(const torch::Tensor& obs)
{
    auto x = torch::relu(input_bn->forward(input->forward(features(obs))));
    for (auto& b : blocks)
        x = b->forward(x);
    angle_output out;
    out.logits = head->forward(x).squeeze(1);
    out.azimuth = soft_argmax(out.logits, d_grid, d_s.window);
    return out;
}

} // namespace nn
} // namespace sems
} // namespace gr
