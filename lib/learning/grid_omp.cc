// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: orthogonal matching pursuit on the delay grid (see lib/learning/grid_omp.h). */
#include "learning/grid_omp.h"
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace nn {

namespace {
using cd = std::complex<double>;
constexpr int max_rounds = 8;

// |Σ_s r[s] conj(D[m_s, q])| · scale for every q, over the support's subcarriers m_s.
void correlate(const std::vector<int>& sup,
               const cd* r,
               const double* dc,
               const double* ds,
               int q,
               double scale,
               double* __restrict cr,
               double* __restrict ci,
               double* __restrict mag)
{
    std::fill(cr, cr + q, 0.0);
    std::fill(ci, ci + q, 0.0);
    for (size_t s = 0; s < sup.size(); ++s) {
        const double a = r[s].real(), b = r[s].imag();
        const double* __restrict c = dc + static_cast<size_t>(sup[s]) * q;
        const double* __restrict sn = ds + static_cast<size_t>(sup[s]) * q;
        for (int k = 0; k < q; ++k) { // (a + jb)(c + j sn)
            cr[k] += a * c[k] - b * sn[k];
            ci[k] += a * sn[k] + b * c[k];
        }
    }
    for (int k = 0; k < q; ++k)
        mag[k] = std::sqrt(cr[k] * cr[k] + ci[k] * ci[k]) * scale;
}

// The first index of the largest value (a NaN counts as the largest, as torch's argmax).
int argmax(const double* v, int n)
{
    int best = 0;
    for (int k = 0; k < n; ++k) {
        if (std::isnan(v[k]))
            return k;
        if (v[k] > v[best])
            best = k;
    }
    return best;
}

// Solves G x = r in place for a Hermitian positive definite L x L matrix G (Cholesky;
// the caller regularises G). G is row-major, overwritten by its factor.
void solve_hpd(cd* g, cd* r, int l)
{
    for (int j = 0; j < l; ++j) {
        double d = g[j * l + j].real();
        for (int k = 0; k < j; ++k)
            d -= std::norm(g[j * l + k]);
        d = std::sqrt(std::max(d, 0.0));
        g[j * l + j] = d;
        for (int i = j + 1; i < l; ++i) {
            cd v = g[i * l + j];
            for (int k = 0; k < j; ++k)
                v -= g[i * l + k] * std::conj(g[j * l + k]);
            g[i * l + j] = d > 0.0 ? v / d : cd(0.0);
        }
    }
    for (int i = 0; i < l; ++i) { // L z = r
        cd v = r[i];
        for (int k = 0; k < i; ++k)
            v -= g[i * l + k] * r[k];
        r[i] = g[i * l + i].real() > 0.0 ? v / g[i * l + i].real() : cd(0.0);
    }
    for (int i = l - 1; i >= 0; --i) { // L^H x = z
        cd v = r[i];
        for (int k = i + 1; k < l; ++k)
            v -= std::conj(g[k * l + i]) * r[k];
        r[i] = g[i * l + i].real() > 0.0 ? v / g[i * l + i].real() : cd(0.0);
    }
}
} // namespace

void grid_omp_maps(const float* yr,
                   const float* yi,
                   const float* support,
                   int64_t frames,
                   int m,
                   const double* dict_cos,
                   const double* dict_sin,
                   int q,
                   int rounds,
                   double scale,
                   float* maps)
{
    if (rounds < 1 || rounds > max_rounds || m < 1 || q < 1 || frames < 0)
        throw std::invalid_argument("grid_omp_maps: need 1 <= rounds <= " + std::to_string(max_rounds) +
                                    ", m >= 1, q >= 1 (got rounds " + std::to_string(rounds) + ", m " +
                                    std::to_string(m) + ", q " + std::to_string(q) + ")");
    std::vector<int> sup;
    std::vector<cd> y, res, atoms(static_cast<size_t>(max_rounds) * m), g(max_rounds * max_rounds), b(max_rounds);
    std::vector<double> cr(q), ci(q), mag(q);
    int chosen[max_rounds];
    for (int64_t f = 0; f < frames; ++f) {
        const float* fr = yr + f * m;
        const float* fi = yi + f * m;
        const float* fs = support + f * m;
        sup.clear();
        y.clear();
        for (int k = 0; k < m; ++k)
            if (fs[k] != 0.0f) { // y is zero off the pilots' subcarriers: those terms vanish
                sup.push_back(k);
                y.emplace_back(fr[k], fi[k]);
            }
        const size_t s_n = sup.size();
        res = y;
        correlate(sup, res.data(), dict_cos, dict_sin, q, scale, cr.data(), ci.data(), mag.data());
        for (int l = 0; l < rounds; ++l) {
            chosen[l] = argmax(mag.data(), q);
            cd* a = atoms.data() + static_cast<size_t>(l) * m; // atom l on the support: D[m_s, q_l]
            for (size_t s = 0; s < s_n; ++s) {
                const size_t at = static_cast<size_t>(sup[s]) * q + chosen[l];
                a[s] = cd(dict_cos[at], -dict_sin[at]);
            }
            const int n = l + 1;
            double top = 0.0;
            for (int i = 0; i < n; ++i) {
                const cd* ai = atoms.data() + static_cast<size_t>(i) * m;
                cd rhs = 0.0;
                for (size_t s = 0; s < s_n; ++s)
                    rhs += std::conj(ai[s]) * y[s];
                b[i] = rhs;
                for (int j = 0; j < n; ++j) {
                    const cd* aj = atoms.data() + static_cast<size_t>(j) * m;
                    cd v = 0.0;
                    for (size_t s = 0; s < s_n; ++s)
                        v += std::conj(ai[s]) * aj[s];
                    g[i * n + j] = v;
                }
                top = std::max(top, g[i * n + i].real());
            }
            const double ridge = 1e-9 * (1.0 + top); // as the LibTorch version: keeps a repeated atom solvable
            for (int i = 0; i < n; ++i)
                g[i * n + i] += ridge;
            solve_hpd(g.data(), b.data(), n);
            for (size_t s = 0; s < s_n; ++s) {
                cd v = y[s];
                for (int i = 0; i < n; ++i)
                    v -= atoms[static_cast<size_t>(i) * m + s] * b[i];
                res[s] = v;
            }
            correlate(sup, res.data(), dict_cos, dict_sin, q, scale, cr.data(), ci.data(), mag.data());
            float* out = maps + (f * rounds + l) * q;
            for (int k = 0; k < q; ++k)
                out[k] = static_cast<float>(mag[k]);
        }
    }
}

} // namespace nn
} // namespace sems
} // namespace gr
