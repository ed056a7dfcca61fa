// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the correlation-driven delay decoder (see delay_decoder.h). */
#include "learning/networks/delay_decoder.h"
#include "learning/networks/grid_omp.h"
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/array/steering.h>
#include <algorithm>
#include <cmath>
#include <limits>
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

residual_block1d_module::residual_block1d_module(int c, int k, int dilation)
{
    auto opt = torch::nn::Conv1dOptions(c, c, k).padding(dilation * (k / 2)).dilation(dilation).bias(false);
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
    if (s.dilation_growth < 1 || s.kernel < 1 || s.kernel % 2 == 0)
        throw std::invalid_argument("delay decoder: need an odd kernel >= 1 and dilation_growth >= 1");
    if (s.refine_paths < 0)
        throw std::invalid_argument("delay decoder: refine_paths is " + std::to_string(s.refine_paths) +
                                    " (\"from the training scene\"): give 0 (off) or the number of paths to fit");
    if (s.refine_paths > np)
        throw std::invalid_argument("delay decoder: refine_paths = " + std::to_string(s.refine_paths) +
                                    " exceeds the " + std::to_string(np) + " pilots: at most N_p paths can be fitted");
    if (s.refine_paths > 0 && !(s.refine_span_index > 0.25 && s.refine_trust_index > 0.0))
        throw std::invalid_argument("delay decoder: refinement needs refine_span_index > 0.25 and "
                                    "refine_trust_index > 0");
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
    if (s.residual_maps < 0 || s.residual_maps > 8)
        throw std::invalid_argument("delay decoder: residual_maps must be in [0, 8], got " +
                                    std::to_string(s.residual_maps));
    d_stem = register_module("stem",
                             torch::nn::Conv1d(torch::nn::Conv1dOptions(3 * p + s.residual_maps, s.width, s.kernel)
                                                   .padding(s.kernel / 2)
                                                   .bias(false)));
    d_stem_bn = register_module("stem_bn", torch::nn::BatchNorm1d(s.width));
    d_blocks = register_module("blocks", torch::nn::Sequential());
    // Dilations 1, g, g², ... (capped so a block never dilates past the grid).
    for (int i = 0, d = 1; i < s.depth; ++i, d = std::min(d * s.dilation_growth, s.q))
        d_blocks->push_back(residual_block1d(s.width, s.kernel, d));
    d_head = register_module("head", torch::nn::Conv1d(torch::nn::Conv1dOptions(s.width, 1, 1)));
}

std::pair<torch::Tensor, torch::Tensor> delay_decoder_module::project(const torch::Tensor& x) const
{
    auto yr = x.select(1, 0), yi = x.select(1, 1); // B x N x M
    // Complex projection along slow time: P x N weights -> B x P x M.
    return { torch::matmul(d_proj_re, yr) - torch::matmul(d_proj_im, yi),
             torch::matmul(d_proj_re, yi) + torch::matmul(d_proj_im, yr) };
}

torch::Tensor delay_decoder_module::residual_maps_of(const torch::Tensor& grid)
{
    auto x = normalise_frames(grid, d_np);
    auto [xr, xi] = project(x);
    return residual_maps(xr.select(1, 0), xi.select(1, 0), (x.abs().sum(1).sum(1) > 0).to(x.dtype()),
                         1.0 / std::sqrt(static_cast<double>(d_np)));
}

decoder_output delay_decoder_module::forward(const torch::Tensor& grid)
{
    auto x = normalise_frames(grid, d_np);
    auto [xr, xi] = project(x);
    // r = x · conj(D), D = cos - j sin  =>  conj(D) = cos + j sin.
    const double scale = 1.0 / std::sqrt(static_cast<double>(d_np));
    auto rr = (torch::matmul(xr, d_dict_cos) - torch::matmul(xi, d_dict_sin)) * scale;
    auto ri = (torch::matmul(xr, d_dict_sin) + torch::matmul(xi, d_dict_cos)) * scale;
    // The strongest correlation of the first projection: the phase reference, and the second
    // start of the single-path refinement.
    const bool global_peak = !is_training() && d_s.refine_paths == 1 && d_s.refine_global_peak && d_fitter;
    torch::Tensor strongest;
    if (d_s.phase_reference || global_peak)
        strongest = (rr.select(1, 0).square() + ri.select(1, 0).square()).argmax(1, true); // B x 1
    torch::Tensor maps;
    if (d_s.residual_maps > 0)
        maps = residual_maps(xr.select(1, 0), xi.select(1, 0), (x.abs().sum(1).sum(1) > 0).to(x.dtype()), scale);
    if (d_s.phase_reference) {
        // Rotate by the phase of r_0 at its strongest q: invariant to the common phase.
        const auto& k = strongest;
        auto pr = rr.select(1, 0).gather(1, k), pi = ri.select(1, 0).gather(1, k);
        auto norm = torch::sqrt(pr * pr + pi * pi + 1e-20);
        auto c = (pr / norm).unsqueeze(1), sn = (-pi / norm).unsqueeze(1); // e^{-jφ}
        auto r2 = rr * c - ri * sn;
        ri = rr * sn + ri * c;
        rr = r2;
    }
    auto mag = torch::sqrt(rr * rr + ri * ri + 1e-12);
    // B x (3P + K) x Q, one copy.
    auto feat = maps.defined() ? torch::cat({ rr, ri, mag, maps }, 1) : torch::cat({ rr, ri, mag }, 1);
    decoder_output out;
    out.logits = folded_logits(feat);
    if (!out.logits.defined()) {
        auto h = torch::relu(d_stem_bn->forward(d_stem->forward(feat)));
        if (!d_blocks->is_empty())
            h = d_blocks->forward(h);
        out.logits = d_head->forward(h).squeeze(1);
    }
    out.delay_index = soft_argmax(out.logits, d_tau, d_s.window);
    if (!is_training() && d_s.refine_paths > 0 && d_fitter)
        out.delay_index =
            refine(x, out.delay_index, global_peak ? d_tau.index({ strongest.squeeze(1) }) : torch::Tensor());
    return out;
}

