// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the spectral classifier decoder (see spectral_classifier_decoder.h). */
#include "learning/spectral_classifier_decoder.h"
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {
namespace nn {

namespace {
// mask as B' x 1 x N x M (B' = 1 or B), float.
torch::Tensor mask4(const torch::Tensor& mask, const torch::Tensor& grid)
{
    const auto n = grid.size(2), m = grid.size(3);
    if (mask.dim() == 2 && mask.size(0) == n && mask.size(1) == m)
        return mask.to(grid.dtype()).view({ 1, 1, n, m });
    if (mask.dim() == 3 && (mask.size(0) == grid.size(0) || mask.size(0) == 1) && mask.size(1) == n &&
        mask.size(2) == m)
        return mask.to(grid.dtype()).unsqueeze(1);
    throw std::invalid_argument("spectral classifier: mask of shape " + c10::str(mask.sizes()) +
                                " does not fit the grid " + c10::str(grid.sizes()) + " (need N x M, 1 x N x M or B x N x M)");
}
} // namespace

torch::Tensor remove_zero_doppler(const torch::Tensor& grid, const torch::Tensor& mask)
{
    const auto w = mask4(mask, grid);
    // Pilots per subcarrier (hard counts: the forward mask is exactly 0/1).
    const auto count = w.detach().sum(2, true).clamp_min(1.0);
    // The grid is already zero off the mask (the decoders' input convention); multiplying
    // it by the mask again would square the mask and stop the encoder's gradient at the
    // elements it has not picked.
    const auto mean = grid.sum(2, true) / count;
    return grid - w * mean;
}

spectral_classifier_decoder_module::spectral_classifier_decoder_module(int n, int m, int np, classifier_settings s)
    : d_n(n), d_m(m), d_np(np), d_s(s)
{
    if (s.n_classes < 2)
        throw std::invalid_argument("spectral classifier decoder: n_classes must be >= 2");
    if (s.doppler_bins < n)
        throw std::invalid_argument("spectral classifier decoder: doppler_bins must be >= n_symbols = " +
                                    std::to_string(n) + ", got " + std::to_string(s.doppler_bins));
    if (s.kernel < 1 || s.kernel % 2 == 0)
        throw std::invalid_argument("spectral classifier decoder: kernel must be odd and >= 1, got " +
                                    std::to_string(s.kernel));
    if (!classifier_settings::known_mti(s.mti))
        throw std::invalid_argument("spectral classifier decoder: unknown mti \"" + s.mti +
                                    "\" (known: none, mean, both)");
    const int k = s.doppler_bins;
    // exp(-j2π k n / K) with k·n reduced mod K in integers first: exact phases.
    auto kn = torch::remainder(torch::arange(k, torch::kLong).unsqueeze(1) * torch::arange(n, torch::kLong).unsqueeze(0), k);
    auto arg = kn.to(torch::kDouble) * (2.0 * M_PI / k);
    d_cos = torch::cos(arg).to(torch::kFloat);
    d_sin = torch::sin(arg).to(torch::kFloat);
    if (!(s.conv_slope >= 0.0 && s.conv_slope < 1.0))
        throw std::invalid_argument("spectral classifier decoder: conv_slope must be in [0, 1), got " +
                                    std::to_string(s.conv_slope));
    if (s.range_bins < -1)
        throw std::invalid_argument("spectral classifier decoder: range_bins must be -1 (2·M), 0 (off) or a "
                                    "bin count, got " + std::to_string(s.range_bins));
    if (s.range_bins == -1)
        d_s.range_bins = 2 * m; // recorded resolved in bundle.json (describe())
    if (d_s.range_bins > 0) {
        // exp(+j2π m l / L): subcarrier m's delay phase exp(-j2π m τB/M) undone for τB = l·M/L.
        const int l = d_s.range_bins;
        auto ml = torch::remainder(torch::arange(m, torch::kLong).unsqueeze(1) * torch::arange(l, torch::kLong).unsqueeze(0), l);
        auto rarg = ml.to(torch::kDouble) * (2.0 * M_PI / l);
        d_rcos = torch::cos(rarg).to(torch::kFloat);
        d_rsin = torch::sin(rarg).to(torch::kFloat);
    }
    const int ch = s.mti == "both" ? 2 : 1;
    d_bn = register_module("bn", torch::nn::BatchNorm1d(ch));
    auto conv = [&](int in, int out) {
        return torch::nn::Conv1d(
            torch::nn::Conv1dOptions(in, out, s.kernel).padding(s.kernel / 2).padding_mode(torch::kCircular));
    };
    d_conv1 = register_module("conv1", conv(ch, s.width));
    d_conv2 = register_module("conv2", conv(s.width, s.width));
    d_fc1 = register_module("fc1", torch::nn::Linear(s.width * k, s.hidden));
    d_fc2 = register_module("fc2", torch::nn::Linear(s.hidden, s.features));
    d_out = register_module("out", torch::nn::Linear(s.features, s.n_classes));
}

torch::Tensor spectral_classifier_decoder_module::power_profile(const torch::Tensor& grid,
                                                                const torch::Tensor& used) const
{
    // g: B x 2 x N x M_used. F = W y over slow time: (re + j im)(cos - j sin).
    const auto g = used.defined() ? grid.index_select(3, used) : grid;
    const auto rcos = used.defined() && d_rcos.defined() ? d_rcos.index_select(0, used) : d_rcos;
    const auto rsin = used.defined() && d_rsin.defined() ? d_rsin.index_select(0, used) : d_rsin;
    const auto re = g.select(1, 0), im = g.select(1, 1); // B x N x M_used
    const auto fr = torch::matmul(d_cos, re) + torch::matmul(d_sin, im); // B x K x M
    const auto fi = torch::matmul(d_cos, im) - torch::matmul(d_sin, re);
    torch::Tensor s;
    if (d_s.range_bins == 0) {
        s = (fr * fr + fi * fi).sum(2); // B x K: the subcarriers pooled in power
    } else {
        // Range gate: R[k,l] = Σ_m F[k,m] exp(+j2π m l / L), then the Doppler profile of the
        // delay bin with the most energy (a single target sits in one bin at every Doppler).
        const auto rr = torch::matmul(fr, rcos) - torch::matmul(fi, rsin); // B x K x L
        const auto ri = torch::matmul(fr, rsin) + torch::matmul(fi, rcos);
        const auto p = rr * rr + ri * ri;
        const auto gate = std::get<1>(p.detach().sum(1).max(1)); // B: the strongest delay bin
        s = p.gather(2, gate.view({ -1, 1, 1 }).expand({ p.size(0), p.size(1), 1 })).squeeze(2);
    }
    s = s / (s.mean(1, true) + 1e-12);
    return torch::log(s + 1e-3);
}

torch::Tensor spectral_classifier_decoder_module::profile(const torch::Tensor& grid, const torch::Tensor& mask) const
{
    if (grid.dim() != 4 || grid.size(1) != 2 || grid.size(2) != d_n || grid.size(3) != d_m)
        throw std::invalid_argument("spectral classifier: grid of shape " + c10::str(grid.sizes()) +
                                    " is not B x 2 x " + std::to_string(d_n) + " x " + std::to_string(d_m));
    mask4(mask, grid); // shape check
    // A fixed mask (a sink's, or the decoder phase of training): only its subcarriers carry
    // pilots, so the transforms skip the empty ones (exact: they add zeros). While the
    // encoder learns, the mask carries a gradient and every subcarrier stays in, because
    // the encoder's gradient at an unpicked element flows through the decoder's input there.
    torch::Tensor used;
    if (mask.dim() == 2 && !mask.requires_grad())
        used = (mask.detach().sum(0) > 0).nonzero().squeeze(1);
    const auto g = normalise_frames(grid, d_np);
    if (d_s.mti == "none")
        return power_profile(g, used).unsqueeze(1);
    const auto clean = remove_zero_doppler(g, mask);
    if (d_s.mti == "mean")
        return power_profile(clean, used).unsqueeze(1);
    return torch::stack({ power_profile(g, used), power_profile(clean, used) }, 1);
}

decoder_output spectral_classifier_decoder_module::forward(const torch::Tensor&)
{
    throw std::invalid_argument("spectral classifier decoder: forward needs the pilot mask (forward(grid, mask))");
}

decoder_output spectral_classifier_decoder_module::forward(const torch::Tensor& grid, const torch::Tensor& mask)
{
    auto x = d_bn->forward(profile(grid, mask));
    x = torch::leaky_relu(d_conv1->forward(x), d_s.conv_slope); // slope 0: ReLU
    x = torch::leaky_relu(d_conv2->forward(x), d_s.conv_slope);
    x = torch::leaky_relu(d_fc1->forward(x.flatten(1)), 0.1);
    decoder_output out;
    out.features = d_fc2->forward(x);
    out.logits = d_out->forward(torch::leaky_relu(out.features, 0.1));
    return out;
}

nlohmann::json spectral_classifier_decoder_module::describe() const
{
    return { { "kind", kind() }, { "settings", d_s.to_json() } };
}

} // namespace nn
} // namespace sems
} // namespace gr
