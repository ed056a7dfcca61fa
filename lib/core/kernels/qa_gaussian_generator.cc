// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the vectorised CN(0, 1) generator against the Gaussian's moments and tails,
 * and its determinism (same seed, same samples, whatever the call sizes).
 *
 * Tolerances are 5 standard errors of each estimate at the sample size used
 * (n = 4·10^6 complex samples), so a correct generator fails a check with probability
 * ~6e-7 per check, and the tests are deterministic anyway (fixed seeds). The standard
 * errors, for z = x + jy ~ CN(0, 1), x, y ~ N(0, 1/2):
 *   mean of x:       sqrt(1/(2n))          = 3.5e-4  -> tol 1.8e-3
 *   E x², E y²:      sqrt(Var x² / n) = sqrt(0.5/n) = 3.5e-4 -> tol 1.8e-3
 *   E|z|² (Exp(1)):  sqrt(1/n)             = 5.0e-4  -> tol 2.5e-3
 *   E|z|⁴ = 2:       sqrt((E|z|⁸ - 4)/n) = sqrt(20/n) = 2.2e-3 -> tol 1.1e-2
 *   E xy, lag corr.: sqrt(1/(4n)), sqrt(1/n) -> tol 1.3e-3, 2.5e-3
 *   tails P(|x| > kσ) = 2Q(k) over the 2n rails: Poisson count, tol 5·sqrt(expected)
 *   histograms (64 bins): χ² with 63 dof, mean 63, sd 11.2 -> below 63 + 5·11.2 = 119
 */
#include "core/kernels/gaussian_generator.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <vector>

using namespace gr::sems;

namespace {

constexpr size_t n_samples = 4000000;

std::vector<gr_complex> draw(uint64_t seed, size_t n)
{
    gaussian_generator g(seed);
    std::vector<gr_complex> z(n);
    g.fill(z.data(), n);
    return z;
}

double two_q(double k) { return std::erfc(k / std::sqrt(2.0)); } // P(|N(0,1)| > k)

double chi_square(const std::vector<double>& counts, double expected)
{
    double c = 0;
    for (double v : counts)
        c += (v - expected) * (v - expected) / expected;
    return c;
}

} // namespace

class qa_gaussian_generator : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_gaussian_generator);
    CPPUNIT_TEST(moments);
    CPPUNIT_TEST(tails);
    CPPUNIT_TEST(radius_and_angle_distributions);
    CPPUNIT_TEST(samples_are_uncorrelated);
    CPPUNIT_TEST(same_seed_same_samples_whatever_the_call_sizes);
    CPPUNIT_TEST(add_scales_and_adds);
    CPPUNIT_TEST(stream_is_pinned);
    CPPUNIT_TEST(channel_noise_is_independent_of_call_sizes);
    CPPUNIT_TEST_SUITE_END();