namespace {
// The folded loops run where the network costs at most this many multiply-adds per frame:
// there one LibTorch convolution call (~10-150 us whatever its size) costs more than the
// whole network as loops. The fast bundle's network is ~34 000, the accurate one's ~3.4 million.
constexpr int64_t folded_network_max_macs = 262144;

folded_conv1d fold(torch::nn::Conv1d conv, torch::nn::BatchNorm1d bn)
{
    folded_conv1d f;
    const auto w = conv->weight.detach().to(torch::kFloat).contiguous(); // out x in x k
    f.out_channels = static_cast<int>(w.size(0));
    f.in_channels = static_cast<int>(w.size(1));
    f.kernel = static_cast<int>(w.size(2));
    f.dilation = static_cast<int>((*conv->options.dilation())[0]);
    auto b = conv->bias.defined() ? conv->bias.detach().to(torch::kFloat) : torch::zeros({ w.size(0) });
    auto wf = w;
    if (bn) { // bn(conv(x)) = scale conv(x) + offset
        const auto [scale, offset] = batchnorm_inference_affine(bn);
        wf = w * scale.view({ -1, 1, 1 });
        b = b * scale + offset;
    }
    wf = wf.contiguous();
    b = b.contiguous();
    f.weight.assign(wf.data_ptr<float>(), wf.data_ptr<float>() + wf.numel());
    f.bias.assign(b.data_ptr<float>(), b.data_ptr<float>() + b.numel());
    return f;
}
} // namespace

torch::Tensor delay_decoder_module::folded_logits(const torch::Tensor& features)
{
    const bool no_grad = c10::InferenceMode::is_enabled() || !torch::GradMode::is_enabled();
    const int64_t q = d_s.q, w = d_s.width, k = d_s.kernel;
    const int64_t macs = q * k * w * (features.size(1) + 2 * d_s.depth * w) + q * w;
    if (is_training() || !no_grad || macs > folded_network_max_macs || features.scalar_type() != torch::kFloat)
        return {};
    std::vector<int64_t> versions;
    std::vector<const void*> data;
    for (const auto& t : parameters()) {
        versions.push_back(t._version());
        data.push_back(t.data_ptr());
    }
    for (const auto& t : buffers()) {
        versions.push_back(t._version());
        data.push_back(t.data_ptr());
    }
    std::shared_ptr<const std::vector<folded_conv1d>> layers;
    {
        std::lock_guard<std::mutex> guard(d_folded.lock);
        if (!d_folded.layers || d_folded.versions != versions || d_folded.data != data) {
            torch::NoGradGuard ng;
            auto built = std::make_shared<std::vector<folded_conv1d>>();
            built->push_back(fold(d_stem, d_stem_bn));
            for (const auto& m : *d_blocks) {
                auto block = m.ptr<residual_block1d_module>();
                built->push_back(fold(block->conv1, block->bn1));
                built->push_back(fold(block->conv2, block->bn2));
            }
            built->push_back(fold(d_head, nullptr));
            d_folded.layers = std::move(built);
            d_folded.versions = versions;
            d_folded.data = data;
        }
        layers = d_folded.layers; // a snapshot: concurrent calls run without the lock
    }
    const auto x = features.contiguous();
    const int64_t b = x.size(0);
    // Two B x width x Q buffers: h (the block input, updated in place by the residual
    // layer) and u (the block's middle).
    auto h = torch::empty({ b, w, q }, torch::kFloat), u = torch::empty({ b, w, q }, torch::kFloat);
    auto logits = torch::empty({ b, q }, torch::kFloat);
    const auto& L = *layers;
    folded_conv1d_forward(L.front(), x.data_ptr<float>(), b, q, nullptr, true, h.data_ptr<float>());
    for (size_t i = 1; i + 1 < L.size(); i += 2) {
        folded_conv1d_forward(L[i], h.data_ptr<float>(), b, q, nullptr, true, u.data_ptr<float>());
        folded_conv1d_forward(L[i + 1], u.data_ptr<float>(), b, q, h.data_ptr<float>(), true, h.data_ptr<float>());
    }
    folded_conv1d_forward(L.back(), h.data_ptr<float>(), b, q, nullptr, false, logits.data_ptr<float>());
    return logits;
}

