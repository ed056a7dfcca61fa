// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: orthogonal matching pursuit on the delay grid (see lib/learning/networks/grid_omp.h). */
#include "learning/networks/grid_omp.h"
#include "core/kernels/cpu_dispatch.h"
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SEMS_GRID_OMP_FUSED 1
#endif

namespace gr {
namespace sems {
namespace nn {

namespace {
using cd = std::complex<double>;
constexpr int max_rounds = 8;
// At most max_rounds atoms: Gram matrices and coefficients live on the stack.
using gram = Eigen::Matrix<cd, Eigen::Dynamic, Eigen::Dynamic, 0, max_rounds, max_rounds>;
using coeffs = Eigen::Matrix<cd, Eigen::Dynamic, 1, 0, max_rounds, 1>;

// The sums of the delays k0 <= k < q past the last full block, as plain loops (the order of
// a loop over s outside): both correlations end with it.
inline void correlate_tail(const std::vector<int>& sup,
                           const cd* r,
                           const float* dc,
                           const float* ds,
                           int q,
                           int k0,
                           double* __restrict cr,
                           double* __restrict ci)
{
    std::fill(cr + k0, cr + q, 0.0);
    std::fill(ci + k0, ci + q, 0.0);
    for (size_t s = 0; s < sup.size(); ++s) {
        const double a = r[s].real(), b = r[s].imag();
        const float* c = dc + static_cast<size_t>(sup[s]) * q;
        const float* sn = ds + static_cast<size_t>(sup[s]) * q;
        for (int k = k0; k < q; ++k) {
            cr[k] += a * c[k] - b * sn[k];
            ci[k] += a * sn[k] + b * c[k];
        }
    }
}

// |Σ_s r[s] conj(D[m_s, q])| · scale for every q, over the support's subcarriers m_s (the
// float dictionary promoted to double, as the operator form did). The delay decoder's
// hottest loop of its own (rounds + 1 calls per frame). This exact version rounds every
// product and every sum as written (no FMA); its AVX2 clone runs four doubles per
// instruction, the same operations in the same order, so both give the same bits.
SEMS_TARGET_CLONES("avx2", "default")
void correlate_exact(const std::vector<int>& sup,
                     const cd* r,
                     const float* dc,
                     const float* ds,
                     int q,
                     double scale,
                     double* __restrict cr,
                     double* __restrict ci,
                     double* __restrict mag)
{
    // Blocks of 16 delays held in registers while the support is summed (in order, as a
    // plain loop over s would): the dictionary is read once and the sums never leave the
    // registers, where a loop over s outside stored and reloaded all q sums per subcarrier.
    constexpr int block = 16;
    const size_t n_sup = sup.size();
    int k0 = 0;
    for (; k0 + block <= q; k0 += block) {
        double sr[block] = {}, si[block] = {};
        for (size_t s = 0; s < n_sup; ++s) {
            const double a = r[s].real(), b = r[s].imag();
            const float* __restrict c = dc + static_cast<size_t>(sup[s]) * q + k0;
            const float* __restrict sn = ds + static_cast<size_t>(sup[s]) * q + k0;
            for (int j = 0; j < block; ++j) { // (a + jb)(c + j sn)
                sr[j] += a * c[j] - b * sn[j];
                si[j] += a * sn[j] + b * c[j];
            }
        }
        for (int j = 0; j < block; ++j) {
            cr[k0 + j] = sr[j];
            ci[k0 + j] = si[j];
        }
    }
    correlate_tail(sup, r, dc, ds, q, k0, cr, ci);
    for (int k = 0; k < q; ++k)
        mag[k] = std::sqrt(cr[k] * cr[k] + ci[k] * ci[k]) * scale;
}

#ifdef SEMS_GRID_OMP_FUSED
// correlate_exact with fused multiply-adds (AVX2 + FMA): each sum takes a·c and −b·sn (a·sn
// and b·c) as two FMAs, one rounding per product-and-add where the exact loop rounds twice,
// and half its arithmetic instructions. The sums differ from the exact ones by a few units
// in the last place of a double (~1e-16 relative); the float maps almost always keep their
// bits. Delays past the last block of 16 run the exact loop's tail.
__attribute__((target("avx2,fma"))) void correlate_fused(const std::vector<int>& sup,
                                                         const cd* r,
                                                         const float* dc,
                                                         const float* ds,
                                                         int q,
                                                         double scale,
                                                         double* __restrict cr,
                                                         double* __restrict ci,
                                                         double* __restrict mag)
{
    constexpr int block = 16;
    const size_t n_sup = sup.size();
    int k0 = 0;
    for (; k0 + block <= q; k0 += block) {
        __m256d sr[4], si[4];
        for (int j = 0; j < 4; ++j)
            sr[j] = si[j] = _mm256_setzero_pd();
        for (size_t s = 0; s < n_sup; ++s) {
            const __m256d a = _mm256_set1_pd(r[s].real()), b = _mm256_set1_pd(r[s].imag());
            const float* c = dc + static_cast<size_t>(sup[s]) * q + k0;
            const float* sn = ds + static_cast<size_t>(sup[s]) * q + k0;
            for (int j = 0; j < 4; ++j) { // (a + jb)(c + j sn), four delays per register
                const __m256d cj = _mm256_cvtps_pd(_mm_loadu_ps(c + 4 * j));
                const __m256d sj = _mm256_cvtps_pd(_mm_loadu_ps(sn + 4 * j));
                sr[j] = _mm256_fnmadd_pd(b, sj, _mm256_fmadd_pd(a, cj, sr[j]));
                si[j] = _mm256_fmadd_pd(b, cj, _mm256_fmadd_pd(a, sj, si[j]));
            }
        }
        for (int j = 0; j < 4; ++j) {
            _mm256_storeu_pd(cr + k0 + 4 * j, sr[j]);
            _mm256_storeu_pd(ci + k0 + 4 * j, si[j]);
            const __m256d m2 = _mm256_add_pd(_mm256_mul_pd(sr[j], sr[j]), _mm256_mul_pd(si[j], si[j]));
            _mm256_storeu_pd(mag + k0 + 4 * j, _mm256_mul_pd(_mm256_sqrt_pd(m2), _mm256_set1_pd(scale)));
        }
    }
    _mm256_zeroupper(); // GCC leaves the upper halves dirty otherwise (see complex_kernels.cc)
    correlate_tail(sup, r, dc, ds, q, k0, cr, ci);
    for (int k = k0; k < q; ++k)
        mag[k] = std::sqrt(cr[k] * cr[k] + ci[k] * ci[k]) * scale;
}
#endif

// Whether the fused correlation runs where the CPU has it (a test may choose the exact one).
std::atomic<bool> prefer_fused{ true };

void correlate(const std::vector<int>& sup,
               const cd* r,
               const float* dc,
               const float* ds,
               int q,
               double scale,
               double* cr,
               double* ci,
               double* mag)
{
#ifdef SEMS_GRID_OMP_FUSED
    if (prefer_fused.load(std::memory_order_relaxed) && grid_omp_fused_available()) {
        correlate_fused(sup, r, dc, ds, q, scale, cr, ci, mag);
        return;
    }
#endif
    correlate_exact(sup, r, dc, ds, q, scale, cr, ci, mag);
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
} // namespace

bool grid_omp_fused_available()
{
#ifdef SEMS_GRID_OMP_FUSED
    // Asked on first use, not during the library's static initialisation (where the CPU
    // model __builtin_cpu_supports reads may not be filled in yet).
    static const bool available = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    }();
    return available;
#else
    return false;
#endif
}

bool grid_omp_use_fused(bool fused)
{
    prefer_fused.store(fused, std::memory_order_relaxed);
    return fused && grid_omp_fused_available();
}

void grid_omp_maps(const float* yr,
                   const float* yi,
                   const float* support,
                   int64_t frames,
                   int m,
                   const float* dict_cos,
                   const float* dict_sin,
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
    std::vector<cd> y, res, atoms(static_cast<size_t>(max_rounds) * m);
    std::vector<double> cr(q), ci(q), mag(q);
    int chosen[max_rounds];
    gram g_all(max_rounds, max_rounds); // A^H A and A^H y of the atoms so far, grown a row per round
    coeffs b_all(max_rounds);
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
            // The earlier atoms' rows are those of the previous round: only atom l's are new.
            {
                cd rhs = 0.0;
                for (size_t s = 0; s < s_n; ++s)
                    rhs += std::conj(a[s]) * y[s];
                b_all[l] = rhs;
                for (int j = 0; j < n; ++j) {
                    const cd* aj = atoms.data() + static_cast<size_t>(j) * m;
                    cd v = 0.0, w = 0.0;
                    for (size_t s = 0; s < s_n; ++s) {
                        v += std::conj(a[s]) * aj[s];
                        w += std::conj(aj[s]) * a[s];
                    }
                    g_all(l, j) = v;
                    g_all(j, l) = w;
                }
            }
            gram g = g_all.topLeftCorner(n, n);
            coeffs b = b_all.head(n);
            // As the LibTorch version: a ridge keeps a repeated atom solvable (G stays positive definite).
            g.diagonal().array() += cd(1e-9 * (1.0 + g.diagonal().real().maxCoeff()), 0.0);
            b = g.llt().solve(b).eval();
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
