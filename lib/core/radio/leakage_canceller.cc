// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: leakage canceller (see leakage_canceller.h). */
#include <gnuradio/sems/core/radio/leakage_canceller.h>
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

// Σ_n conj(φ(n))·φ(n)ᵀ over the window (upper triangle), added to R. Its entries are lagged
// products of the transmitted samples summed over a shifted range, so each lag's products are
// summed once (prefix sums in double) and every entry of that lag is a difference of two: L
// passes for the direct and L for the image block, instead of K(K + 1)/2 products per sample.
void leakage_fit::add_window_normal_matrix()
{
    const size_t w = size_t(d_set.window), l = size_t(d_set.taps), k = size_t(d_set.regressors());
    const size_t len = w + l - 1; // the history and the window
    const gr_complex* x = d_hist.data();
    // x index of regressor `a`'s sample n: n + l − 1 − a, so it spans [l − 1 − a, l − 1 − a + w).
    std::vector<std::complex<double>>& direct = d_prefix_direct; // Σ conj(x[m + d])·x[m]
    std::vector<std::complex<double>>& image = d_prefix_image;   // Σ conj(x[m + d])·conj(x[m])
    auto sum = [&](const std::vector<std::complex<double>>& prefix, size_t from) {
        return prefix[from + w] - prefix[from];
    };
    for (size_t d = 0; d < l; ++d) {
        direct.assign(len - d + 1, 0.0);
        image.assign(d_set.widely_linear ? len - d + 1 : 0, 0.0);
        for (size_t m = 0; m + d < len; ++m) {
            const std::complex<double> lead = std::conj(std::complex<double>(x[m + d])), now(x[m]);
            direct[m + 1] = direct[m] + lead * now;
            if (d_set.widely_linear)
                image[m + 1] = image[m] + lead * std::conj(now);
        }
        // R[a][a + d] = Σ_n conj(x[n + l − 1 − a])·x[n + l − 1 − a − d]: m = n + l − 1 − a − d.
        for (size_t a = 0; a + d < l; ++a) {
            const size_t b = a + d, from = l - 1 - b;
            const std::complex<double> v = sum(direct, from);
            d_r[a * k + b] += v;
            if (d_set.widely_linear) {
                d_r[(l + a) * k + (l + b)] += std::conj(v); // Σ x[·a]·conj(x[·b])
                // R[a][l + b] = Σ conj(x[·a])·conj(x[·b]), symmetric in a and b.
                const std::complex<double> u = sum(image, from);
                d_r[a * k + (l + b)] += u;
                if (d != 0)
                    d_r[b * k + (l + a)] += u;
            }
        }
    }
    if (d_set.dc) { // R[i][K − 1] = Σ conj(φ_i), R[K − 1][K − 1] = W
        std::vector<std::complex<double>>& prefix = d_prefix_direct;
        prefix.assign(len + 1, 0.0);
        for (size_t m = 0; m < len; ++m)
            prefix[m + 1] = prefix[m] + std::complex<double>(x[m]);
        for (size_t a = 0; a < l; ++a) {
            const std::complex<double> v = sum(prefix, l - 1 - a);
            d_r[a * k + (k - 1)] += std::conj(v);
            if (d_set.widely_linear)
                d_r[(l + a) * k + (k - 1)] += v;
        }
        d_r[(k - 1) * k + (k - 1)] += double(w);
    }
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
    add_window_normal_matrix();
    // The right side p_i = Σ_n conj(φ_i(n))·rx[n], one regressor at a time over the window;
    // clipped samples are not the model's: their terms come out of R and p again.
    const gr_complex* x = d_hist.data() + (l - 1); // x[n − d] = tx[n − d]
    for (size_t d = 0; d < l; ++d) {
        std::complex<double> direct(0.0, 0.0), image(0.0, 0.0);
        for (size_t n = 0; n < w; ++n) {
            const std::complex<double> t(x[ptrdiff_t(n) - ptrdiff_t(d)]), y(rx[n]);
            direct += std::conj(t) * y;
            image += t * y;
        }
        d_p[d] += direct;
        if (d_set.widely_linear)
            d_p[l + d] += image;
    }
    if (d_set.dc) {
        std::complex<double> total(0.0, 0.0);
        for (size_t n = 0; n < w; ++n)
            total += std::complex<double>(rx[n]);
        d_p[k - 1] += total;
    }
    std::vector<std::complex<double>> phi(k);
    if (clipping)
        for (size_t n = 0; n < w; ++n) {
            if (!d_clipped[n])
                continue;
            regressors(n, phi.data());
            const std::complex<double> y(rx[n]);
            for (size_t i = 0; i < k; ++i) {
                const std::complex<double> ci = std::conj(phi[i]);
                d_p[i] -= ci * y;
                std::complex<double>* row = d_r.data() + i * k;
                for (size_t j = i; j < k; ++j)
                    row[j] -= ci * phi[j];
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
    std::vector<std::complex<double>>& fit = d_fit;
    fit.assign(w, std::complex<double>(d_set.dc ? coef(Eigen::Index(k - 1)) : 0.0));
    for (size_t d = 0; d < l; ++d) {
        const std::complex<double> h = coef(Eigen::Index(d));
        const std::complex<double> g = d_set.widely_linear ? coef(Eigen::Index(l + d)) : 0.0;
        for (size_t n = 0; n < w; ++n) {
            const std::complex<double> t(x[ptrdiff_t(n) - ptrdiff_t(d)]);
            fit[n] += h * t + g * std::conj(t);
        }
    }
    for (size_t n = 0; n < w; ++n) {
        gr_complex residual = rx[n] - gr_complex(fit[n]);
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