torch::Tensor delay_decoder_module::residual_maps(const torch::Tensor& xr,
                                                  const torch::Tensor& xi,
                                                  const torch::Tensor& support,
                                                  double scale) const
{
    // Orthogonal matching pursuit on the grid, without gradient (a fixed feature extractor):
    // lib/learning/networks/grid_omp.h, in double precision from the float dictionary buffers.
    torch::NoGradGuard ng;
    const auto yr = xr.detach().to(torch::kFloat).contiguous(), yi = xi.detach().to(torch::kFloat).contiguous();
    const auto sup = support.detach().to(torch::kFloat).contiguous();
    const auto dc = d_dict_cos.contiguous(), ds = d_dict_sin.contiguous(); // float, M x Q: no copy
    const int64_t b = yr.size(0);
    auto maps = torch::empty({ b, d_s.residual_maps, d_s.q }, torch::kFloat);
    grid_omp_maps(yr.data_ptr<float>(), yi.data_ptr<float>(), sup.data_ptr<float>(), b, d_m,
                  dc.data_ptr<float>(), ds.data_ptr<float>(), d_s.q, d_s.residual_maps, scale,
                  maps.data_ptr<float>());
    return maps.to(xr.scalar_type()); // B x K x Q
}

void delay_decoder_module::set_pilot_positions(const frame_settings& fs, const std::vector<int64_t>& flat)
{
    if (fs.n_symbols != d_n || fs.n_subcarriers != d_m)
        throw std::invalid_argument("delay decoder: pilot positions for a " + std::to_string(fs.n_symbols) + " x " +
                                    std::to_string(fs.n_subcarriers) + " frame, but the decoder is " +
                                    std::to_string(d_n) + " x " + std::to_string(d_m));
    if (static_cast<int>(flat.size()) != d_np)
        throw std::invalid_argument("delay decoder: " + std::to_string(flat.size()) +
                                    " pilot positions, but the decoder takes " + std::to_string(d_np));
    std::vector<pilot_position> pos;
    for (int64_t f : flat)
        pos.push_back({ static_cast<int>(f / d_m), static_cast<int>(f % d_m) });
    // The mask constructor checks range and distinctness; pilots stay in the given order
    // only if it is mask order, which is what gather_pilots and the trainer use.
    const pilot_mask mask(d_n, d_m, pos, gr_complex(1.0f, 0.0f), { { "kind", "explicit" } },
                          "delay decoder pilot positions");
    for (size_t k = 0; k < flat.size(); ++k)
        if (static_cast<int64_t>(mask.positions()[k].n) * d_m + mask.positions()[k].m != flat[k])
            throw std::invalid_argument("delay decoder: pilot positions must be in mask order (row-major)");
    d_positions = flat;
    // The pilots are float32 (relative precision 6e-8): a step below 1e-7 of a delay index
    // (or of a cycle per symbol) no longer moves the estimate by anything the data can tell;
    // the baselines' default (1e-10) cost the decoder one or two more LM iterations per frame.
    multipath_fitter::settings fit;
    fit.tolerance = 1e-7;
    d_fitter = std::make_shared<multipath_fitter>(fs, mask, fit);
    d_global_fit.reset();
    if (d_s.refine_paths > 1 && d_s.refine_global_fit) {
        // The reference searches the decoder's own dictionary grid (window and spacing).
        ls_delay_estimator::settings ls;
        ls.search.oversample = std::max(1, static_cast<int>(std::lround(1.0 / d_s.spacing())));
        ls.search.min_index = d_s.tau_min_index;
        ls.search.max_index = d_s.tau_max_index;
        ls.n_paths = d_s.refine_paths;
        ls.fit = fit;
        d_global_fit = std::make_shared<ls_delay_estimator>(fs, mask, ls);
    }
}

