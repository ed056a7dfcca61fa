// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the semantic encoder (see lib/learning/training/semantic_encoder.h). */
#include "learning/training/semantic_encoder.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

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

namespace {
// Gumbel top-k's draw: the perturbed scores Z + g and the k largest of them, in order (pick t
// is the t-th largest). Arguments are checked in the name of `who`; NaN scores are refused
// rather than picked.
struct topk_draw {
    torch::Tensor perturbed, picks;
};
topk_draw draw_topk(const char* who, const torch::Tensor& scores, int k, double temperature, const torch::Tensor& uniform)
{
    const std::string name(who);
    if (!(temperature > 0.0) || !std::isfinite(temperature))
        throw std::invalid_argument(name + ": temperature must be positive and finite");
    if (scores.dim() != 1)
        throw std::invalid_argument(name + ": scores must be one row (K), got shape " + c10::str(scores.sizes()));
    const int64_t n = scores.size(0);
    if (k < 1 || k > n)
        throw std::invalid_argument(name + ": k must be in [1, " + std::to_string(n) + "], got " + std::to_string(k));
    auto u = uniform.defined() ? uniform.to(scores.dtype()) : torch::rand_like(scores);
    u = u.clamp(uniform_eps, 1.0 - uniform_eps);
    topk_draw d;
    d.perturbed = scores - torch::log(-torch::log(u));
    const auto pd = d.perturbed.detach();
    if (torch::isnan(pd).any().item<bool>())
        throw std::invalid_argument(name + ": NaN score");
    d.picks = std::get<1>(pd.topk(k)); // k distinct indices
    return d;
}
} // namespace

torch::Tensor gumbel_topk_st(const torch::Tensor& scores,
                             int k,
                             double temperature,
                             const torch::Tensor& uniform,
                             bool hard_forward)
{
    const auto [perturbed, picks] = draw_topk("gumbel_topk_st", scores, k, temperature, uniform);
    const int64_t n = scores.size(0);
    auto hard = torch::zeros({ k, n }, scores.options());
    hard.scatter_(1, picks.unsqueeze(1), 1.0);
    // Relaxed draws without replacement: pick i's softmax excludes the picks before it.
    const auto logits = perturbed / temperature;
    const auto before = torch::cumsum(hard.detach(), 0) - hard.detach(); // 1 where taken by an earlier pick
    const auto masked = logits.unsqueeze(0).masked_fill(before > 0.5, -std::numeric_limits<double>::infinity());
    const auto soft = torch::exp(torch::log_softmax(masked, 1));
    if (!hard_forward)
        return soft;
    return hard + (soft - soft.detach());
}

torch::Tensor gumbel_topk_mask_st(const torch::Tensor& scores,
                                  int k,
                                  double temperature,
                                  const torch::Tensor& uniform,
                                  bool hard_forward)
{
    const auto [perturbed, picks] = draw_topk("gumbel_topk_mask_st", scores, k, temperature, uniform);
    const int64_t n = scores.size(0);
    const auto hard = torch::zeros({ n }, scores.options()).scatter(0, picks, 1.0);
    const auto logits = perturbed / temperature;
    // In logs, so that no row's normaliser under- or overflows at any temperature: pick t's
    // logit a_t is the largest left in row t, and log Z_i = logsumexp(a_i, …, a_{k−1}, log U).
    const auto a = logits.index_select(0, picks);
    auto v = a;
    const auto unpicked = logits.masked_fill(hard.detach() > 0.5, -std::numeric_limits<double>::infinity());
    if (torch::isfinite(unpicked.detach()).any().item<bool>())
        v = torch::cat({ a, torch::logsumexp(unpicked, 0, true) });
    const auto log_z = torch::flip(torch::logcumsumexp(torch::flip(v, { 0 }), 0), { 0 }).slice(0, 0, k);
    const auto l = torch::logcumsumexp(-log_z, 0); // l_t = log Σ_{i ≤ t} 1/Z_i
    // Column j: e_j·Σ 1/Z_i over the rows that still hold it.
    const auto soft = torch::exp((logits + l[k - 1]).scatter(0, picks, a + l));
    if (!hard_forward)
        return soft;
    return hard + (soft - soft.detach());
}

semantic_encoder_module::semantic_encoder_module(
    int n_pilots, int n_symbols, int n_subcarriers, encoder_settings s, bool learn_power,
    const std::vector<int>& guard_subcarriers)
    : d_np(n_pilots), d_n(n_symbols), d_m(n_subcarriers), d_s(s), d_topk(s.kind == "gumbel_topk")
{
    if (!guard_subcarriers.empty()) {
        auto bias = torch::zeros({ n_symbols, n_subcarriers });
        for (int m : guard_subcarriers) {
            if (m < 0 || m >= n_subcarriers)
                throw std::invalid_argument("semantic encoder: guard subcarrier " + std::to_string(m) +
                                            " is outside [0, " + std::to_string(n_subcarriers - 1) + "]");
            bias.select(1, m).fill_(-std::numeric_limits<float>::infinity());
        }
        const long long usable = static_cast<long long>(n_symbols) *
                                 (n_subcarriers - static_cast<long long>(torch::isinf(bias[0]).sum().item<int64_t>()));
        if (n_pilots > usable)
            throw std::invalid_argument("semantic encoder: " + std::to_string(n_pilots) +
                                        " pilots do not fit the " + std::to_string(usable) +
                                        " resource elements off the guard subcarriers");
        d_guard_bias = bias.view({ 1, n_symbols * n_subcarriers });
    }
    if (n_pilots < 1 || n_pilots > n_symbols * n_subcarriers)
        throw std::invalid_argument("semantic encoder: n_pilots must be in [1, N*M], got " +
                                    std::to_string(n_pilots));
    if (!encoder_settings::known_kind(s.kind))
        throw std::invalid_argument("semantic encoder: unknown kind \"" + s.kind +
                                    "\" (known: gumbel_topk, gumbel_heads)");
    // Zero logits: equal power at the start. (Without learn_power nothing is registered:
    // the equal-power encoder keeps exactly its parameters and random draws.)
    if (learn_power)
        d_power_logits = register_parameter("power_logits", torch::zeros({ n_symbols * n_subcarriers }));
    if (d_topk) {
        // Zero scores: the first masks are uniformly random over the grid.
        d_a = register_parameter("symbol_scores", torch::zeros({ n_symbols }));
        d_b = register_parameter("subcarrier_scores", torch::zeros({ n_subcarriers }));
        if (s.free_scores)
            d_free = register_parameter("free_scores", torch::zeros({ n_symbols, n_subcarriers }));
        return;
    }
    // One extra embedding row: its scores are added to every head's (a preference the
    // heads share, e.g. for a subcarrier or a symbol), see encoder_settings::shared.
    d_embedding = register_parameter("embedding", torch::randn({ n_pilots + (s.shared ? 1 : 0), s.embedding }));
    d_fc1 = register_module("fc1", torch::nn::Linear(s.embedding, s.hidden));
    d_fc2 = register_module(
        "fc2", torch::nn::Linear(s.hidden, s.factorized ? n_symbols + n_subcarriers : n_symbols * n_subcarriers));
}

