// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: orthogonal matching pursuit on the delay decoder's grid (internal, torch-free).
 *
 * The delay decoder's residual maps (delay_decoder.h): a fixed feature extractor, no
 * gradient. Per frame, y is the first slow-time projection of the pilots (M complex
 * values, zero on subcarriers without pilots), `support` marks the subcarriers with pilots, and the dictionary is D[m, q] =
 * cos[m, q] - j sin[m, q] (the steering of delay τ_q, dict_cos / dict_sin of the decoder).
 * Round 1 picks the q of the largest |Σ_m y[m] conj(D[m, q])|; every round refits all the
 * atoms picked so far (restricted to the frame's pilot subcarriers) by least squares,
 * writes the map |Σ_m r[m] conj(D[m, q])| · scale of the residual r, and picks the next q
 * from it (a Cholesky solve of the L x L Gram matrix). On a CPU with AVX2 and FMA the
 * correlations run with fused multiply-adds (maps within ~1e-16 relative of the exact loop's,
 * as float almost always the same bits); elsewhere, or when a test chooses it, the exact loop. Written as plain loops over the pilots'
 * subcarriers: as LibTorch operators
 * (complex double, a batched solve per round) it was ~50 small calls per batch, most of
 * the small decoder's time.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_GRID_OMP_H
#define INCLUDED_SEMS_LIB_LEARNING_GRID_OMP_H

#include <cstdint>

namespace gr {
namespace sems {
namespace nn {

/*!
 * \param yr, yi    frames x m: real and imaginary parts of y (row-major)
 * \param support   frames x m: nonzero on the subcarriers that carry pilots (y is zero elsewhere)
 * \param frames    number of frames
 * \param m         subcarriers
 * \param dict_cos  m x q, row-major
 * \param dict_sin  m x q, row-major
 * \param q         grid delays
 * \param rounds    maps per frame (atoms picked), 1..8
 * \param scale     factor of every map value
 * \param maps      out: frames x rounds x q (row-major)
 */
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
                   float* maps);

/*! Whether this CPU can run the fused (AVX2 + FMA) correlation. */
bool grid_omp_fused_available();

/*!
 * Chooses the fused correlation (the default where available) or the exact loop; for the
 * tests (every thread follows the last choice). Returns whether the fused one now runs.
 */
bool grid_omp_use_fused(bool fused);

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_GRID_OMP_H */
