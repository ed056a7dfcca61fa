// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the project's random number generator (internal).
 *
 * xoshiro256** seeded through splitmix64: fast, small state, and the same stream on
 * every platform and standard library (std::normal_distribution is not), so a seed
 * names the same frames everywhere. Gaussians come from Boost.Random's ziggurat
 * (a fixed algorithm, unlike the standard library's): ~10x cheaper than Box–Muller,
 * which matters because noise is the emulator's per-sample cost.
 */
#ifndef INCLUDED_SEMS_LIB_CORE_RNG_H
#define INCLUDED_SEMS_LIB_CORE_RNG_H

#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>

namespace gr {
namespace sems {

class rng
{
public:
    explicit rng(uint64_t seed = 0) { reseed(seed); }

    void reseed(uint64_t seed)
    {
        uint64_t x = seed;
        for (auto& s : d_s)
            s = splitmix64(x);
    }

    // UniformRandomBitGenerator, so Boost.Random distributions can draw from it.
    using result_type = uint64_t;
    static constexpr result_type min() { return 0; }
    static constexpr result_type max() { return std::numeric_limits<uint64_t>::max(); }
    result_type operator()() { return next_u64(); }

    uint64_t next_u64()
    {
        const uint64_t result = rotl(d_s[1] * 5, 7) * 9;
        const uint64_t t = d_s[1] << 17;
        d_s[2] ^= d_s[0];
        d_s[3] ^= d_s[1];
        d_s[1] ^= d_s[2];
        d_s[0] ^= d_s[3];
        d_s[2] ^= t;
        d_s[3] = rotl(d_s[3], 45);
        return result;
    }

    // Uniform in [0, 1), 53 bits.
    double uniform() { return (next_u64() >> 11) * 0x1.0p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    // Uniform integer in [0, n), n > 0 (Lemire's multiply-shift; bias < 2^-64·n).
    uint64_t below(uint64_t n) { return static_cast<uint64_t>((static_cast<unsigned __int128>(next_u64()) * n) >> 64); }

    // Standard normal, N(0, 1).
    double normal() { return d_normal(*this); }

    // Circular complex Gaussian with E|z|² = variance.
    std::complex<double> complex_normal(double variance)
    {
        const double s = std::sqrt(0.5 * variance);
        const double re = normal();
        return { s * re, s * normal() };
    }

    // splitmix64: advances x by the golden ratio and returns its mixed value (the seeding
    // step; also how a seed is derived from several numbers, e.g. a seed and a track index).
    static uint64_t splitmix64(uint64_t& x)
    {
        uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }

private:
    static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    uint64_t d_s[4];
    boost::random::normal_distribution<double> d_normal; // stateless ziggurat
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_RNG_H */