torch::Tensor semantic_encoder_module::scores()
{
    if (d_topk) {
        auto z = d_a.unsqueeze(1) + d_b.unsqueeze(0);
        if (d_free.defined())
            z = z + d_free;
        z = z.view({ 1, d_n * d_m });
        return d_guard_bias.defined() ? z + d_guard_bias : z;
    }
    auto z = d_fc2->forward(torch::relu(d_fc1->forward(d_embedding)));
    if (d_s.shared)
        z = z.slice(0, 0, d_np) + z.slice(0, d_np, d_np + 1);
    if (d_s.factorized) { // Z_r[n,m] = a_r[n] + b_r[m]
        auto a = z.slice(1, 0, d_n).unsqueeze(2);
        auto b = z.slice(1, d_n, d_n + d_m).unsqueeze(1);
        z = (a + b).view({ d_np, d_n * d_m });
    }
    return d_guard_bias.defined() ? z + d_guard_bias : z;
}

torch::Tensor semantic_encoder_module::sample(double temperature, bool hard)
{
    if (d_topk)
        return gumbel_topk_st(scores().squeeze(0), d_np, temperature, {}, hard);
    return gumbel_softmax_st(scores(), temperature, {}, hard);
}

torch::Tensor semantic_encoder_module::sample_mask(double temperature, bool hard)
{
    constexpr double dense_limit = double(1 << 24); // N_p·N·M elements of the dense selection
    if (d_topk && double(d_np) * d_n * d_m > dense_limit)
        return gumbel_topk_mask_st(scores().squeeze(0), d_np, temperature, {}, hard).view({ d_n, d_m });
    return mask_from_selection(sample(temperature, hard), d_n, d_m);
}

torch::Tensor semantic_encoder_module::mask_from_selection(const torch::Tensor& selection, int n, int m)
{
    return selection.sum(0).view({ n, m });
}

torch::Tensor semantic_encoder_module::collision_penalty(double temperature)
{
    if (d_topk)
        return torch::zeros({}); // distinct by construction
    const auto p = torch::exp(torch::log_softmax(scores() / temperature, -1));
    const auto total = p.sum(0);
    return (total * total).sum() - (p * p).sum();
}

std::vector<int64_t> semantic_encoder_module::final_indices()
{
    torch::NoGradGuard ng;
    if (d_topk) {
        const auto z = scores().squeeze(0).to(torch::kDouble);
        if (torch::isnan(z).any().item<bool>())
            throw std::invalid_argument("semantic encoder: NaN score");
        const auto idx = std::get<1>(z.topk(d_np)).contiguous();
        return std::vector<int64_t>(idx.data_ptr<int64_t>(), idx.data_ptr<int64_t>() + d_np);
    }
    return greedy_distinct_assignment(scores());
}

torch::Tensor semantic_encoder_module::pilot_power(const torch::Tensor& selection, double floor)
{
    if (!learns_power())
        throw std::logic_error("semantic encoder: pilot_power without learned power");
    const auto logits = torch::matmul(selection, d_power_logits); // N_p: the selected elements' logits
    return floor + (1.0 - floor) * d_np * torch::softmax(logits, 0);
}

std::vector<double> semantic_encoder_module::final_power(const std::vector<int64_t>& idx, double floor)
{
    if (!learns_power())
        return std::vector<double>(idx.size(), 1.0);
    torch::NoGradGuard ng;
    const auto w = d_power_logits.to(torch::kDouble).index_select(0, torch::tensor(idx, torch::kLong));
    const auto p = (floor + (1.0 - floor) * double(idx.size()) * torch::softmax(w, 0)).contiguous();
    std::vector<double> out(p.data_ptr<double>(), p.data_ptr<double>() + p.numel());
    double sum = 0.0;
    for (double v : out)
        sum += v;
    for (auto& v : out) // mean 1 exactly (to rounding), as the mask file requires
        v *= double(out.size()) / sum;
    return out;
}

int semantic_encoder_module::distinct_argmax()
{
    if (d_topk)
        return d_np;
    torch::NoGradGuard ng;
    auto a = std::get<0>(torch::_unique(scores().argmax(-1)));
    return static_cast<int>(a.numel());
}

} // namespace nn
} // namespace sems
} // namespace gr
