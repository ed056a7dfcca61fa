// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the angle references — the CRB against the ULA's closed form, beamforming against
 * the CRB (it is the one-target maximum-likelihood estimate), MUSIC with smoothing on two
 * coherent targets 1.5 beamwidths apart, Capon on targets inside a beamwidth, and bad settings. */
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/core/array/steering.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {

using cd = std::complex<double>;
const double lambda = 0.1;
const int K = 8;
const double d = lambda / 2;
// The half-power beamwidth of a broadside ULA: 0.886 λ/(K d) rad.
const double beamwidth = 0.886 * lambda / (K * d);

// L snapshots of targets at `az` with amplitudes `amp[i]·s_t` (one shared snapshot sequence: the
// targets are coherent when there are several), plus CN(0, σ²) noise; element-major.
std::vector<gr_complex> observe(const array_geometry& a, const std::vector<double>& az, const std::vector<cd>& amp,
                                int l, double sigma2, std::mt19937_64& g)
{
    std::normal_distribution<double> n(0.0, 1.0);
    std::uniform_real_distribution<double> u(0.0, 2.0 * M_PI);
    const int k = a.n_receive();
    std::vector<gr_complex> y(size_t(k) * l);
    std::vector<cd> s(static_cast<size_t>(l));
    for (auto& x : s)
        x = std::polar(1.0, u(g));
    for (size_t i = 0; i < az.size(); ++i) {
        const auto st = steering_vector(a, az[i], 0.0, lambda);
        for (int e = 0; e < k; ++e)
            for (int t = 0; t < l; ++t)
                y[size_t(e) * l + t] += gr_complex(amp[i] * st[size_t(e)] * s[size_t(t)]);
    }
    const double sd = std::sqrt(sigma2 / 2.0);
    for (auto& v : y)
        v += gr_complex(sd * n(g), sd * n(g));
    return y;
}

// The same with independent snapshot phases per target (incoherent: different delays or
// Dopplers).
std::vector<gr_complex> observe_incoherent(const array_geometry& a, const std::vector<double>& az, int l, double sigma2,
                                           std::mt19937_64& g)
{
    std::vector<gr_complex> y(size_t(a.n_receive()) * l);
    for (double x : az) {
        const auto one = observe(a, { x }, { 1.0 }, l, 0.0, g);
        for (size_t i = 0; i < y.size(); ++i)
            y[i] += one[i];
    }
    const auto noise = observe(a, {}, {}, l, sigma2, g);
    for (size_t i = 0; i < y.size(); ++i)
        y[i] += noise[i];
    return y;
}

} // namespace

class qa_baselines_angle : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_baselines_angle);
    CPPUNIT_TEST(crb_of_a_centred_ula_is_the_closed_form);
    CPPUNIT_TEST(beamforming_reaches_the_crb_for_one_target);
    CPPUNIT_TEST(smoothed_music_resolves_two_coherent_targets);
    CPPUNIT_TEST(capon_resolves_incoherent_targets_inside_a_beamwidth);
    CPPUNIT_TEST(bad_settings_are_refused_by_name);
    CPPUNIT_TEST_SUITE_END();

