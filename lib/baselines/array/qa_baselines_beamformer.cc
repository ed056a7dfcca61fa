// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: an array's pilots combined into one antenna's (array_beamformer.h) — the combined
 * plane wave against the ULA's array factor in closed form, white noise divided by the
 * elements, the strongest of two targets kept, one stream passed through, bad input. */
#include <gnuradio/sems/baselines/array_beamformer.h>
#include <gnuradio/sems/core/array/steering.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <string>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace beamformer_qa { // named: the unity build joins this file with qa_baselines_angle.cc

using cd = std::complex<double>;
const double lambda = 0.1;
const int K = 8;
const double d = lambda / 2;

// A plane wave from (φ0, θ0) on a centred ULA along y, written from the geometry alone: element
// k at y_k = (k − (K−1)/2)·d gains the carrier phase 2π y_k cos θ0 sin φ0 / λ; snapshot t
// carries s_t. Element-major, as the pilot extractor gives it.
std::vector<gr_complex> plane_wave(double az0, double el0, const std::vector<cd>& s)
{
    const size_t l = s.size();
    std::vector<gr_complex> y(size_t(K) * l);
    for (int k = 0; k < K; ++k) {
        const double yk = (k - (K - 1) / 2.0) * d;
        const cd phasor = std::polar(1.0, 2.0 * M_PI * yk * std::cos(el0) * std::sin(az0) / lambda);
        for (size_t t = 0; t < l; ++t)
            y[size_t(k) * l + t] = gr_complex(phasor * s[t]);
    }
    return y;
}

// The centred ULA's array factor towards φ for a wave from (φ0, θ0): (1/K) Σ_k e^{jψ y_k/d} =
// sin(Kψ/2) / (K sin(ψ/2)), ψ = 2π d (cos θ0 sin φ0 − sin φ)/λ (real: the array is centred).
double array_factor(double az0, double el0, double az)
{
    const double psi = 2.0 * M_PI * d * (std::cos(el0) * std::sin(az0) - std::sin(az)) / lambda;
    return std::fabs(psi) < 1e-12 ? 1.0 : std::sin(K * psi / 2.0) / (K * std::sin(psi / 2.0));
}

std::vector<cd> random_snapshots(int l, std::mt19937_64& g)
{
    std::uniform_real_distribution<double> u(0.0, 2.0 * M_PI);
    std::vector<cd> s(static_cast<size_t>(l));
    for (auto& x : s)
        x = std::polar(1.0, u(g));
    return s;
}

class qa_baselines_beamformer : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_baselines_beamformer);
    CPPUNIT_TEST(a_plane_wave_combines_to_the_array_factor);
    CPPUNIT_TEST(combining_divides_white_noise_by_the_elements);
    CPPUNIT_TEST(the_combiner_steers_at_the_strongest_target);
    CPPUNIT_TEST(one_stream_passes_through);
    CPPUNIT_TEST(bad_input_is_refused_by_name);
    CPPUNIT_TEST_SUITE_END();

