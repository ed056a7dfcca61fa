// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the spectral classifier decoder (see spectral_classifier_decoder.h). */
#include "learning/networks/spectral_classifier_decoder.h"
#include <gnuradio/sems/core/array/steering.h>
#include <ATen/ATen.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {
namespace nn {

namespace {
// On a frame of this many subcarriers or more, the range gate is an inverse FFT of length L
// instead of a product with the M x L phasor matrix: the product costs 4·M·L real
// multiply-adds per Doppler bin and holds 2·M·L floats, quadratic in the frame's subcarriers
// (at 4 096 the matrices alone take 268 MB), the FFT O(L log L): at M = 256 the gate's
// forward and backward pass took a quarter of the product's time, at 1 024 half (PyTorch,
// one thread). Below it the product stays, so the bundles of the paper's and the SDR preset's
// 64-subcarrier frames keep their bits (the two agree to float rounding).
constexpr int range_gate_fft_min_subcarriers = 128;

// The FFT range gate, S[b,k] = |R[b,k,l*_b]|² with R = ifft(Z, L) ("forward" norm, no 1/L)
// and l*_b = argmax_l Σ_k |R[b,k,l]|², a few frames at a time. Through autograd the gate held
// B x K x L complex values and their squares for the backward pass (at 14 x 4 096 and batch
// 256, 1 GB each, cleared and faulted in at every step) and spent three passes over them on
// a gradient that is zero off the gate. Here forward keeps R[b,k,l*] alone; backward builds
// the same sparse gradient of R and runs the same transform on it, chunk by chunk: the ops
// are autograd's own (the square x·x, its derivative g·(2x), the backward transform
// _fft_c2c(G, forward) and the pad's slice), each applied to every element as before, so
// values and gradients are the same bits, in a few MB.
//
// The input is Z (B x K x M complex), or the slow-time DFT as the matrix product leaves it,
// B x M x 2K with Z[b,k,m] = F[b,m,k] + j F[b,m,K+k], taken chunk by chunk: then neither Z
// nor its gradient is held whole (F's gradient is Re and Im of Z's, as complex() passes them
// back), and neither is F in the B x 2K x M layout matmul() copies it to.
struct fft_range_gate : public torch::autograd::Function<fft_range_gate> {
    // Frames per chunk: one chunk's B' x K x L complex values within ~32 MB.
    static int64_t chunk_frames(int64_t k, int64_t l)
    {
        return std::max<int64_t>(1, (int64_t(32) << 20) / std::max<int64_t>(1, k * l * 8));
    }

    static torch::Tensor forward(torch::autograd::AutogradContext* ctx, const torch::Tensor& in, int64_t l)
    {
        const bool rows = !in.is_complex(); // B x M x 2K: [Re, Im] of Z along the last axis
        const int64_t b = in.size(0), k = rows ? in.size(2) / 2 : in.size(1), step = chunk_frames(k, l);
        auto s = torch::empty({ b, k }, torch::dtype(torch::kFloat));
        auto x_gate = torch::empty({ b, k, 2 }, torch::dtype(torch::kFloat)); // R at the gate, (re, im)
        auto gate = torch::empty({ b }, torch::kLong);
        for (int64_t a = 0; a < b; a += step) {
            const int64_t e = std::min(b, a + step);
            const auto part = in.slice(0, a, e);
            const auto z = rows ? torch::complex(part.slice(2, 0, k), part.slice(2, k)).transpose(1, 2) : part;
            const auto x = torch::view_as_real(torch::fft::ifft(z, l, -1, "forward")); // B' x K x L x 2
            const auto p = x.square().sum(-1);                                           // B' x K x L
            const auto g = std::get<1>(p.sum(1).max(1));                                // B'
            gate.slice(0, a, e).copy_(g);
            s.slice(0, a, e).copy_(p.gather(2, g.view({ -1, 1, 1 }).expand({ e - a, k, 1 })).squeeze(2));
            x_gate.slice(0, a, e).copy_(x.gather(2, g.view({ -1, 1, 1, 1 }).expand({ e - a, k, 1, 2 })).squeeze(2));
        }
        ctx->save_for_backward({ x_gate, gate });
        ctx->saved_data["l"] = l;
        ctx->saved_data["m"] = rows ? in.size(1) : in.size(2);
        ctx->saved_data["rows"] = rows;
        return s;
    }

