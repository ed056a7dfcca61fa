// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the scatterer models' loops over many symbols at once (internal to libgnuradio-sems).
 *
 * The scatterer models evaluate a phase per scatterer and per symbol; one loop over a frame's
 * symbols, which the compiler vectorises (AVX2 picked at load time), costs a fraction of a
 * libm call per argument. Double precision throughout: the argument is reduced by
 * Cody–Waite with π/2 in three parts (exact for |x| ≤ 1e6), then Cephes' polynomials on
 * [−π/4, π/4]; the result is within 2 ulp of the true value (qa_complex_kernels checks it
 * against libm). Beyond |x| > 1e6 the few such arguments go through libm. Compiled without
 * FMA contraction, so the vector and portable versions give the same bits.
 */
#ifndef INCLUDED_SEMS_LIB_CORE_VECTOR_MATH_H
#define INCLUDED_SEMS_LIB_CORE_VECTOR_MATH_H

#include <cstddef>

namespace gr {
namespace sems {
namespace detail {

/* s[i] = sin(x[i]), c[i] = cos(x[i]) for i < n. s and c may not overlap x or each other. */
void sincos_batch(const double* x, double* s, double* c, size_t n);

/* out[i] = 2π·frac(f·t[i]) + φ + offset: an angle turning at f Hz (whole turns dropped in
 * double first), for i < n. */
void turning_angles(const double* t, double rate_hz, double phase_rad, double offset_rad, double* out, size_t n);

/* A point scatterer's moments (scatterer_moments.h) at n instants, added to re, im:
 * re[p·n + i] + j·im[p·n + i] += a[i]·e^{-jκ r[i]}·(−j r[i])^p/p! for p ≤ order, given
 * cs[i] + j·sn[i] = e^{jκ r[i]}. x and y are scratch of n doubles each. */
void add_point_moments(const double* r, const double* a, const double* cs, const double* sn, size_t n, int order,
                       double* re, double* im, double* x, double* y);

/* The line integrals E_p(z_i) = ∫_0^1 s^p e^{-j z_i s} ds for p ≤ order at n arguments, by the
 * upward recurrence E_0 = (1 − e^{-jz})/(jz), E_p = (e^{-jz} − p E_{p−1})/(−jz), given
 * cs[i] − j·sn[i] = e^{-j z_i}: re[p·n + i] + j·im[p·n + i]. The recurrence is stable where
 * |z_i| ≥ max(2, order) (each step scales the error by p/|z| ≤ 1); the values of the other
 * arguments are meaningless (not even finite at z = 0): the caller replaces them
 * (line_integrals(), scatterer_moments.h). w is scratch of n doubles. */
void upward_line_integrals(const double* z, const double* cs, const double* sn, size_t n, int order, double* re,
                           double* im, double* w);

/* A line's moments (scatterer_moments.h) at n instants, added to out_re, out_im: for q ≤ order,
 * L_q = a[i]·(−j e[i])^q/q!·E_q with E_q = e_re[q·n + i] + j·e_im[q·n + i] (from 0 to e, r0 = 0);
 * with pair, the line and its mirror image (−e): 2 Re L_q to out_re, nothing to out_im.
 * mag is scratch of n doubles. */
void add_line_moments(const double* e_re, const double* e_im, const double* e, const double* a, size_t n, int order,
                      bool pair, double* out_re, double* out_im, double* mag);

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_VECTOR_MATH_H */
