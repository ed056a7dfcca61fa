// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the correlation-driven delay decoder (see delay_decoder.h). */
#include "learning/delay_decoder.h"
#include <gnuradio/sems/core/steering.h>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {
namespace nn {

torch::Tensor soft_argmax(const torch::Tensor& logits, const torch::Tensor& grid_values, int window)
{
    const int64_t q = logits.size(-1);
    if (window <= 0 || 2 * window + 1 >= q)
        return (torch::softmax(logits, -1) * grid_values).sum(-1); // softmax subtracts the max
    // Local: indices [k*-w, k*+w] around the arg-max, shifted to stay inside the grid.
    auto center = logits.detach().argmax(-1, true).clamp(window, q - 1 - window);
    auto offsets = torch::arange(-window, window + 1, torch::dtype(torch::kLong).device(logits.device()));
    auto idx = center + offsets.unsqueeze(0);
    auto z = logits.gather(-1, idx);
    auto tau = grid_values.index_select(0, idx.flatten()).view(idx.sizes());
    return (torch::softmax(z, -1) * tau).sum(-1);
}

residual_block1d_module::residual_block1d_module(int c, int k)
{
    auto opt = torch::nn::Conv1dOptions(c, c, k).padding(k / 2).bias(false);
    conv1 = register_module("conv1", torch::nn::Conv1d(opt));
    bn1 = register_module("bn1", torch::nn::BatchNorm1d(c));
    conv2 = register_module("conv2", torch::nn::Conv1d(opt));
    bn2 = register_module("bn2", torch::nn::BatchNorm1d(c));
}

torch::Tensor residual_block1d_module::forward(const torch::Tensor& x)
{
    auto y = torch::relu(bn1->forward(conv1->forward(x)));
    y = bn2->forward(conv2->forward(y));
    return torch::relu(x + y);
}

delay_decoder_module::delay_decoder_module(int n, int m, int np, delay_settings s)
    : d_n(n), d_m(m), d_np(np), d_s(s)
{
    if (s.q < 2 || !(s.tau_max_index > s.tau_min_index))
        throw std::invalid_argument("delay decoder: need q >= 2 and tau_max_index > tau_min_index");
    const int p = s.projections;
    // Start as a plain sum over slow time (real weight 1/N): a sensible matched filter.
    d_proj_re = register_parameter("proj_re", torch::full({ p, n }, 1.0 / n) + 0.01 * torch::randn({ p, n }));
    d_proj_im = register_parameter("proj_im", 0.01 * torch::randn({ p, n }));
    auto tau = torch::linspace(s.tau_min_index, s.tau_max_index, s.q, torch::kDouble);
    // The dictionary D[m,q] = conj(delay_phasor(m, τ_q)) = exp(+j2π m Δf τ_q), split into
    // its real and imaginary parts (the correlation is done in real arithmetic).
    auto dict_cos = torch::empty({ m, s.q }, torch::kDouble);
    auto dict_sin = torch::empty({ m, s.q }, torch::kDouble);
    auto tau_a = tau.accessor<double, 1>();
    auto cos_a = dict_cos.accessor<double, 2>();
    auto sin_a = dict_sin.accessor<double, 2>();
    for (int k = 0; k < m; ++k)
        for (int q = 0; q < s.q; ++q) {
            const auto d = std::conj(delay_phasor(k, tau_a[q], m));
            cos_a[k][q] = d.real();
            sin_a[k][q] = d.imag();
        }
    d_tau = register_buffer("tau", tau.to(torch::kFloat));
    d_dict_cos = register_buffer("dict_cos", dict_cos.to(torch::kFloat));
    d_dict_sin = register_buffer("dict_sin", dict_sin.to(torch::kFloat));
    d_stem = register_module(
        "stem", torch::nn::Conv1d(torch::nn::Conv1dOptions(3 * p, s.width, s.kernel).padding(s.kernel / 2).bias(false)));
    d_stem_bn = register_module("stem_bn", torch::nn::BatchNorm1d(s.width));
    d_blocks = register_module("blocks", torch::nn::Sequential());
    for (int i = 0; i < s.depth; ++i)
        d_blocks->push_back(residual_block1d(s.width, s.kernel));
    d_head = register_module("head", torch::nn::Conv1d(torch::nn::Conv1dOptions(s.width, 1, 1)));
}

decoder_output delay_decoder_module::forward(const torch::Tensor& grid)
{
    auto x = normalise_frames(grid, d_np);
    auto yr = x.select(1, 0), yi = x.select(1, 1); // B x N x M
    // Complex projection along slow time: P x N weights -> B x P x M.
    auto xr = torch::matmul(d_proj_re, yr) - torch::matmul(d_proj_im, yi);
    auto xi = torch::matmul(d_proj_re, yi) + torch::matmul(d_proj_im, yr);
    // r = x · conj(D), D = cos - j sin  =>  conj(D) = cos + j sin.
    const double scale = 1.0 / std::sqrt(static_cast<double>(d_np));
    auto rr = (torch::matmul(xr, d_dict_cos) - torch::matmul(xi, d_dict_sin)) * scale;
    auto ri = (torch::matmul(xr, d_dict_sin) + torch::matmul(xi, d_dict_cos)) * scale;
    auto mag = torch::sqrt(rr * rr + ri * ri + 1e-12);
    auto feat = torch::cat({ rr, ri, mag }, 1); // B x 3P x Q
    auto h = torch::relu(d_stem_bn->forward(d_stem->forward(feat)));
    if (!d_blocks->is_empty())
        h = d_blocks->forward(h);
    decoder_output out;
    out.logits = d_head->forward(h).squeeze(1);
    out.delay_index = soft_argmax(out.logits, d_tau, d_s.window);
    return out;
}

nlohmann::json delay_decoder_module::describe() const
{
    return { { "kind", kind() }, { "settings", d_s.to_json() } };
}

} // namespace nn
} // namespace sems
} // namespace gr
