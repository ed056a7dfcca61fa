// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: van de Beek's cyclic-prefix timing and frequency offset (see cp_sync.h). */
#include <gnuradio/sems/core/frame/cp_sync.h>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {

void check(int symbols, int m, int cp)
{
    if (symbols < 1)
        throw std::invalid_argument("cp_sync: symbols must be >= 1, got " + std::to_string(symbols));
    if (m < 1)
        throw std::invalid_argument("cp_sync: m (the FFT size) must be >= 1, got " + std::to_string(m));
    if (cp < 1 || cp > m)
        throw std::invalid_argument("cp_sync: cp must be in [1, M = " + std::to_string(m) +
                                    "] (no prefix, nothing to correlate), got " + std::to_string(cp));
}

// γ and Φ of the symbols starting at θ, θ + S, ... (S = M + cp)
void correlate(const gr_complex* x, int symbols, int m, int cp, int theta, std::complex<double>& g, double& phi)
{
    g = 0.0;
    phi = 0.0;
    const size_t s = size_t(m + cp);
    for (int k = 0; k < symbols; ++k) {
        const gr_complex* p = x + size_t(theta) + size_t(k) * s;
        for (int i = 0; i < cp; ++i) {
            const std::complex<double> a(p[i]), b(p[i + m]);
            g += a * std::conj(b);
            phi += 0.5 * (std::norm(a) + std::norm(b));
        }
    }
}

double cfo_of(const std::complex<double>& g)
{
    double e = -std::arg(g) / (2.0 * M_PI); // (−½, ½]
    return e >= 0.5 ? e - 1.0 : e;
}

} // namespace

cp_sync_estimate cp_sync(const gr_complex* x, int symbols, int m, int cp, double snr)
{
    check(symbols, m, cp);
    if (!(snr > 0.0))
        throw std::invalid_argument("cp_sync: snr must be > 0 (linear), got " + std::to_string(snr));
    const double rho = std::isinf(snr) ? 1.0 : snr / (snr + 1.0);
    cp_sync_estimate best;
    best.metric = -INFINITY;
    std::complex<double> best_g = 0.0;
    for (int theta = 0; theta < m + cp; ++theta) {
        std::complex<double> g;
        double phi;
        correlate(x, symbols, m, cp, theta, g, phi);
        const double metric = std::abs(g) - rho * phi;
        if (metric > best.metric) {
            best.metric = metric;
            best.timing = theta;
            best_g = g;
        }
    }
    best.cfo = cfo_of(best_g);
    return best;
}

double cp_cfo(const gr_complex* x, int symbols, int m, int cp)
{
    check(symbols, m, cp);
    std::complex<double> g;
    double phi;
    correlate(x, symbols, m, cp, 0, g, phi);
    return cfo_of(g);
}

void cp_cfo_correct(gr_complex* x, size_t n, double cfo, int m, unsigned long long k0)
{
    if (m < 1)
        throw std::invalid_argument("cp_cfo_correct: m (the FFT size) must be >= 1, got " + std::to_string(m));
    if (!std::isfinite(cfo))
        throw std::invalid_argument("cp_cfo_correct: cfo must be finite, got " + std::to_string(cfo));
    // The phase of sample k0 + k in turns, reduced in long double: continuous across calls.
    for (size_t k = 0; k < n; ++k) {
        const long double turns = std::fmod((long double)cfo * (long double)(k0 + k) / m, 1.0L);
        x[k] *= gr_complex(std::polar(1.0, -2.0 * M_PI * double(turns)));
    }
}

double cp_cfo_variance(double snr, long pairs)
{
    return (1.0 / snr + 1.0 / (2.0 * snr * snr)) / (4.0 * M_PI * M_PI * double(pairs));
}

} // namespace sems
} // namespace gr