    static torch::autograd::variable_list backward(torch::autograd::AutogradContext* ctx,
                                                   torch::autograd::variable_list grads)
    {
        const auto saved = ctx->get_saved_variables();
        const auto& x_gate = saved[0];
        const auto& gate = saved[1];
        const int64_t l = ctx->saved_data["l"].toInt(), m = ctx->saved_data["m"].toInt();
        const bool rows = ctx->saved_data["rows"].toBool();
        const int64_t b = x_gate.size(0), k = x_gate.size(1);
        const auto grad_in = rows ? torch::empty({ b, m, 2 * k }, torch::dtype(torch::kFloat))
                                  : torch::empty({ b, k, m }, torch::dtype(torch::kComplexFloat));
        if (!grads[0].defined()) {
            grad_in.zero_();
            return { grad_in, torch::Tensor() };
        }
        // d|R|²/d(re, im) = 2 (re, im) at the gate (pow's derivative: grad · (2·x)), 0 elsewhere.
        const auto g_gate = grads[0].unsqueeze(-1) * (2.0 * x_gate); // B x K x 2
        const int64_t step = chunk_frames(k, l);
        for (int64_t a = 0; a < b; a += step) {
            const int64_t e = std::min(b, a + step);
            auto g_r = torch::zeros({ e - a, k, l, 2 }, torch::dtype(torch::kFloat));
            g_r.scatter_(2, gate.slice(0, a, e).view({ -1, 1, 1, 1 }).expand({ e - a, k, 1, 2 }),
                         g_gate.slice(0, a, e).unsqueeze(2));
            // ifft's backward: the forward transform, same normalisation (none), then the pad's slice.
            const auto g_z = at::_fft_c2c(torch::view_as_complex(g_r), { 2 }, 0, true).narrow(2, 0, std::min(m, l));
            auto dst = grad_in.slice(0, a, e);
            if (!rows) {
                dst.copy_(g_z);
            } else { // complex()'s backward: the real and imaginary parts
                dst.slice(2, 0, k).copy_(at::real(g_z).transpose(1, 2));
                dst.slice(2, k).copy_(at::imag(g_z).transpose(1, 2));
            }
        }
        return { grad_in, torch::Tensor() };
    }
};

// The profile's last step: log of the power relative to its mean.
torch::Tensor finish_profile(const torch::Tensor& power)
{
    const auto s = power / (power.mean(1, true) + 1e-12);
    return torch::log(s + 1e-3);
}

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
    s.validate("spectral classifier decoder");
    if (s.doppler_bins < n)
        throw std::invalid_argument("spectral classifier decoder: doppler_bins must be >= n_symbols = " +
                                    std::to_string(n) + ", got " + std::to_string(s.doppler_bins));
    if (s.range_bins == -1)
        d_s.range_bins = 2 * m; // recorded resolved in bundle.json (describe())
    if (d_s.range_bins > 0 && m < range_gate_fft_min_subcarriers) {
        // G[m,l] = conj(delay_phasor(m, l·M/L)) = exp(+j2π m l / L): subcarrier m's delay
        // phase undone for the delay index l·M/L (the steering phasor of core/array/steering.h).
        const int l = d_s.range_bins;
        d_rcos = torch::empty({ m, l });
        d_rsin = torch::empty({ m, l });
        auto c = d_rcos.accessor<float, 2>(), sn = d_rsin.accessor<float, 2>();
        for (int sub = 0; sub < m; ++sub)
            for (int bin = 0; bin < l; ++bin) {
                const auto g = std::conj(delay_phasor(sub, static_cast<double>(bin) * m / l, m));
                c[sub][bin] = static_cast<float>(g.real());
                sn[sub][bin] = static_cast<float>(g.imag());
            }
    }
    const int k = s.doppler_bins;
    // exp(-j2π k n / K) with k·n reduced mod K in integers first: exact phases.
    auto kn = torch::remainder(torch::arange(k, torch::kLong).unsqueeze(1) * torch::arange(n, torch::kLong).unsqueeze(0), k);
    const auto arg = kn.to(torch::kDouble) * (2.0 * M_PI / k);
    d_cos = torch::cos(arg).to(torch::kFloat);
    d_sin = torch::sin(arg).to(torch::kFloat);
    d_dft = torch::cat({ torch::cat({ d_cos, d_sin }, 1), torch::cat({ -d_sin, d_cos }, 1) }, 0); // 2K x 2N
    if (s.chirp_bins > 0) {
        // π α_j (n - (N-1)/2)² per rate (J x N): the chirps are centred on the frame.
        const auto centred = torch::arange(n, torch::kDouble) - 0.5 * (n - 1);
        d_chirp_phase = ((M_PI * torch::tensor(d_s.chirp_rates(n), torch::kDouble)).unsqueeze(1) *
                         centred.square().unsqueeze(0)).to(torch::kFloat);
        d_symbol_index = torch::arange(n, torch::kFloat).view({ 1, 1, n });
        d_tone_bn = register_module("tone_bn", torch::nn::BatchNorm1d(s.chirp_bins));
        d_tone_fc = register_module("tone_fc", torch::nn::Linear(s.chirp_bins, s.features));
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
    // The tone fit's own small layer joins the profile's hidden layer: its few features
    // would be drowned among the width·K of the convolutions at the first layer's input.
    d_fc2 = register_module("fc2", torch::nn::Linear(s.hidden + (s.chirp_bins > 0 ? s.features : 0), s.features));
    d_out = register_module("out", torch::nn::Linear(s.features, s.n_classes));
    if (s.template_frames == -1)
        throw std::invalid_argument("spectral classifier decoder: template_frames -1 (every training frame) is for "
                                    "the trainer to resolve; a decoder needs the bank's frame count");
    if (s.template_frames > 0)
        d_templates = register_module("templates", std::make_shared<template_bank_module>(np, s.template_frames, s.n_classes));
}

torch::Tensor spectral_classifier_decoder_module::power_profile(const torch::Tensor& g,
                                                                const torch::Tensor& cols) const
{
    // g: B x 2 x N x M' (M' = M, or the subcarriers `cols`). F = W y over slow time:
    // (re + j im)(cos - j sin), one real product:
    // [fr; fi] = [[cos, sin], [-sin, cos]] [re; im] (2K x 2N times B x 2N x M').
    const auto b = g.size(0), m = g.size(3);
    if (d_s.range_bins > 0 && d_m >= range_gate_fft_min_subcarriers && !cols.defined() && m <= d_s.range_bins) {
        // The product matmul() computes (it folds the batch into one mm: the same call, the
        // same bits), left as B x M x 2K for the FFT gate, which forms Z from it.
        const auto ft = g.reshape({ b, 2 * d_n, m }).mT().reshape({ -1, 2 * d_n }).mm(d_dft.t()).view({ b, m, -1 });
        return finish_profile(fft_range_gate::apply(ft, d_s.range_bins));
    }
    const auto f = torch::matmul(d_dft, g.reshape({ b, 2 * d_n, m })); // B x 2K x M'
    torch::Tensor s;
    if (d_s.range_bins == 0) {
        s = f.square().view({ b, 2, d_s.doppler_bins, m }).sum({ 1, 3 }); // B x K: subcarriers pooled in power
    } else {
        // Range gate: R[k,l] = Σ_m F[k,m] exp(+j2π m l / L), then the Doppler profile of the
        // delay bin with the most energy (a single target sits in one bin at every Doppler).
        const auto fr = f.slice(1, 0, d_s.doppler_bins), fi = f.slice(1, d_s.doppler_bins);
        if (d_m >= range_gate_fft_min_subcarriers) {
            const int64_t l = d_s.range_bins;
            auto z = torch::complex(fr, fi); // B x K x M'
            if (cols.defined()) // back on the frame's subcarriers, zeros elsewhere
                z = torch::zeros({ b, d_s.doppler_bins, d_m }, z.options()).index_copy(2, cols, z);
            if (z.size(2) > l) {
                // Fewer bins than subcarriers: exp(+j2π m l / L) repeats every L subcarriers,
                // so subcarrier m adds to the bin sum of m mod L (zeros pad to whole periods).
                const auto periods = (z.size(2) + l - 1) / l;
                z = torch::constant_pad_nd(z, { 0, periods * l - z.size(2) }).view({ b, d_s.doppler_bins, periods, l }).sum(2);
            }
            // Σ_m Z[k,m] exp(+j2π m l / L): the inverse DFT without its 1/L ("forward" norm),
            // gated at each frame's strongest delay bin (fft_range_gate).
            s = fft_range_gate::apply(z, l);
        } else {
            const auto rcos = cols.defined() ? d_rcos.index_select(0, cols) : d_rcos;
            const auto rsin = cols.defined() ? d_rsin.index_select(0, cols) : d_rsin;
            const auto rr = torch::matmul(fr, rcos) - torch::matmul(fi, rsin);
            const auto ri = torch::matmul(fr, rsin) + torch::matmul(fi, rcos);
            const auto p = rr * rr + ri * ri;
            const auto gate = std::get<1>(p.detach().sum(1).max(1)); // B: the strongest delay bin
            s = p.gather(2, gate.view({ -1, 1, 1 }).expand({ p.size(0), p.size(1), 1 })).squeeze(2);
        }
    }
    return finish_profile(s);
}

torch::Tensor spectral_classifier_decoder_module::tone_fit(const torch::Tensor& g,
                                                           const torch::Tensor& mask,
                                                           const torch::Tensor& profile) const
{
    // Every subcarrier's slow-time series z_m[n] = y[n,m], explained by one common chirp with
    // a gain and phase of its own per subcarrier (the target's delay phase): exact on any mask,
    // whatever symbols each subcarrier observes.
    auto n_obs = mask4(mask, g).detach().squeeze(1).sum(1); // B' x M': pilots per subcarrier
    auto z = g;
    // Only subcarriers with chirp_min_pilots or more count (a soft mask's weights summed):
    // some chirp explains one or two pilots exactly, whatever the target. The others' series
    // are zeroed once, so they add nothing to the energy nor to any power below.
    if (d_s.chirp_min_pilots > 1) {
        const auto counted = (n_obs >= d_s.chirp_min_pilots - 1e-3).to(g.dtype());
        z = g * counted.unsqueeze(1).unsqueeze(1); // B' x 1 x 1 x M'
        n_obs = n_obs * counted;
    }
    const auto zr = z.select(1, 0), zi = z.select(1, 1); // B x N x M'
    // Cauchy-Schwarz: Σ_m |Σ_n z_m[n] u[n]|² <= Σ_m n_m Σ_n |z_m[n]|² for a unit-modulus u,
    // with equality iff every series is that chirp: the share E is in [0, 1] (0 when no
    // subcarrier counts: a constant feature, nothing to learn from).
    const auto energy = (n_obs * (zr.square() + zi.square()).sum(1)).sum(1, true) + 1e-12; // B x 1
    // The power of the series against the chirp of rate j at frequency f[b, j] (cycles/symbol): B x J.
    auto power_at = [&](const torch::Tensor& f) {
        const auto theta = (2.0 * M_PI) * f.unsqueeze(2) * d_symbol_index + d_chirp_phase.unsqueeze(0); // B x J x N
        const auto c = torch::cos(theta), sn = torch::sin(theta);
        const auto re = torch::matmul(c, zr) + torch::matmul(sn, zi); // B x J x M'
        const auto im = torch::matmul(c, zi) - torch::matmul(sn, zr);
        return (re.square() + im.square()).sum(2);
    };
    torch::Tensor f_best;
    {
        // The frequency is searched without gradient (at the maximum the power's derivative
        // in f is zero, so nothing is lost). Start: the profile's peak bin k* (the chirps are
        // centred on the frame, so dechirping moves no peak); per rate one parabola through
        // k* and its neighbours, then one through f ± 1/(8K), the better point kept: a tone
        // between two bins loses up to a fifth of its power on the K-bin grid, far more than
        // a pedestrian's chirp does; after the two steps the loss is ~1e-5.
        torch::NoGradGuard ng;
        const int64_t k = d_s.doppler_bins;
        const auto k0 = profile.detach().flatten(1).argmax(1).remainder(k).to(g.dtype()).view({ -1, 1 })
                            .expand({ g.size(0), d_s.chirp_bins });
        // The vertex of the parabola through (-1, lo), (0, mid), (1, hi), within ±limit.
        auto vertex = [](const torch::Tensor& lo, const torch::Tensor& mid, const torch::Tensor& hi, double limit) {
            const auto den = lo - 2 * mid + hi;
            return torch::where(den < 0, 0.5 * (lo - hi) / den.clamp_max(-1e-30), torch::zeros_like(den))
                .clamp(-limit, limit);
        };
        const double step = 1.0 / k;
        const auto f0 = k0 / static_cast<double>(k);
        // (The peak of a K-bin grid with K >= N lies within half a bin of its largest bin.)
        const auto f1 = f0 + vertex(power_at(f0 - step), power_at(f0), power_at(f0 + step), 0.5) * step;
        const double h = 1.0 / (8.0 * k);
        const auto p_mid = power_at(f1);
        const auto f2 = f1 + h * vertex(power_at(f1 - h), p_mid, power_at(f1 + h), 2.0);
        f_best = torch::where(power_at(f2) >= p_mid, f2, f1);
    }
    const auto share = (power_at(f_best) / energy).clamp(0.0, 1.0);
    return torch::log(1.0 - share + 1e-4); // B x J
}

torch::Tensor spectral_classifier_decoder_module::tone_features(const torch::Tensor& grid, const torch::Tensor& mask) const
{
    return inputs(grid, mask, true).second;
}

torch::Tensor spectral_classifier_decoder_module::profile(const torch::Tensor& grid, const torch::Tensor& mask) const
{
    return inputs(grid, mask, false).first;
}

std::pair<torch::Tensor, torch::Tensor> spectral_classifier_decoder_module::inputs(const torch::Tensor& grid,
                                                                                   const torch::Tensor& mask,
                                                                                   bool with_tone,
                                                                                   const torch::Tensor& columns) const
{
    // A compact grid (only some subcarriers, with the mask of those columns, no gradient)
    // is accepted too: the profile sums over subcarriers, so absent ones count as zeros.
    const bool compact = grid.dim() == 4 && grid.size(3) < d_m && mask.dim() == 2 &&
                         mask.size(1) == grid.size(3) && !grid.requires_grad();
    if (grid.dim() != 4 || grid.size(1) != 2 || grid.size(2) != d_n || (grid.size(3) != d_m && !compact))
        throw std::invalid_argument("spectral classifier: grid of shape " + c10::str(grid.sizes()) +
                                    " is not B x 2 x " + std::to_string(d_n) + " x " + std::to_string(d_m) +
                                    " (nor B x 2 x N x M' with an N x M' mask of the same columns)");
    mask4(mask, grid); // shape check
    auto g = grid;
    auto m = mask;
    torch::Tensor cols; // the subcarriers of g's columns (undefined: all M)
    if (compact) {
        const auto& given = columns.defined() ? columns : d_compact_cols;
        if (!given.defined() || given.size(0) != grid.size(3))
            throw std::invalid_argument("spectral classifier: a compact grid of " + std::to_string(grid.size(3)) +
                                        " columns needs its subcarriers (set_compact_columns() or the call's) first");
        cols = given;
    }
    // A fixed mask and no gradient to carry (inference, decoder-only training): the grid is
    // zero on the subcarriers without pilots, which add nothing to the profile's sum over
    // subcarriers nor to the zero-Doppler means, so only the occupied columns are transformed
    // (a mask on 2 of 64 subcarriers costs 1/32 of the dense DFT and of the normalisation's
    // temporaries). A learned mask keeps the
    // dense path: its gradient reaches the encoder through every element.
    if (!compact && mask.dim() == 2 && !g.requires_grad() && !mask.requires_grad()) {
        const auto used = (mask.sum(0) > 0).nonzero().squeeze(1);
        if (used.size(0) < g.size(3)) {
            g = g.index_select(3, used);
            m = mask.index_select(1, used);
            cols = used;
        }
    }
    g = normalise_frames(g, d_np); // per frame, over its pilots (the zeros add nothing)
    // The tone/chirp fit sees what the profile of the last stage sees (after MTI where there
    // is one: static clutter is a pure tone at 0 Hz) and starts from that profile's peak.
    // It trains the decoder but does not steer a learned mask (its input is detached): the
    // share is largest where subcarriers hold few pilots (some chirp fits one or two exactly),
    // so its gradient pushed the mask learner from one subcarrier over every symbol onto
    // three symbols over many subcarriers (docs/RESULTS.md, the collapsed seed).
    torch::Tensor tone;
    const bool fit = with_tone && d_s.chirp_bins > 0;
    if (d_s.mti == "none") {
        auto p = power_profile(g, cols).unsqueeze(1);
        if (fit)
            tone = tone_fit(g.detach(), m, p);
        return { p, tone };
    }
    const auto clean = remove_zero_doppler(g, m);
    auto p_clean = power_profile(clean, cols).unsqueeze(1);
    if (fit)
        tone = tone_fit(clean.detach(), m, p_clean);
    if (d_s.mti == "mean")
        return { p_clean, tone };
    return { torch::cat({ power_profile(g, cols).unsqueeze(1), p_clean }, 1), tone };
}

void spectral_classifier_decoder_module::set_compact_columns(const std::vector<int64_t>& subcarriers)
{
    for (auto c : subcarriers)
        if (c < 0 || c >= d_m)
            throw std::invalid_argument("spectral classifier: compact column subcarrier " + std::to_string(c) +
                                        " outside [0, " + std::to_string(d_m) + ")");
    d_compact_cols = torch::tensor(subcarriers, torch::kLong);
}

decoder_output spectral_classifier_decoder_module::forward(const torch::Tensor&)
{
    throw std::invalid_argument("spectral classifier decoder: forward needs the pilot mask (forward(grid, mask))");
}

namespace {
// Dense products up to this many multiply-adds per frame replace a convolution at inference:
// below it one matrix product costs less than the MKL-DNN convolution's fixed cost per call
// (measured ~150 us at batch 32 for 4 channels, whatever the size).
constexpr int64_t dense_conv_max_macs = 65536;
} // namespace

torch::Tensor spectral_classifier_decoder_module::inference_conv(torch::nn::Conv1d conv,
                                                                 dense_conv& cache,
                                                                 const torch::Tensor& x,
                                                                 bool with_bn) const
{
    auto bn = d_bn; // a non-const holder
    const auto& w = conv->weight; // C_out x C_in x k
    const int64_t co = w.size(0), ci = w.size(1), k = w.size(2), bins = x.size(2);
    const bool no_grad = c10::InferenceMode::is_enabled() || !torch::GradMode::is_enabled();
    if (is_training() || !no_grad || co * ci * bins * bins > dense_conv_max_macs)
        return conv->forward(with_bn ? bn->forward(x) : x);
    std::vector<int64_t> versions{ w._version(), conv->bias._version() };
    if (with_bn)
        for (const auto* t : { &bn->weight, &bn->bias, &bn->running_mean, &bn->running_var })
            versions.push_back(t->_version());
    std::lock_guard<std::mutex> guard(cache.lock);
    if (!cache.matrix.defined() || cache.versions != versions || cache.data != w.data_ptr()) {
        torch::NoGradGuard ng;
        // y[o, t] = b[o] + sum_{i, j} w[o, i, j] x[i, (t + j - k/2) mod K] (circular padding):
        // D[(i, s), (o, t)] = sum_j w[o, i, j] [s == (t + j - k/2) mod K].
        auto shift = torch::zeros({ k, bins, bins }); // [j, s, t]
        auto ps = shift.accessor<float, 3>();
        for (int64_t j = 0; j < k; ++j)
            for (int64_t t = 0; t < bins; ++t)
                ps[j][((t + j - k / 2) % bins + bins) % bins][t] = 1.0f;
        auto d = torch::matmul(w.detach().reshape({ co * ci, k }), shift.reshape({ k, bins * bins })); // (o,i),(s,t)
        auto m = d.view({ co, ci, bins, bins }).permute({ 1, 2, 0, 3 }).reshape({ ci * bins, co * bins });
        auto b = conv->bias.detach().repeat_interleave(bins);
        if (with_bn) {
            // The BatchNorm in front (inference: x_i -> scale_i x_i + offset_i) folded in.
            const auto [scale, offset] = batchnorm_inference_affine(bn);
            b = b + torch::matmul(offset.repeat_interleave(bins), m);
            m = m * scale.repeat_interleave(bins).unsqueeze(1);
        }
        cache.matrix = m.contiguous();
        cache.bias = b.contiguous();
        cache.versions = versions;
        cache.data = w.data_ptr();
    }
    return torch::addmm(cache.bias, x.reshape({ x.size(0), ci * bins }), cache.matrix).view({ x.size(0), co, bins });
}

decoder_output spectral_classifier_decoder_module::forward(const torch::Tensor& grid, const torch::Tensor& mask)
{
    return forward(grid, mask, torch::Tensor());
}

decoder_output spectral_classifier_decoder_module::forward(const torch::Tensor& grid,
                                                           const torch::Tensor& mask,
                                                           const torch::Tensor& columns)
{
    // Leaky ReLU with conv_slope (0: ReLU, the legacy bundles).
    const auto [prof, tone] = inputs(grid, mask, true, columns);
    auto x = torch::leaky_relu(inference_conv(d_conv1, d_dense1, prof, true), d_s.conv_slope);
    x = torch::leaky_relu(inference_conv(d_conv2, d_dense2, x, false), d_s.conv_slope).flatten(1);
    x = torch::leaky_relu(d_fc1->forward(x), 0.1);
    if (tone.defined())
        x = torch::cat({ x, torch::leaky_relu(d_tone_fc->forward(d_tone_bn->forward(tone)), 0.1) }, 1);
    decoder_output out;
    out.profile = prof;
    out.features = d_fc2->forward(x);
    out.logits = d_out->forward(torch::leaky_relu(out.features, 0.1));
    if (d_templates && d_templates->ready())
        out.logits = out.logits + d_templates->forward(template_observations(grid, mask));
    return out;
}

torch::Tensor spectral_classifier_decoder_module::template_observations(const torch::Tensor& grid,
                                                                        const torch::Tensor& mask) const
{
    // The bank holds one mask's pilots in its (row-major) order; the grid's columns and the
    // mask's agree (whole or compact), so the mask's nonzero elements in order are the pilots.
    torch::Tensor m = mask;
    if (m.dim() == 3 && m.size(0) == 1)
        m = m[0];
    if (m.dim() != 2)
        throw std::invalid_argument("spectral classifier: the template bank needs one N x M mask for the batch, got " +
                                    c10::str(mask.sizes()));
    const auto idx = (m.detach().flatten() > 0.5).nonzero().squeeze(1);
    if (idx.size(0) != d_np)
        throw std::invalid_argument("spectral classifier: the template bank holds " + std::to_string(d_np) +
                                    " pilots per frame, the mask has " + std::to_string(idx.size(0)));
    return grid.flatten(2).index_select(2, idx); // B x 2 x N_p
}

nlohmann::json spectral_classifier_decoder_module::describe() const
{
    return { { "kind", kind() }, { "settings", d_s.to_json() } };
}

} // namespace nn
} // namespace sems
} // namespace gr
