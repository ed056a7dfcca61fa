// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: vectorised CN(0, 1) generator (see gaussian_generator.h).
 *
 * The loops below are written for the compiler's auto-vectoriser: fixed trip counts
 * over the lanes, no branches (selects only), no calls. GCC 12 at -O3 vectorises them
 * (checked with -fopt-info-vec). target_clones builds AVX-512 and AVX2 versions next
 * to the baseline (SSE2) one and picks one at load time; the file is compiled with
 * -ffp-contract=off (no FMA contraction), so every version gives the same bits.
 */
#include "core/kernels/gaussian_generator.h"
#include "core/kernels/cpu_dispatch.h"
#include <algorithm>
#include <cmath>

namespace gr {
namespace sems {

namespace {

uint64_t splitmix64(uint64_t& x)
{
    uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

// One xoshiro128+ output of a lane's state, and the state advanced (inlined into the lane
// loop below, which the compiler vectorises across lanes).
inline __attribute__((always_inline)) uint32_t
xoshiro128plus(uint32_t& s0, uint32_t& s1, uint32_t& s2, uint32_t& s3)
{
    const uint32_t out = s0 + s3;
    const uint32_t t = s1 << 9;
    s2 ^= s0;
    s3 ^= s1;
    s1 ^= s2;
    s0 ^= s3;
    s2 ^= t;
    s3 = (s3 << 11) | (s3 >> 21);
    return out;
}

constexpr int L = gaussian_generator::lanes;
constexpr int steps = gaussian_generator::block / L;

// One block: `steps` rounds of L lanes, each lane two xoshiro128+ outputs -> one CN(0, 1).
SEMS_TARGET_CLONES("avx512f", "avx2", "default")
void generate_block(uint32_t* __restrict s0,
                    uint32_t* __restrict s1,
                    uint32_t* __restrict s2,
                    uint32_t* __restrict s3,
                    float* __restrict out)
{
    for (int step = 0; step < steps; ++step) {
        float* __restrict o = out + 2 * step * L;
        for (int k = 0; k < L; ++k) {
            // xoshiro128+, twice: a for the radius, b for the angle (upper bits used).
            const uint32_t a = xoshiro128plus(s0[k], s1[k], s2[k], s3[k]);
            const uint32_t b = xoshiro128plus(s0[k], s1[k], s2[k], s3[k]);

            // u in [2^-32, 1]: 31 random bits, never 0.
            const float u = static_cast<float>(static_cast<int32_t>(a >> 1)) * 0x1p-31f + 0x1p-32f;
            // ln u (Cephes logf): u = m·2^e, m in [sqrt(1/2), sqrt(2)).
            const int32_t bits = __builtin_bit_cast(int32_t, u);
            const int32_t e0 = ((bits >> 23) & 0xff) - 126;
            const float m = __builtin_bit_cast(float, (bits & 0x007fffff) | 0x3f000000); // [0.5, 1)
            const int32_t lt = m < 0.707106781186547524f ? 1 : 0;
            const float x = lt ? m + m - 1.0f : m - 1.0f;
            const float fe = static_cast<float>(e0 - lt);
            const float z = x * x;
            float p = 7.0376836292e-2f;
            p = p * x - 1.1514610310e-1f;
            p = p * x + 1.1676998740e-1f;
            p = p * x - 1.2420140846e-1f;
            p = p * x + 1.4249322787e-1f;
            p = p * x - 1.6668057665e-1f;
            p = p * x + 2.0000714765e-1f;
            p = p * x - 2.4999993993e-1f;
            p = p * x + 3.3333331174e-1f;
            float y = p * x * z;
            y += -2.12194440e-4f * fe;
            y += -0.5f * z;
            const float ln_u = x + y + 0.693359375f * fe;
            const float r = std::sqrt(std::max(-ln_u, 0.0f)); // |z|² ~ Exp(1)

            // Angle: quadrant q from the top 2 bits, offset in [-π/4, π/4) from the next 24.
            const uint32_t q = b >> 30;
            const float f = static_cast<float>(static_cast<int32_t>((b >> 6) & 0xffffff)) * 0x1p-24f;
            const float w = (f - 0.5f) * 1.57079632679489662f;
            const float w2 = w * w;
            const float sn = ((-1.9515295891e-4f * w2 + 8.3321608736e-3f) * w2 - 1.6666654611e-1f) * w2 * w + w;
            const float cs =
                ((2.443315711809948e-5f * w2 - 1.388731625493765e-3f) * w2 + 4.166664568298827e-2f) * w2 * w2 -
                0.5f * w2 + 1.0f;
            // Rotate (cs, sn) by q·π/2: swap on odd q, then flip signs.
            const bool odd = (q & 1u) != 0;
            const float re0 = odd ? sn : cs;
            const float im0 = odd ? cs : sn;
            const uint32_t re_sign = ((q ^ (q >> 1)) & 1u) << 31;
            const uint32_t im_sign = (q >> 1) << 31;
            const float re = __builtin_bit_cast(float, __builtin_bit_cast(uint32_t, re0) ^ re_sign);
            const float im = __builtin_bit_cast(float, __builtin_bit_cast(uint32_t, im0) ^ im_sign);
            o[2 * k] = r * re;
            o[2 * k + 1] = r * im;
        }
    }
}

} // namespace

gaussian_generator::gaussian_generator(uint64_t seed) { reseed(seed); }

void gaussian_generator::reseed(uint64_t seed)
{
    uint64_t x = seed;
    for (int k = 0; k < L; ++k) {
        const uint64_t a = splitmix64(x), b = splitmix64(x);
        d_s0[k] = static_cast<uint32_t>(a);
        d_s1[k] = static_cast<uint32_t>(a >> 32);
        d_s2[k] = static_cast<uint32_t>(b);
        d_s3[k] = static_cast<uint32_t>(b >> 32);
        if ((d_s0[k] | d_s1[k] | d_s2[k] | d_s3[k]) == 0)
            d_s0[k] = 1; // xoshiro's one forbidden state
    }
    d_pos = block;
}

void gaussian_generator::refill()
{
    generate_block(d_s0, d_s1, d_s2, d_s3, d_buf);
    d_pos = 0;
}

void gaussian_generator::add(gr_complex* y, size_t count, float sigma)
{
    float* __restrict yf = reinterpret_cast<float*>(y);
    while (count > 0) {
        if (d_pos == block)
            refill();
        const size_t n = std::min(count, static_cast<size_t>(block) - d_pos);
        const float* __restrict g = d_buf + 2 * d_pos;
        for (size_t i = 0; i < 2 * n; ++i)
            yf[i] += sigma * g[i];
        yf += 2 * n;
        count -= n;
        d_pos += n;
    }
}

void gaussian_generator::fill(gr_complex* out, size_t count)
{
    float* __restrict of = reinterpret_cast<float*>(out);
    while (count > 0) {
        if (d_pos == block)
            refill();
        const size_t n = std::min(count, static_cast<size_t>(block) - d_pos);
        std::copy(d_buf + 2 * d_pos, d_buf + 2 * (d_pos + n), of);
        of += 2 * n;
        count -= n;
        d_pos += n;
    }
}

} // namespace sems
} // namespace gr
