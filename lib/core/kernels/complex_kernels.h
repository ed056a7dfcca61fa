// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the emulators' fused complex loops (internal to the libraries).
 *
 * Each kernel is one pass over interleaved complex floats that VOLK would do in two or
 * three (a product, a scaling, an accumulation). An AVX2 version is picked at run time
 * when the CPU has it; it evaluates the same products and sums in the same order as the
 * portable version, without FMA, so both give the same bits.
 *
 * Without AVX2 (older x86, ARM) the time-domain loops run their portable versions (plain
 * loops the compiler vectorises), and the frequency-domain rows run VOLK's kernels, two
 * passes per path (VOLK has SSE and NEON versions). A 3-path row of 64 subcarriers on this
 * project's machine: AVX2 65 ns, VOLK's passes 111 ns, the portable row (a scalar loop) 345
 * ns. The VOLK rows agree with the others to float rounding, not bit for bit.
 */
#ifndef INCLUDED_SEMS_LIB_CORE_COMPLEX_KERNELS_H
#define INCLUDED_SEMS_LIB_CORE_COMPLEX_KERNELS_H

#include <gnuradio/gr_complex.h>
#include <complex>

namespace gr {
namespace sems {
namespace detail {

/*!
 * out[k] += x[k] · (c · d[k]), k < n: a path's per-sample phasor d (times the symbol's
 * phase c) applied to its delayed samples and added to the output. The arrays may not
 * overlap; operands are finite.
 */
void accumulate_rotated(gr_complex* out, const gr_complex* x, const gr_complex* d, gr_complex c, int n);

/*!
 * out[k] += x[k] · p · s^k, k < n: a linear phase (a rotator) applied to x and added to out.
 * p·s^j for j < 4 and s⁴ are formed in double; from there four lanes advance by s⁴ in
 * float, as VOLK's rotator advances by s (relative phase error ~n·6e-8). x and out may not
 * overlap.
 */
void accumulate_rotator(gr_complex* out, const gr_complex* x, int n, std::complex<double> p, std::complex<double> s);

/*!
 * y[k] = x[k] · Σ_l c[l] · d[l·stride + k], k < n, l < n_rows: a symbol of the
 * frequency-domain channel, its row built and applied in one pass (the sum in order
 * l = 0, 1, ...). y may alias x; the rows may not overlap y.
 */
void apply_row_sum(gr_complex* y, const gr_complex* x, const gr_complex* d, int stride, const gr_complex* c,
                   int n_rows, int n);

/*! h[k] = Σ_l c[l] · d[l·stride + k]: apply_row_sum's row alone (the same bits). */
void row_sum(gr_complex* h, const gr_complex* d, int stride, const gr_complex* c, int n_rows, int n);

/*!
 * h[k] += e[k] · Σ_{p ≤ order} u_k^p · c[p] for k0 ≤ k < k1, the polynomial by Horner's rule
 * (u_k real, given twice: u2[2k] = u2[2k + 1] = u_k; not read when order = 0): one sub-band of a scatterer body's
 * path in a row of the frequency-domain channel (e its delay phasor, c its terms at the symbol).
 */
void add_horner(gr_complex* h, const gr_complex* e, const float* u2, const gr_complex* c, int order, int k0, int k1);

/*!
 * y[k] = x[k] · (h[k] + e[k] · Σ_{p ≤ order} u_k^p · c[p]) for k < n (h = 0 when null): add_horner
 * on a whole row followed by multiply, in one pass and with the same bits (the last
 * scatterer body of a symbol whose body has one sub-band). y may alias x; not h, e or u2.
 */
void apply_horner(gr_complex* y,
                  const gr_complex* x,
                  const gr_complex* h,
                  const gr_complex* e,
                  const float* u2,
                  const gr_complex* c,
                  int order,
                  int n);

/*! y[k] = x[k] · h[k], k < n (y may alias x or h). */
void multiply(gr_complex* y, const gr_complex* x, const gr_complex* h, int n);

/*! Which versions run; for the tests (not thread-safe). */
enum class kernel_choice {
    fastest,      ///< AVX2 when the CPU has it, else what a CPU without AVX2 runs (the default)
    portable,     ///< the portable loops everywhere: the AVX2 versions' bit-exact twins
    without_avx2, ///< what a CPU without AVX2 runs: the portable loops, VOLK for the rows
};

/*! Selects the versions that run (tests compare them). */
void complex_kernels_choose(kernel_choice choice);

/*! True when the AVX2 versions run (this CPU has AVX2 and kernel_choice::fastest). */
bool complex_kernels_use_avx2();

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_COMPLEX_KERNELS_H */