public:
    void moments()
    {
        const auto z = draw(11, n_samples);
        double mx = 0, my = 0, xx = 0, yy = 0, xy = 0, p2 = 0, p4 = 0;
        for (const auto& v : z) {
            const double x = v.real(), y = v.imag(), p = x * x + y * y;
            CPPUNIT_ASSERT(std::isfinite(x) && std::isfinite(y));
            mx += x;
            my += y;
            xx += x * x;
            yy += y * y;
            xy += x * y;
            p2 += p;
            p4 += p * p;
        }
        const double n = double(z.size());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, mx / n, 1.8e-3);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, my / n, 1.8e-3);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.5, xx / n, 1.8e-3);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.5, yy / n, 1.8e-3);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, xy / n, 1.3e-3); // circular: E z² = 0
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, p2 / n, 2.5e-3);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(2.0, p4 / n, 1.1e-2); // E|z|⁴ = 2 for CN(0, 1)
    }

    void tails()
    {
        const auto z = draw(12, n_samples);
        const double sigma = std::sqrt(0.5); // per rail
        for (double k : { 2.0, 3.0, 4.0 }) {
            double count = 0;
            for (const auto& v : z)
                count += (std::fabs(v.real()) > k * sigma) + (std::fabs(v.imag()) > k * sigma);
            const double expected = 2.0 * double(z.size()) * two_q(k); // 4σ: 507 of 8e6 rails
            CPPUNIT_ASSERT_DOUBLES_EQUAL(expected, count, 5.0 * std::sqrt(expected));
        }
        // The documented cut: |z|² <= 32 ln 2 (u1 >= 2^-32), i.e. 6.66σ per rail.
        double max_p = 0;
        for (const auto& v : z)
            max_p = std::max(max_p, double(std::norm(v)));
        CPPUNIT_ASSERT(max_p <= 32.0 * std::log(2.0) * (1.0 + 1e-5));
        CPPUNIT_ASSERT(max_p > 10.0); // the tail is reached (P(|z|² > 10) = 4.5e-5: ~180 samples)
    }

    void radius_and_angle_distributions()
    {
        // exp(-|z|²) is uniform on (0, 1) and arg z uniform on (-π, π]: 64-bin histograms.
        const auto z = draw(13, n_samples);
        std::vector<double> r(64, 0.0), a(64, 0.0);
        for (const auto& v : z) {
            const double u = std::exp(-double(std::norm(v)));
            r[std::min<size_t>(63, size_t(u * 64))] += 1;
            const double t = (std::arg(std::complex<double>(v)) + M_PI) / (2 * M_PI);
            a[std::min<size_t>(63, size_t(t * 64))] += 1;
        }
        const double expected = double(z.size()) / 64;
        CPPUNIT_ASSERT(chi_square(r, expected) < 119.0);
        CPPUNIT_ASSERT(chi_square(a, expected) < 119.0);
    }

    void samples_are_uncorrelated()
    {
        // Neighbours come from different lanes, lag `lanes` from the same lane's next step.
        const auto z = draw(14, n_samples);
        for (size_t lag : { size_t(1), size_t(gaussian_generator::lanes), size_t(gaussian_generator::block) }) {
            std::complex<double> c = 0;
            for (size_t i = lag; i < z.size(); ++i)
                c += std::complex<double>(z[i]) * std::conj(std::complex<double>(z[i - lag]));
            c /= double(z.size() - lag);
            CPPUNIT_ASSERT(std::abs(c) < 2.5e-3 * std::sqrt(2.0)); // |c|: both rails at 5 SE
        }
    }

    void same_seed_same_samples_whatever_the_call_sizes()
    {
        const size_t n = 5000;
        const auto ref = draw(21, n);
        gaussian_generator g(21);
        std::vector<gr_complex> z(n);
        size_t pos = 0;
        for (size_t k = 0; pos < n; ++k) { // call sizes 1, 7, 64, 255, 1000, ...
            const size_t sizes[] = { 1, 7, 64, 255, 1000, 3 };
            const size_t c = std::min(sizes[k % 6], n - pos);
            g.fill(z.data() + pos, c);
            pos += c;
        }
        CPPUNIT_ASSERT(z == ref); // bit-identical
        g.reseed(21);
        std::vector<gr_complex> again(n);
        g.fill(again.data(), n);
        CPPUNIT_ASSERT(again == ref);
        CPPUNIT_ASSERT(draw(22, n) != ref);
    }

    void stream_is_pinned()
    {
        // The same bits on every machine and instruction set (SSE2, AVX2, AVX-512 and an
        // -O0 scalar build all gave this FNV-1a hash): a seed names the same noise everywhere.
        const auto z = draw(7, size_t(1) << 20);
        uint64_t h = 1469598103934665603ULL;
        const auto* p = reinterpret_cast<const unsigned char*>(z.data());
        for (size_t i = 0; i < z.size() * sizeof(gr_complex); ++i) {
            h ^= p[i];
            h *= 1099511628211ULL;
        }
        CPPUNIT_ASSERT_EQUAL(uint64_t(0x7eb2dae1090918f2ULL), h);
    }

    void add_scales_and_adds()
    {
        const size_t n = 1000;
        const auto ref = draw(31, n);
        gaussian_generator g(31);
        std::vector<gr_complex> y(n, gr_complex(1.0f, -2.0f));
        g.add(y.data(), n, 0.25f);
        for (size_t i = 0; i < n; ++i)
            CPPUNIT_ASSERT(y[i] == gr_complex(1.0f, -2.0f) + 0.25f * ref[i]);
    }

    void channel_noise_is_independent_of_call_sizes()
    {
        // What target_channel relies on: add_noise per row gives the frames add_noise on
        // the whole grid gives (same seed), so a flowgraph's work() sizes change nothing.
        const frame_settings fs{};
        const scene sc = scene::fixed({ target_spec{} });
        channel_model a(fs, sc, 5), b(fs, sc, 5);
        const size_t grid = size_t(fs.grid_size()) * 3;
        std::vector<gr_complex> ya(grid, gr_complex(0, 0)), yb(grid, gr_complex(0, 0));
        a.add_noise(ya.data(), grid, 10.0);
        for (size_t i = 0; i < grid; i += fs.n_subcarriers)
            b.add_noise(yb.data() + i, fs.n_subcarriers, 10.0);
        CPPUNIT_ASSERT(ya == yb);
        CPPUNIT_ASSERT_THROW(a.add_noise(ya.data(), 1, -1000.0), std::invalid_argument); // σ beyond float
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_gaussian_generator);