namespace {
// refine_global_fit: closer than this the two fits agree on which path is first (the
// refinement has settled within its own trust region), so the network's answer stays.
constexpr double global_fit_min_move = 0.25;
// refine_global_fit: the reference's fit replaces the network's only when it lowers the
// residual by more than this many noise variances (twice the log-likelihood ratio under
// the model). The scene's micro-Doppler does not share the paths' Doppler, so two different
// 3-path fits of one frame often differ by a few variances: with any gain accepted, 0.3 %
// of the shipped bundle's frames moved to a spurious early "path" (mean 0.098 on
// qa_learning_shipped's 3 000 frames at 30 dB, twice that with 20); 10 and 40 gave means
// within 0.006 of 20's there and on three other frame sets (docs/results/notes/shipped_models.md).
constexpr double global_fit_min_gain = 20.0;
} // namespace

torch::Tensor
delay_decoder_module::refine(const torch::Tensor& x, const torch::Tensor& estimate, const torch::Tensor& peak) const
{
    // The pilots of the normalised grid (a common scale does not move a delay), in mask order.
    auto obs = gather_pilots(x, d_positions).contiguous(); // B x N_p x 2
    auto est = estimate.to(torch::kDouble).contiguous();
    const int64_t b = obs.size(0);
    auto out = torch::empty({ b }, torch::kDouble);
    const auto* po = reinterpret_cast<const gr_complex*>(obs.data_ptr<float>());
    const double* pe = est.data_ptr<double>();
    double* pr = out.data_ptr<double>();
    torch::Tensor pk;
    if (peak.defined())
        pk = peak.to(torch::kDouble).contiguous();
    const double* pp = pk.defined() ? pk.data_ptr<double>() : nullptr;
    // Whether a model leaving `residual` explains refine_global_min_fraction of y's energy.
    auto explains = [this](const gr_complex* y, double residual) {
        double energy = 0.0;
        for (int k = 0; k < d_np; ++k)
            energy += std::norm(std::complex<double>(y[k]));
        return energy > 0.0 && 1.0 - residual / energy >= d_s.refine_global_min_fraction;
    };
    for (int64_t i = 0; i < b; ++i) {
        const gr_complex* y = po + i * d_np;
        const auto fit = d_fitter->refine_anchored(y, pe[i], d_s.refine_paths, d_s.refine_span_index);
        const double first = fit.delay_index.front();
        const bool trusted = std::isfinite(first) && std::abs(first - pe[i]) < d_s.refine_trust_index;
        pr[i] = trusted ? first : pe[i];
        if (d_global_fit) { // multipath: the oracle-order reference as the second start
            // A frame the decoder's own fit explains poorly (low SNR): the reference, far worse
            // than the network there, would only trade noise for noise. Skip it.
            if (d_s.refine_global_min_fraction > 0.0 && !explains(y, fit.residual))
                continue;
            const auto other = d_global_fit->fit(y);
            const double alt = *std::min_element(other.delay_index.begin(), other.delay_index.end());
            if (!(std::isfinite(alt) && alt >= d_s.tau_min_index && alt <= d_s.tau_max_index &&
                  std::abs(alt - pr[i]) > global_fit_min_move))
                continue;
            // The residual of what is kept: the fit, or (outside the trust region) the
            // network's delay with the fit's later paths.
            double kept = fit.residual;
            if (!trusted) {
                auto delays = fit.delay_index;
                delays.front() = pe[i];
                const bool finite = std::all_of(delays.begin(), delays.end(), [](double t) { return std::isfinite(t); });
                kept = finite ? d_fitter->evaluate(y, delays, fit.doppler_hz).residual
                              : std::numeric_limits<double>::infinity();
            }
            if (other.residual < kept) {
                // The residual of the better fit over its degrees of freedom estimates the
                // noise variance; the improvement must exceed global_fit_min_gain of them.
                const double dof = 2.0 * d_np - (3.0 * d_s.refine_paths + 1.0);
                if ((kept - other.residual) * dof > global_fit_min_gain * other.residual)
                    pr[i] = alt;
            }
            continue;
        }
        if (!pp || !(std::abs(pp[i] - pe[i]) > d_s.refine_trust_index))
            continue; // no second start, or the network is already at the grid peak
        if (d_s.refine_global_min_fraction > 0.0 && // a peak that noise alone could make: skip
            !explains(y, d_fitter->evaluate(y, { pp[i] }, fit.doppler_hz).residual))
            continue;
        // One path: the kept delay's residual against the fit from the grid peak.
        const double kept = trusted ? fit.residual : d_fitter->evaluate(y, { pe[i] }, fit.doppler_hz).residual;
        const auto other = d_fitter->refine_anchored(y, pp[i], 1, d_s.refine_span_index);
        const double alt = other.delay_index.front();
        if (std::isfinite(alt) && alt >= d_s.tau_min_index && alt <= d_s.tau_max_index && other.residual < kept)
            pr[i] = alt;
    }
    return out.to(estimate.scalar_type());
}

nlohmann::json delay_decoder_module::describe() const
{
    return { { "kind", kind() }, { "settings", d_s.to_json() } };
}

} // namespace nn
} // namespace sems
} // namespace gr
