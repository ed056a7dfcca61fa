// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the semantic encoder (see lib/learning/semantic_encoder.h). */
#include "learning/semantic_encoder.h"
#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace gr {
namespace sems {
namespace nn {

namespace {
constexpr double uniform_eps = 1e-6;
}

torch::Tensor gumbel_softmax_st(const torch::Tensor& scores,
                                double temperature,
                                const torch::Tensor& uniform,
                                bool hard_forward)
{
    if (!(temperature > 0.0))
        throw std::invalid_argument("gumbel_softmax_st: temperature must be positive");
    auto u = uniform.defined() ? uniform.to(scores.dtype()) : torch::rand_like(scores);
    u = u.clamp(uniform_eps, 1.0 - uniform_eps);
    const auto g = -torch::log(-torch::log(u));
    const auto log_soft = torch::log_softmax((scores + g) / temperature, -1);
    const auto soft = torch::exp(log_soft);
    if (!hard_forward)
        return soft;
    const auto hard = torch::zeros_like(soft).scatter_(-1, log_soft.argmax(-1, true), 1.0);
    // hard + exact zero in the forward pass; the soft gradient in the backward pass.
    return hard + (soft - soft.detach());
}

std::vector<int64_t> greedy_distinct_assignment(const torch::Tensor& scores)
{
    const auto z = scores.detach().to(torch::kDouble).contiguous();
    const int64_t r = z.size(0), k = z.size(1);
    if (r > k)
        throw std::invalid_argument("greedy_distinct_assignment: more heads than grid elements");
    const double* p = z.data_ptr<double>();
    std::vector<int64_t> order(r);
    std::iota(order.begin(), order.end(), 0);
    std::vector<double> best(r);
    for (int64_t i = 0; i < r; ++i)
        best[i] = *std::max_element(p + i * k, p + (i + 1) * k);
    std::stable_sort(order.begin(), order.end(), [&](int64_t a, int64_t b) { return best[a] > best[b]; });
    std::vector<char> taken(k, 0);
    std::vector<int64_t> out(r, -1);
    for (int64_t head : order) {
        int64_t pick = -1;
        for (int64_t j = 0; j < k; ++j) // NaN scores never win; the first free element is the fallback
            if (!taken[j] && (pick < 0 || p[head * k + j] > p[head * k + pick]))
                pick = j;
        taken[pick] = 1;
        out[head] = pick;
    }
    return out;
}

semantic_encoder_module::semantic_encoder_module(int n_pilots, int n_symbols, int n_subcarriers, encoder_settings s)
    : d_np(n_pilots), d_n(n_symbols), d_m(n_subcarriers), d_s(s)
{
    if (n_pilots < 1 || n_pilots > n_symbols * n_subcarriers)
        throw std::invalid_argument("semantic encoder: n_pilots must be in [1, N*M], got " +
                                    std::to_string(n_pilots));
    // One extra embedding row: its scores are added to every head's (a preference the
    // heads share, e.g. for a subcarrier or a symbol), see encoder_settings::shared.
    d_embedding = register_parameter("embedding", torch::randn({ n_pilots + (s.shared ? 1 : 0), s.embedding }));
    d_fc1 = register_module("fc1", torch::nn::Linear(s.embedding, s.hidden));
    d_fc2 = register_module(
        "fc2", torch::nn::Linear(s.hidden, s.factorized ? n_symbols + n_subcarriers : n_symbols * n_subcarriers));
}

torch::Tensor semantic_encoder_module::scores()
{
    auto z = d_fc2->forward(torch::relu(d_fc1->forward(d_embedding)));
    if (d_s.shared)
        z = z.slice(0, 0, d_np) + z.slice(0, d_np, d_np + 1);
    if (!d_s.factorized)
        return z;
    // Z_r[n,m] = a_r[n] + b_r[m]
    auto a = z.slice(1, 0, d_n).unsqueeze(2);
    auto b = z.slice(1, d_n, d_n + d_m).unsqueeze(1);
    return (a + b).view({ d_np, d_n * d_m });
}

torch::Tensor semantic_encoder_module::sample(double temperature)
{
    return gumbel_softmax_st(scores(), temperature, {}, temperature <= d_s.soft_above);
}

torch::Tensor semantic_encoder_module::mask_from_selection(const torch::Tensor& selection, int n, int m)
{
    return selection.sum(0).view({ n, m });
}

torch::Tensor semantic_encoder_module::collision_penalty(double temperature)
{
    const auto p = torch::exp(torch::log_softmax(scores() / temperature, -1));
    const auto total = p.sum(0);
    return (total * total).sum() - (p * p).sum();
}

std::vector<int64_t> semantic_encoder_module::final_indices()
{
    torch::NoGradGuard ng;
    return greedy_distinct_assignment(scores());
}

int semantic_encoder_module::distinct_argmax()
{
    torch::NoGradGuard ng;
    auto a = std::get<0>(torch::_unique(scores().argmax(-1)));
    return static_cast<int>(a.numel());
}

} // namespace nn
} // namespace sems
} // namespace gr
