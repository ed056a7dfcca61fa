// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the emulators' fused complex loops (see complex_kernels.h).
 *
 * Interleaved complex products written out: a·b = (ar·br − ai·bi, ar·bi + ai·br). The AVX2
 * versions compute four complex values at once with exactly these products and sums
 * (addsub, no FMA), so they agree bit for bit with the portable loops; the portable loops
 * are plain float arithmetic (std::complex's operator* would keep a NaN recovery branch).
 * Without AVX2 the rows run VOLK's kernels instead (complex_kernels.h).
 *
 * Each AVX2 loop ends with vzeroupper itself: GCC does not add it to a function compiled
 * with target("avx2") in an SSE2 file, and the SSE code that runs next in the thread (the
 * block's work(), the scheduler) then paid for the dirty upper halves on every
 * instruction (measured: the channel block's CPU time per symbol up by ~60 % of the kernel's).
 */
#include "core/kernels/complex_kernels.h"
#include "core/kernels/complex_mul.h"
#include <volk/volk.h>
#include <algorithm>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SEMS_KERNELS_AVX2 1
#endif

namespace gr {
namespace sems {
namespace detail {

namespace {

void accumulate_rotated_portable(float* o, const float* x, const float* d, float cr, float ci, int k, int n)
{
    for (; k < n; ++k) {
        const float pr = d[2 * k] * cr - d[2 * k + 1] * ci; // p = c·d[k]
        const float pi = d[2 * k + 1] * cr + d[2 * k] * ci;
        const float xr = x[2 * k], xi = x[2 * k + 1];
        o[2 * k] += xr * pr - xi * pi;
        o[2 * k + 1] += xi * pr + xr * pi;
    }
}

// out[k] += x[k] · P_(k mod 4) for k in [k, n), the lanes P advanced by s4 after every four:
// (pr·s4r − pi·s4i, pi·s4r + pr·s4i), the AVX2 loop's scale4.
void accumulate_rotator_portable(float* o, const float* x, float* lanes, float s4r, float s4i, int k, int n)
{
    for (; k < n; k += 4) {
        const int m = n - k < 4 ? n - k : 4;
        for (int j = 0; j < m; ++j) {
            const float pr = lanes[2 * j], pi = lanes[2 * j + 1];
            const float xr = x[2 * (k + j)], xi = x[2 * (k + j) + 1];
            o[2 * (k + j)] += xr * pr - xi * pi;
            o[2 * (k + j) + 1] += xi * pr + xr * pi;
        }
        for (int j = 0; j < 4; ++j) {
            const float pr = lanes[2 * j], pi = lanes[2 * j + 1];
            lanes[2 * j] = pr * s4r - pi * s4i;
            lanes[2 * j + 1] = pi * s4r + pr * s4i;
        }
    }
}

// y[k] = (x[k] ·) Σ_l c_l d_l[k] for k in [k, n); x only when TimesX. The sum is kept as
// four partial sums, Σ dr·cr, Σ di·cr, Σ dr·ci, Σ −di·ci (rows in order), combined at the
// end: what the AVX2 loop computes lane by lane (two products and two sums per row).
template <bool TimesX>
void row_sum_portable(float* y, const float* x, const float* d, int stride, const gr_complex* c, int rows, int k,
                      int n)
{
    for (; k < n; ++k) {
        float ar = 0.0f, ai = 0.0f, br = 0.0f, bi = 0.0f;
        for (int l = 0; l < rows; ++l) {
            const float* dl = d + 2 * (static_cast<long>(l) * stride + k);
            const float cr = c[l].real(), ci = c[l].imag();
            ar += dl[0] * cr;
            ai += dl[1] * cr;
            br += dl[0] * ci;
            bi += dl[1] * -ci;
        }
        const float hr = ar + bi, hi = ai + br;
        if (TimesX) {
            const float xr = x[2 * k], xi = x[2 * k + 1];
            y[2 * k] = xr * hr - xi * hi;
            y[2 * k + 1] = xi * hr + xr * hi;
        } else {
            y[2 * k] = hr;
            y[2 * k + 1] = hi;
        }
    }
}

// add_horner's portable loop from k: acc = c_P, acc = acc·u + c_p down to p = 0, then h += e·acc
// (Apply = false, out = h) or, for apply_horner, out = x·(h + e·acc) (h = 0 when null): the
// same operations as add_horner followed by multiply.
template <bool Apply>
void horner_portable(float* out, const float* x, const float* h, const float* e, const float* u2, const gr_complex* c,
                     int order, int k, int k1)
{
    for (; k < k1; ++k) {
        const float u = order > 0 ? u2[2 * k] : 0.0f; // P = 0: no u to read
        float ar = c[order].real(), ai = c[order].imag();
        for (int p = order - 1; p >= 0; --p) {
            ar = ar * u + c[p].real();
            ai = ai * u + c[p].imag();
        }
        const float er = e[2 * k], ei = e[2 * k + 1];
        const float tr = er * ar - ei * ai, ti = ei * ar + er * ai;
        if (!Apply) {
            out[2 * k] += tr;
            out[2 * k + 1] += ti;
            continue;
        }
        const float hr = (h ? h[2 * k] : 0.0f) + tr, hi = (h ? h[2 * k + 1] : 0.0f) + ti;
        const float xr = x[2 * k], xi = x[2 * k + 1];
        out[2 * k] = xr * hr - xi * hi;
        out[2 * k + 1] = xi * hr + xr * hi;
    }
}

void multiply_portable(float* y, const float* x, const float* h, int k, int n)
{
    for (; k < n; ++k) {
        const float xr = x[2 * k], xi = x[2 * k + 1], hr = h[2 * k], hi = h[2 * k + 1];
        y[2 * k] = xr * hr - xi * hi;
        y[2 * k + 1] = xi * hr + xr * hi;
    }
}

#ifdef SEMS_KERNELS_AVX2
// c·v for four complex v and a scalar c given as (cr, cr, ...) and (−ci, ci, ...):
// (vr·cr + vi·(−ci), vi·cr + vr·ci), the portable loop's products and sums.
__attribute__((target("avx2"))) inline __m256 scale4(__m256 v, __m256 c_re, __m256 c_im_signed)
{
    const __m256 swapped = _mm256_permute_ps(v, 0xB1); // (vi, vr)
    return _mm256_add_ps(_mm256_mul_ps(v, c_re), _mm256_mul_ps(swapped, c_im_signed));
}

// x·p for four complex x, p: (xr·pr − xi·pi, xi·pr + xr·pi).
__attribute__((target("avx2"))) inline __m256 product4(__m256 x, __m256 p)
{
    const __m256 p_re = _mm256_moveldup_ps(p);
    const __m256 p_im = _mm256_movehdup_ps(p);
    const __m256 x_swapped = _mm256_permute_ps(x, 0xB1);
    return _mm256_addsub_ps(_mm256_mul_ps(x, p_re), _mm256_mul_ps(x_swapped, p_im));
}

__attribute__((target("avx2"))) void
accumulate_rotated_avx2(float* o, const float* x, const float* d, float cr, float ci, int n)
{
    const __m256 c_re = _mm256_set1_ps(cr);
    const __m256 c_im = _mm256_setr_ps(-ci, ci, -ci, ci, -ci, ci, -ci, ci);
    int k = 0;
    for (; k + 4 <= n; k += 4) {
        const __m256 p = scale4(_mm256_loadu_ps(d + 2 * k), c_re, c_im);
        const __m256 r = product4(_mm256_loadu_ps(x + 2 * k), p);
        _mm256_storeu_ps(o + 2 * k, _mm256_add_ps(_mm256_loadu_ps(o + 2 * k), r));
    }
    _mm256_zeroupper();
    accumulate_rotated_portable(o, x, d, cr, ci, k, n);
}

__attribute__((target("avx2"))) void
accumulate_rotator_avx2(float* o, const float* x, float* lanes, float s4r, float s4i, int n)
{
    const __m256 c_re = _mm256_set1_ps(s4r);
    const __m256 c_im = _mm256_setr_ps(-s4i, s4i, -s4i, s4i, -s4i, s4i, -s4i, s4i);
    __m256 p = _mm256_loadu_ps(lanes);
    int k = 0;
    for (; k + 4 <= n; k += 4) {
        const __m256 r = product4(_mm256_loadu_ps(x + 2 * k), p);
        _mm256_storeu_ps(o + 2 * k, _mm256_add_ps(_mm256_loadu_ps(o + 2 * k), r));
        p = scale4(p, c_re, c_im);
    }
    _mm256_storeu_ps(lanes, p);
    _mm256_zeroupper();
    accumulate_rotator_portable(o, x, lanes, s4r, s4i, k, n);
}

template <bool TimesX>
__attribute__((target("avx2"))) void
row_sum_avx2(float* y, const float* x, const float* d, int stride, const gr_complex* c, int rows, int n)
{
    const __m256 negate_odd = _mm256_setr_ps(0.0f, -0.0f, 0.0f, -0.0f, 0.0f, -0.0f, 0.0f, -0.0f);
    int k = 0;
    for (; k + 4 <= n; k += 4) {
        // a = Σ v·(cr, cr), b = Σ v·(ci, −ci); h = a + swap(b), as the portable loop.
        __m256 a = _mm256_setzero_ps(), b = _mm256_setzero_ps();
        for (int l = 0; l < rows; ++l) {
            const __m256 cc = _mm256_castpd_ps(_mm256_broadcast_sd(reinterpret_cast<const double*>(c + l)));
            const __m256 v = _mm256_loadu_ps(d + 2 * (static_cast<long>(l) * stride + k));
            a = _mm256_add_ps(a, _mm256_mul_ps(v, _mm256_moveldup_ps(cc)));
            b = _mm256_add_ps(b, _mm256_mul_ps(v, _mm256_xor_ps(_mm256_movehdup_ps(cc), negate_odd)));
        }
        const __m256 h = _mm256_add_ps(a, _mm256_permute_ps(b, 0xB1));
        _mm256_storeu_ps(y + 2 * k, TimesX ? product4(_mm256_loadu_ps(x + 2 * k), h) : h);
    }
    _mm256_zeroupper();
    row_sum_portable<TimesX>(y, x, d, stride, c, rows, k, n);
}

// Four subcarriers' e·acc = t, stored: h += t (add_horner, out = h) or out = x·(h + t)
// (apply_horner, h = 0 when null), the portable loop's operations.
template <bool Apply>
__attribute__((target("avx2"), always_inline)) inline void
store_horner(float* out, const float* x, const float* h, int j, __m256 t)
{
    if (Apply) {
        const __m256 row = _mm256_add_ps(h ? _mm256_loadu_ps(h + j) : _mm256_setzero_ps(), t);
        _mm256_storeu_ps(out + j, product4(_mm256_loadu_ps(x + j), row));
    } else {
        _mm256_storeu_ps(out + j, _mm256_add_ps(_mm256_loadu_ps(out + j), t));
    }
}

// V vectors of four subcarriers from k: V independent Horner chains, so the loop is bound by
// throughput rather than by the latency of one chain's multiply-then-add.
template <int V, bool Apply>
__attribute__((target("avx2"), always_inline)) inline void horner_chunk(
    float* out, const float* x, const float* h, const float* e, const float* u2, const double* cd, int order, int k)
{
    __m256 acc[V];
    const __m256 top = _mm256_castpd_ps(_mm256_broadcast_sd(cd + order));
    for (int v = 0; v < V; ++v)
        acc[v] = top;
    for (int p = order - 1; p >= 0; --p) {
        const __m256 c = _mm256_castpd_ps(_mm256_broadcast_sd(cd + p));
        for (int v = 0; v < V; ++v)
            acc[v] = _mm256_add_ps(_mm256_mul_ps(acc[v], _mm256_loadu_ps(u2 + 2 * (k + 4 * v))), c);
    }
    for (int v = 0; v < V; ++v) {
        const int j = 2 * (k + 4 * v);
        store_horner<Apply>(out, x, h, j, product4(_mm256_loadu_ps(e + j), acc[v]));
    }
}

template <bool Apply>
__attribute__((target("avx2"))) void horner_avx2(float* out, const float* x, const float* h, const float* e,
                                                 const float* u2, const gr_complex* c, int order, int k0, int k1)
{
    const double* cd = reinterpret_cast<const double*>(c);
    int k = k0;
    if (order == 0) { // P = 0: t = e·c_0, no u to read
        for (; k + 4 <= k1; k += 4)
            store_horner<Apply>(out, x, h, 2 * k,
                                product4(_mm256_loadu_ps(e + 2 * k), _mm256_castpd_ps(_mm256_broadcast_sd(cd))));
    } else {
        for (; k + 32 <= k1; k += 32)
            horner_chunk<8, Apply>(out, x, h, e, u2, cd, order, k);
        for (; k + 4 <= k1; k += 4)
            horner_chunk<1, Apply>(out, x, h, e, u2, cd, order, k);
    }
    _mm256_zeroupper();
    horner_portable<Apply>(out, x, h, e, u2, c, order, k, k1);
}

__attribute__((target("avx2"))) void multiply_avx2(float* y, const float* x, const float* h, int n)
{
    int k = 0;
    for (; k + 4 <= n; k += 4)
        _mm256_storeu_ps(y + 2 * k, product4(_mm256_loadu_ps(x + 2 * k), _mm256_loadu_ps(h + 2 * k)));
    _mm256_zeroupper();
    multiply_portable(y, x, h, k, n);
}
#endif

kernel_choice choice = kernel_choice::fastest;

// Without AVX2, a row with VOLK's kernels (which have SSE and NEON versions): h = d_0·c_0,
// then h += d_l·c_l (a scaled copy and an add per path), then y = x·h. Scratch per thread,
// allocation-free once grown.
void row_sum_volk(gr_complex* y, const gr_complex* x, const gr_complex* d, int stride, const gr_complex* c, int rows,
                  int n)
{
    thread_local std::vector<gr_complex> h, scaled;
    h.resize(static_cast<size_t>(n));
    scaled.resize(static_cast<size_t>(n));
    const auto len = static_cast<unsigned>(n);
    if (rows == 0)
        std::fill(h.begin(), h.end(), gr_complex(0.0f, 0.0f));
    else
        volk_32fc_s32fc_multiply_32fc(h.data(), d, c[0], len);
    for (int l = 1; l < rows; ++l) {
        volk_32fc_s32fc_multiply_32fc(scaled.data(), d + static_cast<long>(l) * stride, c[l], len);
        volk_32f_x2_add_32f(reinterpret_cast<float*>(h.data()),
                            reinterpret_cast<const float*>(h.data()),
                            reinterpret_cast<const float*>(scaled.data()),
                            2 * len);
    }
    if (x)
        volk_32fc_x2_multiply_32fc(y, x, h.data(), len);
    else
        std::copy(h.begin(), h.end(), y);
}

} // namespace

void complex_kernels_choose(kernel_choice c) { choice = c; }

bool complex_kernels_use_avx2()
{
#ifdef SEMS_KERNELS_AVX2
    static const bool avx2 = __builtin_cpu_supports("avx2");
    return avx2 && choice == kernel_choice::fastest;
#else
    return false;
#endif
}

void accumulate_rotated(gr_complex* out, const gr_complex* x, const gr_complex* d, gr_complex c, int n)
{
    auto* o = reinterpret_cast<float*>(out);
    const auto* xs = reinterpret_cast<const float*>(x);
    const auto* ds = reinterpret_cast<const float*>(d);
#ifdef SEMS_KERNELS_AVX2
    if (complex_kernels_use_avx2())
        return accumulate_rotated_avx2(o, xs, ds, c.real(), c.imag(), n);
#endif
    accumulate_rotated_portable(o, xs, ds, c.real(), c.imag(), 0, n);
}

void accumulate_rotator(gr_complex* out, const gr_complex* x, int n, std::complex<double> p, std::complex<double> s)
{
    float lanes[8];
    std::complex<double> v = p;
    for (int j = 0; j < 4; ++j, v = mul(v, s)) {
        lanes[2 * j] = static_cast<float>(v.real());
        lanes[2 * j + 1] = static_cast<float>(v.imag());
    }
    const std::complex<double> s2 = mul(s, s), s4 = mul(s2, s2);
    const float s4r = static_cast<float>(s4.real()), s4i = static_cast<float>(s4.imag());
    auto* o = reinterpret_cast<float*>(out);
    const auto* xs = reinterpret_cast<const float*>(x);
#ifdef SEMS_KERNELS_AVX2
    if (complex_kernels_use_avx2())
        return accumulate_rotator_avx2(o, xs, lanes, s4r, s4i, n);
#endif
    accumulate_rotator_portable(o, xs, lanes, s4r, s4i, 0, n);
}

void apply_row_sum(gr_complex* y, const gr_complex* x, const gr_complex* d, int stride, const gr_complex* c,
                   int n_rows, int n)
{
    auto* ys = reinterpret_cast<float*>(y);
    const auto* xs = reinterpret_cast<const float*>(x);
    const auto* ds = reinterpret_cast<const float*>(d);
#ifdef SEMS_KERNELS_AVX2
    if (complex_kernels_use_avx2())
        return row_sum_avx2<true>(ys, xs, ds, stride, c, n_rows, n);
#endif
    if (choice == kernel_choice::portable)
        return row_sum_portable<true>(ys, xs, ds, stride, c, n_rows, 0, n);
    row_sum_volk(y, x, d, stride, c, n_rows, n);
}

void row_sum(gr_complex* h, const gr_complex* d, int stride, const gr_complex* c, int n_rows, int n)
{
    auto* hs = reinterpret_cast<float*>(h);
    const auto* ds = reinterpret_cast<const float*>(d);
#ifdef SEMS_KERNELS_AVX2
    if (complex_kernels_use_avx2())
        return row_sum_avx2<false>(hs, nullptr, ds, stride, c, n_rows, n);
#endif
    if (choice == kernel_choice::portable)
        return row_sum_portable<false>(hs, nullptr, ds, stride, c, n_rows, 0, n);
    row_sum_volk(h, nullptr, d, stride, c, n_rows, n);
}

void add_horner(gr_complex* h, const gr_complex* e, const float* u2, const gr_complex* c, int order, int k0, int k1)
{
    auto* hs = reinterpret_cast<float*>(h);
    const auto* es = reinterpret_cast<const float*>(e);
#ifdef SEMS_KERNELS_AVX2
    if (complex_kernels_use_avx2())
        return horner_avx2<false>(hs, nullptr, hs, es, u2, c, order, k0, k1);
#endif
    horner_portable<false>(hs, nullptr, hs, es, u2, c, order, k0, k1);
}

void apply_horner(gr_complex* y, const gr_complex* x, const gr_complex* h, const gr_complex* e, const float* u2,
                  const gr_complex* c, int order, int n)
{
    auto* ys = reinterpret_cast<float*>(y);
    const auto* xs = reinterpret_cast<const float*>(x);
    const auto* hs = reinterpret_cast<const float*>(h);
    const auto* es = reinterpret_cast<const float*>(e);
#ifdef SEMS_KERNELS_AVX2
    if (complex_kernels_use_avx2())
        return horner_avx2<true>(ys, xs, hs, es, u2, c, order, 0, n);
#endif
    horner_portable<true>(ys, xs, hs, es, u2, c, order, 0, n);
}

void multiply(gr_complex* y, const gr_complex* x, const gr_complex* h, int n)
{
    auto* ys = reinterpret_cast<float*>(y);
    const auto* xs = reinterpret_cast<const float*>(x);
    const auto* hs = reinterpret_cast<const float*>(h);
#ifdef SEMS_KERNELS_AVX2
    if (complex_kernels_use_avx2())
        return multiply_avx2(ys, xs, hs, n);
#endif
    multiply_portable(ys, xs, hs, 0, n);
}

} // namespace detail
} // namespace sems
} // namespace gr
