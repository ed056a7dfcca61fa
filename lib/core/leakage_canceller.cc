// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: leakage canceller (see leakage_canceller.h). */
#include <gnuradio/sems/core/leakage_canceller.h>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

void leakage_canceller_settings::validate() const
{
    if (taps < 1 || taps > 64)
        throw std::invalid_argument("leakage_canceller: taps must be in [1, 64], got " + std::to_string(taps));
    if (window < 2 * regressors())
        throw std::invalid_argument("leakage_canceller: window must be >= 2 x the " +
                                    std::to_string(regressors()) + " regressors (" +
                                    std::to_string(2 * regressors()) + " samples), got " + std::to_string(window));
    if (!(forgetting >= 0.0 && forgetting < 1.0))
        throw std::invalid_argument("leakage_canceller: forgetting must be in [0, 1), got " +
                                    std::to_string(forgetting));
    if (!(std::isfinite(clip_level) && clip_level >= 0.0))
        throw std::invalid_argument("leakage_canceller: clip_level (the converter's full scale) must be finite "
                                    "and >= 0 (0: no clipping handled), got " +
                                    std::to_string(clip_level));
}

leakage_fit::leakage_fit(const leakage_canceller_settings& settings) : d_set(settings)
{
    d_set.validate();
    reset();
}

void leakage_fit::hold_as_steady_state()
{
    const double weight = 1.0 / (1.0 - d_set.forgetting);
    for (auto& v : d_r)
        v *= weight;
    for (auto& v : d_p)
        v *= weight;
}

void leakage_fit::reset()
{
    const size_t k = size_t(d_set.regressors()), l = size_t(d_set.taps);
    d_r.assign(k * k, 0.0);
    d_p.assign(k, 0.0);
    d_hist.assign(l - 1 + size_t(d_set.window), gr_complex(0.0f, 0.0f));
    d_h.assign(l, gr_complex(0.0f, 0.0f));
    d_g.assign(l, gr_complex(0.0f, 0.0f));
    d_c = gr_complex(0.0f, 0.0f);
    d_windows = 0;
    d_clipped.assign(d_set.clip_level > 0.0 ? size_t(d_set.window) : 0, 0);
}

void leakage_fit::mark_clipped(const gr_complex* rx)
{
    // A rail at full scale, compared in float as the stream carries it (a relative margin of
    // a few float steps, so a full scale given in double still matches its float copy).
    const float level = float(d_set.clip_level) * (1.0f - 1e-6f);
    for (size_t n = 0; n < d_clipped.size(); ++n)
        d_clipped[n] = (unsigned char)((std::abs(rx[n].real()) >= level ? 1 : 0) |
                                       (std::abs(rx[n].imag()) >= level ? 2 : 0));
}

namespace {
// The residual a clipped rail can still vouch for: at +full scale the echo is at least the
// residual, so a negative residual is the leakage's lost overshoot and becomes 0.
float bounded_residual(float received, float residual)
{
    return received > 0.0f ? std::max(residual, 0.0f) : std::min(residual, 0.0f);
}
} // namespace

// φ = [tx[n] .. tx[n−L+1], conj(tx[n]) .. conj(tx[n−L+1]), 1] (parts as configured)
void leakage_fit::regressors(size_t n, std::complex<double>* phi) const
{
    const size_t l = size_t(d_set.taps);
    const gr_complex* t = d_hist.data() + n + l - 1; // tx[n]
    size_t i = 0;
    for (size_t d = 0; d < l; ++d)
        phi[i++] = std::complex<double>(*(t - d));
    if (d_set.widely_linear)
        for (size_t d = 0; d < l; ++d)
            phi[i++] = std::conj(std::complex<double>(*(t - d)));
    if (d_set.dc)
        phi[i++] = 1.0;
}

void leakage_fit::process(const gr_complex* rx, const gr_complex* tx, gr_complex* out)
{
    const size_t w = size_t(d_set.window), l = size_t(d_set.taps), k = size_t(d_set.regressors());
    std::copy(tx, tx + w, d_hist.begin() + std::ptrdiff_t(l - 1));

    // Normal equations of this window, added to the forgotten ones (upper triangle).
    const double lambda = d_set.forgetting;
    for (auto& v : d_r)
        v *= lambda;
    for (auto& v : d_p)
        v *= lambda;
    const bool clipping = d_set.clip_level > 0.0;
    if (clipping)
        mark_clipped(rx);
    std::vector<std::complex<double>> phi(k);
    for (size_t n = 0; n < w; ++n) {
        if (clipping && d_clipped[n])
            continue; // a clipped sample is not the model's: left out of the fit
        regressors(n, phi.data());
        const std::complex<double> y(rx[n]);
        for (size_t i = 0; i < k; ++i) {
            const std::complex<double> ci = std::conj(phi[i]);
            d_p[i] += ci * y;
            std::complex<double>* row = d_r.data() + i * k;
            for (size_t j = i; j < k; ++j)
                row[j] += ci * phi[j];
        }
    }

    // Solve R·w = p (Hermitian, positive semi-definite). A tiny diagonal load keeps a
    // degenerate window (silence, a real-valued tx making conj(tx) = tx) solvable: there
    // the split between taps is arbitrary but the fit is the same.
    Eigen::MatrixXcd r(k, k);
    Eigen::VectorXcd p(k);
    double trace = 0.0;
    for (size_t i = 0; i < k; ++i) {
        p(Eigen::Index(i)) = d_p[i];
        trace += d_r[i * k + i].real();
        for (size_t j = i; j < k; ++j) {
            r(Eigen::Index(i), Eigen::Index(j)) = d_r[i * k + j];
            r(Eigen::Index(j), Eigen::Index(i)) = std::conj(d_r[i * k + j]);
        }
    }
    Eigen::VectorXcd coef = Eigen::VectorXcd::Zero(Eigen::Index(k));
    if (trace > 0.0) {
        r.diagonal().array() += 1e-12 * trace / double(k);
        coef = r.ldlt().solve(p);
    }
    size_t i = 0;
    for (size_t d = 0; d < l; ++d)
        d_h[d] = gr_complex(coef(Eigen::Index(i++)));
    for (size_t d = 0; d < l; ++d)
        d_g[d] = d_set.widely_linear ? gr_complex(coef(Eigen::Index(i++))) : gr_complex(0.0f, 0.0f);
    d_c = d_set.dc ? gr_complex(coef(Eigen::Index(i))) : gr_complex(0.0f, 0.0f);

    // Subtract the fit from the window.
    for (size_t n = 0; n < w; ++n) {
        regressors(n, phi.data());
        std::complex<double> fit(0.0, 0.0);
        for (size_t j = 0; j < k; ++j)
            fit += coef(Eigen::Index(j)) * phi[j];
        gr_complex residual = rx[n] - gr_complex(fit);
        if (clipping && d_clipped[n]) {
            if (d_clipped[n] & 1)
                residual.real(bounded_residual(rx[n].real(), residual.real()));
            if (d_clipped[n] & 2)
                residual.imag(bounded_residual(rx[n].imag(), residual.imag()));
        }
        out[n] = residual;
    }
    // Keep the last L − 1 transmitted samples for the next window.
    std::copy(d_hist.end() - std::ptrdiff_t(l - 1), d_hist.end(), d_hist.begin());
    ++d_windows;
}

} // namespace sems
} // namespace gr
