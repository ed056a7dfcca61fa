// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: sine and cosine of many doubles at once (see vector_math.h). */
#include "core/kernels/vector_math.h"
#include "core/kernels/cpu_dispatch.h"
#include <cmath>
#include <cstdint>

namespace gr {
namespace sems {
namespace detail {

namespace {

constexpr double reduction_limit = 1e6; // |x| up to here: j = round(2x/π) < 2^20, j·(π/2 part) exact
constexpr double two_over_pi = 0.636619772367581343076;
constexpr double pio2_1 = 1.57079632673412561417e+00;  // π/2, first 33 bits
constexpr double pio2_2 = 6.07710050630396597660e-11;  // next 33 bits
constexpr double pio2_3 = 2.02226624879595063154e-21;  // π/2 − pio2_1 − pio2_2
constexpr double shifter = 0x1.8p52;                   // x + shifter rounds x to an integer in the low bits

// The loop the compiler vectorises: no calls, no branches (selects only), fixed operations.
// Returns whether an argument lies beyond the reduction's limit (or is NaN).
SEMS_TARGET_CLONES("avx2", "default")
bool sincos_reduced(const double* __restrict x, double* __restrict s, double* __restrict c, size_t n)
{
    uint64_t far = 0;
    for (size_t i = 0; i < n; ++i) {
        const double xi = x[i];
        far |= !(std::fabs(xi) <= reduction_limit) ? 1u : 0u;
        const double k = xi * two_over_pi + shifter;
        const uint64_t q = __builtin_bit_cast(uint64_t, k) & 3u; // quadrant j mod 4
        const double j = k - shifter;
        const double r = ((xi - j * pio2_1) - j * pio2_2) - j * pio2_3; // in [−π/4, π/4]
        const double z = r * r;
        const double sp = ((((1.58962301576546568060e-10 * z - 2.50507477628578072866e-8) * z +
                             2.75573136213857245213e-6) * z - 1.98412698295895385996e-4) * z +
                           8.33333333332211858878e-3) * z - 1.66666666666666307295e-1;
        const double cp = ((((-1.13585365213876817300e-11 * z + 2.08757008419747316778e-9) * z -
                             2.75573141792967388112e-7) * z + 2.48015872888517045348e-5) * z -
                           1.38888888888730564116e-3) * z + 4.16666666666665929218e-2;
        const double sn = r + r * z * sp;
        const double cs = (1.0 - 0.5 * z) + z * z * cp;
        // Rotate by j·π/2: odd quadrants swap sine and cosine, then the signs.
        const bool odd = (q & 1u) != 0;
        const double s0 = odd ? cs : sn;
        const double c0 = odd ? sn : cs;
        s[i] = (q & 2u) != 0 ? -s0 : s0;
        c[i] = ((q + 1u) & 2u) != 0 ? -c0 : c0;
    }
    return far != 0;
}

SEMS_TARGET_CLONES("avx2", "default")
void turning(const double* __restrict t, double rate_hz, double phase_rad, double offset_rad, double* __restrict out,
             size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        const double turns = rate_hz * t[i]; // whole turns dropped in double before the angle
        out[i] = 2.0 * M_PI * (turns - std::floor(turns)) + phase_rad + offset_rad;
    }
}

SEMS_TARGET_CLONES("avx2", "default")
void point_moments(const double* __restrict r,
                   const double* __restrict a,
                   const double* __restrict cs,
                   const double* __restrict sn,
                   size_t n,
                   int order,
                   double* __restrict re,
                   double* __restrict im,
                   double* __restrict x,
                   double* __restrict y)
{
    for (size_t i = 0; i < n; ++i) {
        x[i] = a[i] * cs[i];
        y[i] = -a[i] * sn[i];
    }
    // a e^{-jκr} (−jr)^p / p! by recurrence over p: (x + jy)(−jr)/(p+1) = (y r − j x r)/(p+1)
    for (int p = 0; p <= order; ++p) {
        double* __restrict rp = re + size_t(p) * n;
        double* __restrict ip = im + size_t(p) * n;
        const double inv = 1.0 / double(p + 1);
        for (size_t i = 0; i < n; ++i) {
            rp[i] += x[i];
            ip[i] += y[i];
            const double f = r[i] * inv;
            const double nx = y[i] * f;
            y[i] = -x[i] * f;
            x[i] = nx;
        }
    }
}

SEMS_TARGET_CLONES("avx2", "default")
void upward(const double* __restrict z, const double* __restrict cs, const double* __restrict sn, size_t n, int order,
            double* __restrict re, double* __restrict im, double* __restrict w)
{
    // Dividing by −jz is a product by j/z: (x + jy)·j/z = (−y + jx)/z, over the instants at once.
    for (size_t i = 0; i < n; ++i) {
        w[i] = 1.0 / z[i];
        re[i] = sn[i] * w[i]; // x + jy = e^{-jz} − 1 = (cs − 1) − j sn
        im[i] = (cs[i] - 1.0) * w[i];
    }
    for (int p = 1; p <= order; ++p) {
        const double* __restrict pr = re + size_t(p - 1) * n;
        const double* __restrict pi = im + size_t(p - 1) * n;
        double* __restrict qr = re + size_t(p) * n;
        double* __restrict qi = im + size_t(p) * n;
        for (size_t i = 0; i < n; ++i) {
            const double x = cs[i] - double(p) * pr[i], y = -sn[i] - double(p) * pi[i];
            qr[i] = -y * w[i];
            qi[i] = x * w[i];
        }
    }
}

SEMS_TARGET_CLONES("avx2", "default")
void line_moments(const double* __restrict e_re, const double* __restrict e_im, const double* __restrict e,
                  const double* __restrict a, size_t n, int order, bool pair, double* __restrict out_re,
                  double* __restrict out_im, double* __restrict mag)
{
    // a (−je)^q / q! = (−j)^q · mag_q, mag_q = a e^q / q! real: a scaling and a quarter turn of E_q.
    for (size_t i = 0; i < n; ++i)
        mag[i] = a[i];
    for (int q = 0; q <= order; ++q) {
        const double* __restrict er = e_re + size_t(q) * n;
        const double* __restrict ei = e_im + size_t(q) * n;
        double* __restrict o_re = out_re + size_t(q) * n;
        double* __restrict o_im = out_im + size_t(q) * n;
        // (−j)^q = 1, −j, −1, j: L = (±vr, ±vi) or (±vi, ∓vr) with v = mag·E
        const bool swap = (q & 1) != 0;
        const double s_re = (q & 3) == 0 || (q & 3) == 1 ? 1.0 : -1.0; // sign of L's real part
        const double s_im = (q & 3) == 0 || (q & 3) == 3 ? 1.0 : -1.0; // sign of L's imaginary part
        const double inv = 1.0 / double(q + 1);
        for (size_t i = 0; i < n; ++i) {
            const double vr = mag[i] * er[i], vi = mag[i] * ei[i];
            const double lr = s_re * (swap ? vi : vr), li = s_im * (swap ? vr : vi);
            if (pair) {
                o_re[i] += 2.0 * lr;
            } else {
                o_re[i] += lr;
                o_im[i] += li;
            }
            mag[i] *= e[i] * inv;
        }
    }
}

} // namespace

void upward_line_integrals(const double* z, const double* cs, const double* sn, size_t n, int order, double* re,
                           double* im, double* w)
{
    upward(z, cs, sn, n, order, re, im, w);
}

void add_line_moments(const double* e_re, const double* e_im, const double* e, const double* a, size_t n, int order,
                      bool pair, double* out_re, double* out_im, double* mag)
{
    line_moments(e_re, e_im, e, a, n, order, pair, out_re, out_im, mag);
}

void add_point_moments(const double* r, const double* a, const double* cs, const double* sn, size_t n, int order,
                       double* re, double* im, double* x, double* y)
{
    point_moments(r, a, cs, sn, n, order, re, im, x, y);
}

void turning_angles(const double* t, double rate_hz, double phase_rad, double offset_rad, double* out, size_t n)
{
    turning(t, rate_hz, phase_rad, offset_rad, out, n);
}

void sincos_batch(const double* x, double* s, double* c, size_t n)
{
    if (!sincos_reduced(x, s, c, n))
        return;
    for (size_t i = 0; i < n; ++i)
        if (!(std::fabs(x[i]) <= reduction_limit)) { // far arguments (and NaN): libm
            s[i] = std::sin(x[i]);
            c[i] = std::cos(x[i]);
        }
}

} // namespace detail
} // namespace sems
} // namespace gr
