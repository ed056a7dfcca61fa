// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the spectral classifier's template bank (see template_bank.h). */
#include "learning/networks/template_bank.h"
#include <gnuradio/sems/core/common/limits.h>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {
namespace nn {

namespace {
// Floors of the scores: a class whose templates all lie far below the best match scores
// exp(-30) of it, not 0 (whose log would reach the layer as -inf), and a frame that one
// template explains exactly keeps β finite.
constexpr double score_floor = -30.0;
constexpr double min_unexplained = 1e-3;
} // namespace

template_bank_module::template_bank_module(int n_pilots, int n_templates, int n_classes)
    : d_np(n_pilots), d_t(n_templates), d_c(n_classes)
{
    if (n_pilots < 1 || n_templates < 1 || n_classes < 2)
        throw std::invalid_argument("template bank: needs N_p >= 1, T >= 1 and C >= 2, got " +
                                    std::to_string(n_pilots) + ", " + std::to_string(n_templates) + ", " +
                                    std::to_string(n_classes));
    if (static_cast<long long>(n_templates) * n_pilots > limits::max_template_values)
        throw std::invalid_argument("template bank: " + std::to_string(n_templates) + " frames x " +
                                    std::to_string(n_pilots) + " pilots exceed the limit of " +
                                    std::to_string(limits::max_template_values) + " values");
    d_templates = register_buffer("templates", torch::zeros({ int64_t(n_templates), 2, int64_t(n_pilots) }));
    d_class_end = register_buffer("class_end", torch::zeros({ n_classes }, torch::kLong));
    // The layer starts at zero, so its random initialisation is not needed: it is undone on the
    // global generator too, so a decoder with a bank and one without draw the same random
    // numbers from the same seed (the trainer then learns the same mask for both).
    auto gen = at::detail::getDefaultCPUGenerator();
    const auto state = gen.get_state();
    d_out = register_module("out", torch::nn::Linear(n_classes + 1, n_classes));
    gen.set_state(state);
    // Zero: a freshly filled bank leaves the network's logits as they are until it has trained.
    torch::NoGradGuard ng;
    d_out->weight.zero_();
    d_out->bias.zero_();
}

bool template_bank_module::ready() const { return d_class_end[d_c - 1].item<int64_t>() > 0; }

torch::Tensor template_bank_module::set(const torch::Tensor& pilots, const torch::Tensor& labels)
{
    if (pilots.dim() != 3 || pilots.size(0) != d_t || pilots.size(1) != 2 || pilots.size(2) != d_np)
        throw std::invalid_argument("template bank: pilots of shape " + c10::str(pilots.sizes()) + " are not " +
                                    std::to_string(d_t) + " x 2 x " + std::to_string(d_np));
    if (labels.dim() != 1 || labels.size(0) != d_t)
        throw std::invalid_argument("template bank: need " + std::to_string(d_t) + " labels, got shape " +
                                    c10::str(labels.sizes()));
    const auto lab = labels.to(torch::kLong);
    if (lab.min().item<int64_t>() < 0 || lab.max().item<int64_t>() >= d_c)
        throw std::invalid_argument("template bank: a label is outside [0, " + std::to_string(d_c) + ")");
    torch::NoGradGuard ng;
    const auto order = std::get<1>(lab.sort(/*stable=*/true, 0, false));
    auto t = pilots.to(torch::kFloat).index_select(0, order); // T x 2 x N_p, by class
    // Unit norm; a frame without energy stays zero and matches nothing.
    t = t / t.square().sum({ 1, 2 }, true).sqrt().clamp_min(std::numeric_limits<float>::min());
    d_templates.copy_(t);
    d_class_end.copy_(torch::bincount(lab, {}, d_c).cumsum(0));
    auto row = torch::empty({ d_t }, torch::kLong);
    row.index_put_({ order }, torch::arange(d_t, torch::kLong));
    return row;
}

torch::Tensor template_bank_module::matrix() const
{
    std::lock_guard<std::mutex> guard(d_matrix.lock);
    const auto version = d_templates._version();
    if (!d_matrix.value.defined() || d_matrix.version != version || d_matrix.data != d_templates.data_ptr()) {
        torch::NoGradGuard ng;
        const auto re = d_templates.select(1, 0).t(), im = d_templates.select(1, 1).t(); // N_p x T
        // [y_re, y_im] times this is [Re(yᴴt), Im(yᴴt)]: Re = y_re·t_re + y_im·t_im, Im = y_re·t_im - y_im·t_re.
        d_matrix.value = torch::cat({ torch::cat({ re, im }, 1), torch::cat({ im, -re }, 1) }, 0).contiguous();
        d_matrix.version = version;
        d_matrix.data = d_templates.data_ptr();
    }
    return d_matrix.value;
}

torch::Tensor template_bank_module::scores(const torch::Tensor& obs) const
{
    if (obs.dim() != 3 || obs.size(1) != 2 || obs.size(2) != d_np)
        throw std::invalid_argument("template bank: observations of shape " + c10::str(obs.sizes()) +
                                    " are not B x 2 x " + std::to_string(d_np));
    torch::NoGradGuard ng;
    const int64_t b = obs.size(0);
    const auto y = obs.detach().to(torch::kFloat).reshape({ b, 2 * d_np });
    const auto energy = y.square().sum(1, true).clamp_min(std::numeric_limits<float>::min());
    const auto z = torch::matmul(y, matrix()); // B x 2T: Re and Im of yᴴt
    auto rho = (z.slice(1, 0, d_t).square() + z.slice(1, d_t).square()) / energy; // B x T
    torch::Tensor excluded; // B bank rows (-1: none), training only
    if (is_training() && d_exclude.defined()) {
        if (d_exclude.dim() != 1 || d_exclude.size(0) != b)
            throw std::invalid_argument("template bank: " + std::to_string(d_exclude.numel()) +
                                        " excluded rows for a batch of " + std::to_string(b));
        excluded = d_exclude.to(torch::kLong);
        const auto keep = excluded >= 0;
        const auto frames = torch::arange(b, torch::kLong).masked_select(keep);
        rho.index_put_({ frames, excluded.masked_select(keep) }, -std::numeric_limits<float>::infinity());
    }
    const auto best = std::get<0>(rho.max(1, true)).clamp(0.0, 1.0); // B x 1
    const auto beta = static_cast<double>(d_np) / (1.0 - best).clamp_min(min_unexplained);
    const auto a = beta * rho; // B x T (-inf where left out)
    std::vector<torch::Tensor> per_class;
    const auto end = d_class_end.contiguous();
    const auto* e = end.data_ptr<int64_t>();
    const float minus_inf = -std::numeric_limits<float>::infinity();
    for (int c = 0; c < d_c; ++c) {
        const int64_t lo = c == 0 ? 0 : e[c - 1], hi = e[c];
        if (hi == lo) { // no template of this class: the floor below
            per_class.push_back(torch::full({ b }, minus_inf));
            continue;
        }
        // The mean over the templates each frame is matched against (one fewer where one is left out).
        auto count = torch::full({ b }, static_cast<float>(hi - lo));
        if (excluded.defined())
            count = count - ((excluded >= lo) & (excluded < hi)).to(torch::kFloat);
        const auto lse = torch::logsumexp(a.slice(1, lo, hi), 1);
        per_class.push_back(torch::where(count > 0, lse - count.clamp_min(1).log(), torch::full_like(lse, minus_inf)));
    }
    auto s = torch::stack(per_class, 1); // B x C
    // (NaN only when every template is left out: a bank of one frame in training.)
    s = torch::nan_to_num(s - torch::logsumexp(s, 1, true), score_floor, score_floor, score_floor)
            .clamp_min(score_floor);
    return torch::cat({ s, torch::log(1.0 - best + 1e-4) }, 1);
}

torch::Tensor template_bank_module::forward(const torch::Tensor& obs) { return d_out->forward(scores(obs)); }

} // namespace nn
} // namespace sems
} // namespace gr
