/* gr-sems: the project's random number generator (internal).
 *
 * xoshiro256** seeded through splitmix64: fast, small state, and the same stream on
 * every platform and standard library (std::normal_distribution is not), so a seed
 * names the same frames everywhere. Normals come in pairs from Box–Muller, which
 * suits complex Gaussian noise exactly.
 */
#ifndef INCLUDED_SEMS_RNG_H
#define INCLUDED_SEMS_RNG_H

#include <cmath>
#include <complex>
#include <cstdint>

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

    // Circular complex Gaussian with E|z|² = variance (Box–Muller: one pair per call).
    std::complex<double> complex_normal(double variance)
    {
        const double u1 = 1.0 - uniform(); // (0, 1]: log stays finite
        const double u2 = uniform();
        const double r = std::sqrt(-variance * std::log(u1));
        return { r * std::cos(2.0 * M_PI * u2), r * std::sin(2.0 * M_PI * u2) };
    }

private:
    static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    static uint64_t splitmix64(uint64_t& x)
    {
        uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    uint64_t d_s[4];
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_RNG_H */