public:
    void a_plane_wave_combines_to_the_array_factor()
    {
        const auto a = array_geometry::ula(K, d);
        std::mt19937_64 g(3);
        const auto s = random_snapshots(16, g);
        std::vector<gr_complex> z(s.size());
        int checked = 0;
        for (double az0 : { -1.2, -0.4, 0.0, 0.3, 0.9 })
            for (double el0 : { 0.0, 0.35 })
                for (double az : { -1.0, -0.2, 0.0, 0.1, 0.6, az0 }) {
                    const auto y = plane_wave(az0, el0, s);
                    beamform_pilots(a, az, 0.0, lambda, y.data(), int(s.size()), z.data());
                    const double af = array_factor(az0, el0, az);
                    for (size_t t = 0; t < s.size(); ++t) {
                        const cd want = af * s[t];
                        CPPUNIT_ASSERT_MESSAGE("az0 " + std::to_string(az0) + " el0 " + std::to_string(el0) + " az " +
                                                   std::to_string(az) + " t " + std::to_string(t),
                                               std::abs(cd(z[t]) - want) < 1e-6);
                    }
                    ++checked;
                }
        CPPUNIT_ASSERT_EQUAL(60, checked);
        // Towards the wave's own direction (elevation included) it keeps the amplitude: a URA.
        const auto ura = array_geometry::ura(4, 2, d, d);
        const auto steer = steering_vector(ura, 0.4, -0.3, lambda);
        std::vector<gr_complex> y(steer.size() * s.size());
        for (size_t k = 0; k < steer.size(); ++k)
            for (size_t t = 0; t < s.size(); ++t)
                y[k * s.size() + t] = gr_complex(steer[k] * s[t]);
        beamform_pilots(ura, 0.4, -0.3, lambda, y.data(), int(s.size()), z.data());
        for (size_t t = 0; t < s.size(); ++t)
            CPPUNIT_ASSERT(std::abs(cd(z[t]) - s[t]) < 1e-6);
    }

    void combining_divides_white_noise_by_the_elements()
    {
        // CN(0, σ²) per element and snapshot, combined towards any direction: CN(0, σ²/K). The
        // sample variance of n = 40 000 snapshots has a relative spread of 1/√n = 0.5 %; 3 %
        // is six of them, while σ²/K' for K' = 7 or 9 differs by 11 % or more.
        const auto a = array_geometry::ula(K, d);
        const int n = 40000;
        const double sigma2 = 2.0;
        std::mt19937_64 g(11);
        std::normal_distribution<double> normal(0.0, std::sqrt(sigma2 / 2.0));
        std::vector<gr_complex> w(size_t(K) * n);
        for (auto& x : w)
            x = gr_complex(float(normal(g)), float(normal(g)));
        std::vector<gr_complex> z(static_cast<size_t>(n));
        for (double az : { 0.0, 0.7 }) {
            beamform_pilots(a, az, 0.0, lambda, w.data(), n, z.data());
            double power = 0.0;
            for (const auto& x : z)
                power += std::norm(x);
            const double ratio = power / n / (sigma2 / K);
            CPPUNIT_ASSERT_MESSAGE("noise power over σ²/K = " + std::to_string(ratio), std::fabs(ratio - 1.0) < 0.03);
        }
    }

    void the_combiner_steers_at_the_strongest_target()
    {
        // Two incoherent targets, at −0.4 rad (amplitude 1) and 0.5 rad (0.5), 32 pilots at 20 dB:
        // the combiner beamforms towards the first, whose pilots come through with its
        // amplitude, the second's attenuated by the array factor between them.
        const auto a = array_geometry::ula(K, d);
        const array_beamformer bf(a, lambda);
        CPPUNIT_ASSERT_EQUAL(K, bf.n_elements());
        std::mt19937_64 g(5);
        std::normal_distribution<double> normal(0.0, std::sqrt(0.01 / 2.0));
        const int l = 32;
        double worst = 0.0, worst_residual = 0.0;
        for (int trial = 0; trial < 50; ++trial) {
            const auto s1 = random_snapshots(l, g), s2 = random_snapshots(l, g);
            auto y = plane_wave(-0.4, 0.0, s1);
            const auto y2 = plane_wave(0.5, 0.0, s2);
            for (size_t i = 0; i < y.size(); ++i)
                y[i] += 0.5f * y2[i] + gr_complex(float(normal(g)), float(normal(g)));
            std::vector<gr_complex> z(static_cast<size_t>(l));
            const double az = bf.combine(y.data(), l, z.data());
            worst = std::max(worst, std::fabs(az + 0.4));
            // What is left besides the first target: the second through the array factor and
            // noise of variance 0.01/K; its power stays within a few times that.
            double residual = 0.0;
            const double leak = 0.5 * std::fabs(array_factor(0.5, 0.0, az));
            for (int t = 0; t < l; ++t)
                residual += std::norm(cd(z[size_t(t)]) - s1[size_t(t)] * array_factor(-0.4, 0.0, az));
            worst_residual = std::max(worst_residual, residual / l / (leak * leak + 0.01 / K));
        }
        CPPUNIT_ASSERT_MESSAGE("azimuth error " + std::to_string(worst), worst < 0.02);
        CPPUNIT_ASSERT_MESSAGE("residual power over leak + noise " + std::to_string(worst_residual), worst_residual < 4.0);
    }

    void one_stream_passes_through()
    {
        const array_beamformer bf(array_geometry(), lambda);
        CPPUNIT_ASSERT_EQUAL(1, bf.n_elements());
        std::vector<gr_complex> y{ { 1.5f, -2.0f }, { 0.25f, 3.0f }, { -1.0f, 0.0f } }, z(3);
        CPPUNIT_ASSERT(std::isnan(bf.combine(y.data(), 3, z.data())));
        for (size_t t = 0; t < y.size(); ++t)
            CPPUNIT_ASSERT(z[t] == y[t]);
    }

    void bad_input_is_refused_by_name()
    {
        const auto a = array_geometry::ula(K, d);
        assert_error([&] { array_beamformer(a, 0.0); }, "wavelength_m", "> 0");
        const array_beamformer bf(a, lambda);
        std::vector<gr_complex> y(size_t(K) * 4, gr_complex(1.0f, 0.0f)), z(4);
        assert_error([&] { bf.combine(y.data(), 0, z.data()); }, "snapshots", "got 0");
        y[5] = gr_complex(NAN, 0.0f);
        assert_error([&] { bf.combine(y.data(), 4, z.data()); }, "observation 5", "not finite");
        const array_beamformer one(array_geometry(), lambda);
        assert_error([&] { one.combine(y.data() + 4, 4, z.data()); }, "pilot 1", "not finite");
        assert_error([&] { beamform_pilots(a, 0.0, 0.0, lambda, y.data(), 0, z.data()); }, "snapshots", "got 0");
        // Cosine elements see nothing behind the array: no direction to beamform towards.
        const auto backed = array_geometry::ula(K, d, element_pattern::cosine);
        assert_error([&] { beamform_pilots(backed, M_PI, 0.0, lambda, y.data(), 4, z.data()); }, "azimuth 3.14", "is zero");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_baselines_beamformer);

} // namespace beamformer_qa