public:
    void crb_of_a_centred_ula_is_the_closed_form()
    {
        const auto a = array_geometry::ula(K, d);
        for (double az : { 0.0, 0.4, -1.0 })
            for (double el : { 0.0, 0.3 }) {
                const double e = 250.0, w = 2 * M_PI * d * std::cos(az) * std::cos(el) / lambda;
                const double want = 6.0 / (e * w * w * K * (K * K - 1));
                CPPUNIT_ASSERT_DOUBLES_EQUAL(want, angle_crb_rad2(a, az, el, lambda, e), 1e-9 * want);
            }
        // A transmit element moves every virtual element alike: the same bound.
        const auto shifted = array_geometry::from_positions(a.receive(), { { 0.0, 0.3, 0.0 } });
        CPPUNIT_ASSERT_DOUBLES_EQUAL(angle_crb_rad2(a, 0.2, 0, lambda, 10), angle_crb_rad2(shifted, 0.2, 0, lambda, 10),
                                     1e-12);
    }

    void beamforming_reaches_the_crb_for_one_target()
    {
        // K = 8 at λ/2, 32 snapshots of unit amplitude: E = 32/σ². The maximum-likelihood estimate
        // is efficient above its threshold: its MSE over 300 trials within 25 % of the mean CRB.
        const auto a = array_geometry::ula(K, d);
        const beamforming_angle_estimator bf(a, 0.0, lambda);
        std::mt19937_64 g(7);
        std::uniform_real_distribution<double> where(-0.8, 0.8);
        for (double snr_db : { 0.0, 20.0 }) {
            const double sigma2 = std::pow(10.0, -snr_db / 10.0);
            double mse = 0.0, crb = 0.0;
            const int trials = 300, l = 32;
            for (int i = 0; i < trials; ++i) {
                const double az = where(g);
                const auto y = observe(a, { az }, { 1.0 }, l, sigma2, g);
                const double err = bf.estimate(y.data(), l)[0] - az;
                mse += err * err / trials;
                crb += angle_crb_rad2(a, az, 0.0, lambda, l / sigma2) / trials;
            }
            CPPUNIT_ASSERT_MESSAGE("at " + std::to_string(snr_db) + " dB MSE/CRB = " + std::to_string(mse / crb),
                                   mse / crb < 1.25 && mse / crb > 0.75);
        }
    }

    void smoothed_music_resolves_two_coherent_targets()
    {
        // Two targets of equal power with the same snapshot phases (the same delay and Doppler),
        // 1.5 beamwidths apart about broadside, at 20 dB: forward–backward smoothing over
        // subarrays of 6 finds both within a quarter beamwidth in >= 95 % of 200 trials; plain
        // MUSIC, whose signal subspace collapses to one dimension, falls short of that bar.
        const auto a = array_geometry::ula(K, d);
        const music_angle_estimator smoothed(a, 0.0, lambda, 2, 6), plain(a, 0.0, lambda, 2);
        std::mt19937_64 g(11);
        std::uniform_real_distribution<double> u(0.0, 2.0 * M_PI);
        const double half = 0.75 * beamwidth;
        int hit_smoothed = 0, hit_plain = 0;
        const int trials = 200, l = 32;
        auto both = [&](std::vector<double> est) {
            if (est.size() != 2)
                return false;
            std::sort(est.begin(), est.end());
            return std::fabs(est[0] + half) < 0.25 * beamwidth && std::fabs(est[1] - half) < 0.25 * beamwidth;
        };
        for (int i = 0; i < trials; ++i) {
            const auto y = observe(a, { -half, half }, { 1.0, std::polar(1.0, u(g)) }, l, 0.01, g);
            hit_smoothed += both(smoothed.estimate(y.data(), l));
            hit_plain += both(plain.estimate(y.data(), l));
        }
        CPPUNIT_ASSERT_MESSAGE("smoothed MUSIC found both in " + std::to_string(hit_smoothed) + " of 200",
                               hit_smoothed >= 190);
        CPPUNIT_ASSERT_MESSAGE("plain MUSIC found both in " + std::to_string(hit_plain) + " of 200", hit_plain < 190);
    }

    void capon_resolves_incoherent_targets_inside_a_beamwidth()
    {
        // One target at 20 dB, 32 snapshots: Capon's MSE near the CRB (within 1.5x over 300
        // trials; it is not the ML estimate, but one target leaves it little to adapt to).
        // Two incoherent targets of equal power 0.7 beamwidths apart at 20 dB, 64 snapshots:
        // Capon's adaptive beam finds both within a quarter beamwidth in >= 95 % of 200 trials,
        // where beamforming's fixed beam merges them (far fewer hits). Two coherent ones cancel
        // in Capon unless smoothed, as in MUSIC.
        const auto a = array_geometry::ula(K, d);
        const capon_angle_estimator capon(a, 0.0, lambda);
        const beamforming_angle_estimator bf(a, 0.0, lambda);
        std::mt19937_64 g(13);
        std::uniform_real_distribution<double> where(-0.8, 0.8);
        double mse = 0.0, crb = 0.0;
        for (int i = 0; i < 300; ++i) {
            const double az = where(g);
            const auto y = observe(a, { az }, { 1.0 }, 32, 0.01, g);
            const double err = capon.estimate(y.data(), 32)[0] - az;
            mse += err * err / 300;
            crb += angle_crb_rad2(a, az, 0.0, lambda, 32 / 0.01) / 300;
        }
        CPPUNIT_ASSERT_MESSAGE("Capon MSE/CRB = " + std::to_string(mse / crb), mse / crb < 1.5);
        const double half = 0.35 * beamwidth;
        auto both = [&](std::vector<double> est) {
            if (est.size() != 2)
                return false;
            std::sort(est.begin(), est.end());
            return std::fabs(est[0] + half) < 0.25 * beamwidth && std::fabs(est[1] - half) < 0.25 * beamwidth;
        };
        int hit_capon = 0, hit_bf = 0, hit_coherent = 0, hit_smoothed = 0;
        const capon_angle_estimator smoothed(a, 0.0, lambda, 1e-3, 6);
        std::uniform_real_distribution<double> u(0.0, 2.0 * M_PI);
        for (int i = 0; i < 200; ++i) {
            const auto y = observe_incoherent(a, { -half, half }, 64, 0.01, g);
            hit_capon += both(capon.estimate(y.data(), 64, 2));
            hit_bf += both(bf.estimate(y.data(), 64, 2));
            const double wide = 0.75 * beamwidth; // coherent: 1.5 beamwidths apart, as for MUSIC
            const auto c = observe(a, { -wide, wide }, { 1.0, std::polar(1.0, u(g)) }, 64, 0.01, g);
            auto both_wide = [&](std::vector<double> est) {
                if (est.size() != 2)
                    return false;
                std::sort(est.begin(), est.end());
                return std::fabs(est[0] + wide) < 0.25 * beamwidth && std::fabs(est[1] - wide) < 0.25 * beamwidth;
            };
            hit_coherent += both_wide(capon.estimate(c.data(), 64, 2));
            hit_smoothed += both_wide(smoothed.estimate(c.data(), 64, 2));
        }
        std::printf("Capon MSE/CRB %.3f; two incoherent at 0.7 BW: Capon %d, beamforming %d of 200; two coherent at "
                    "1.5 BW: Capon %d, smoothed %d of 200\n",
                    mse / crb, hit_capon, hit_bf, hit_coherent, hit_smoothed);
        CPPUNIT_ASSERT_MESSAGE("Capon found both in " + std::to_string(hit_capon) + " of 200", hit_capon >= 190);
        CPPUNIT_ASSERT_MESSAGE("beamforming found both in " + std::to_string(hit_bf) + " of 200", hit_bf < 100);
        CPPUNIT_ASSERT_MESSAGE("smoothed Capon found both coherent in " + std::to_string(hit_smoothed) + " of 200",
                               hit_smoothed >= 190);
    }

    void bad_settings_are_refused_by_name()
    {
        const auto a = array_geometry::ula(K, d);
        assert_error([&] { angle_crb_rad2(a, 0, 0, lambda, 0.0); }, "energy_to_noise", "> 0");
        assert_error([&] { beamforming_angle_estimator(a, 0, 0.0); }, "wavelength_m", "> 0");
        assert_error([&] { beamforming_angle_estimator(a, 0, lambda, { 1.0, -1.0, 64 }); }, "search interval", "min < max");
        assert_error([&] { beamforming_angle_estimator(a, 0, lambda, { -1.0, 1.0, 4 }); }, "search.grid", "got 4");
        assert_error([&] { music_angle_estimator(a, 0, lambda, 6, 6); }, "n_targets", "[1, 5]");
        assert_error([&] { music_angle_estimator(a, 0, lambda, 1, 9); }, "subarray", "[1, 8]");
        assert_error([&] { music_angle_estimator(array_geometry::ura(4, 2, d, d), 0, lambda, 1, 3); }, "needs a ULA");
        assert_error([&] { capon_angle_estimator(a, 0, lambda, -1.0); }, "loading", ">= 0");
        assert_error([&] { capon_angle_estimator(a, 0, lambda, 1e-3, 9); }, "subarray", "[1, 8]");
        const capon_angle_estimator unloaded(a, 0, lambda, 0.0);
        std::vector<gr_complex> few(size_t(K) * 2, gr_complex(1.0f, 0.0f));
        assert_error([&] { unloaded.estimate(few.data(), 2); }, "singular", "2 snapshots");
        const beamforming_angle_estimator bf(a, 0, lambda);
        std::vector<gr_complex> y(size_t(K) * 4, gr_complex(1.0f, 0.0f));
        y[9] = gr_complex(NAN, 0.0f);
        assert_error([&] { bf.estimate(y.data(), 4); }, "observation 9", "not finite");
        assert_error([&] { bf.estimate(y.data(), 0); }, "snapshots", "got 0");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_baselines_angle);
