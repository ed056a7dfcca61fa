// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the emulator's noise generator (internal to libgnuradio-sems).
 *
 * Circular complex Gaussians CN(0, 1) in single precision, generated a block at a
 * time in SIMD lanes:
 *  - uniforms: 16 independent xoshiro128+ streams (32-bit state words, adds, xors and
 *    shifts only, so they vectorise on SSE2 and AVX2 alike), each lane seeded through
 *    splitmix64 from the seed and the lane;
 *  - Gaussians: Box–Muller in its complex form, z = sqrt(-ln u1) · e^{jφ}, so one pair
 *    of uniforms gives one complex sample (|z|² of CN(0, 1) is Exp(1)); ln, sin and cos
 *    are fixed float polynomials (Cephes), so the output is the same bits on every
 *    machine and instruction set (SSE2, AVX2 and AVX-512 versions; no FMA contraction).
 *
 * Determinism: samples are drawn from a block buffer, so the n-th sample after
 * reseed(seed) is the same whatever the sizes of the calls that consumed the first n.
 * Nothing is allocated after construction.
 *
 * Limits of the approximation (documented, not hidden): u1 has 31 random bits and is
 * never 0, so |z| <= sqrt(32 ln 2) = 4.71, i.e. each rail is cut beyond 6.66 σ of its
 * N(0, 1/2) (probability of the complex sample reaching that radius: e^-22.2 = 2.3e-10);
 * the angle is uniform on 2^26 levels; ln/sin/cos are accurate to ~1e-7 relative.
 */
#ifndef INCLUDED_SEMS_LIB_CORE_GAUSSIAN_GENERATOR_H
#define INCLUDED_SEMS_LIB_CORE_GAUSSIAN_GENERATOR_H

#include <gnuradio/gr_complex.h>
#include <cstddef>
#include <cstdint>

namespace gr {
namespace sems {

class gaussian_generator
{
public:
    static constexpr int lanes = 16;                   // independent uniform streams
    static constexpr int block = 16 * lanes;           // complex samples per refill

    explicit gaussian_generator(uint64_t seed = 0);
    void reseed(uint64_t seed);

    /*!
     * \brief y[i] += sigma · z_i with z_i ~ CN(0, 1) (E|z|² = 1), for i < count.
     * \param y the samples to add noise to
     * \param count how many complex samples
     * \param sigma the noise's standard deviation sqrt(E|n|²), finite and >= 0
     */
    void add(gr_complex* y, size_t count, float sigma);

    /*! \brief out[i] = z_i ~ CN(0, 1), the same stream add() consumes. */
    void fill(gr_complex* out, size_t count);

private:
    void refill();

    alignas(64) uint32_t d_s0[lanes];
    alignas(64) uint32_t d_s1[lanes];
    alignas(64) uint32_t d_s2[lanes];
    alignas(64) uint32_t d_s3[lanes];
    alignas(64) float d_buf[2 * block]; // interleaved re, im
    size_t d_pos = block;               // next unread sample; block = empty
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_GAUSSIAN_GENERATOR_H */
