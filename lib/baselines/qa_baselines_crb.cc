// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the delay CRB — closed form against a numeric inversion of the Fisher
 * matrix, and against a Monte-Carlo of the maximum-likelihood estimator (the fine
 * periodogram with parabolic refinement) at high SNR. */
#include "baselines/qa_baselines_frames.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/baselines/periodogram_delay_estimator.h>
#include <gnuradio/sems/baselines/delay_crb.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using namespace gr::sems;

namespace {

// [F⁻¹]_ττ of the 3 x 3 Fisher matrix of (τ, ν, φ) for |α| = 1, built numerically from
// the derivatives and inverted by cofactors, in seconds². Pilot k's noise is σ²/p_k.
double numeric_crb_tau(const pilot_mask& mask, double sigma2)
{
    double f[3][3] = {};
    const double df = fs.subcarrier_spacing_hz(), t = fs.symbol_interval_s;
    for (int k = 0; k < mask.size(); ++k) {
        const auto& p = mask.positions()[k];
        const double g[3] = { -2.0 * M_PI * df * p.m, 2.0 * M_PI * t * p.n, 1.0 };
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                f[i][j] += 2.0 * mask.power()[k] / sigma2 * g[i] * g[j];
    }
    const double det = f[0][0] * (f[1][1] * f[2][2] - f[1][2] * f[2][1]) -
                       f[0][1] * (f[1][0] * f[2][2] - f[1][2] * f[2][0]) +
                       f[0][2] * (f[1][0] * f[2][1] - f[1][1] * f[2][0]);
    return (f[1][1] * f[2][2] - f[1][2] * f[2][1]) / det;
}

} // namespace

class qa_baselines_crb : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_baselines_crb);
    CPPUNIT_TEST(closed_form_matches_fisher_inverse);
    CPPUNIT_TEST(monte_carlo_of_ml_estimator_meets_the_bound);
    CPPUNIT_TEST(bad_input_is_refused);
    CPPUNIT_TEST(pilot_energies_weigh_the_bound);
    CPPUNIT_TEST_SUITE_END();

public:
    void closed_form_matches_fisher_inverse()
    {
        // A pattern whose subcarrier and symbol are correlated, so the unknown Doppler costs.
        std::vector<pilot_position> pos;
        for (int k = 0; k < 16; ++k)
            pos.push_back({ 2 * k, (4 * k + (k % 3) * 7) % 64 });
        const pilot_mask mask(fs.n_symbols, fs.n_subcarriers, pos);
        const double snr = 13.0, sigma2 = std::pow(10.0, -snr / 10.0);
        const double b2 = fs.bandwidth_hz * fs.bandwidth_hz;
        const double unknown = delay_crb::variance_index(fs, mask, snr, false);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(numeric_crb_tau(mask, sigma2) * b2, unknown, 1e-9 * unknown);
        const double known = delay_crb::variance_index(fs, mask, snr, true);
        CPPUNIT_ASSERT(known < unknown);
        // 1/|α|² scaling, 1/σ² scaling, and the Rayleigh-averaged MAE √(2 var₁).
        CPPUNIT_ASSERT_DOUBLES_EQUAL(unknown / 4.0, delay_crb::variance_index(fs, mask, snr, false, 4.0), 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(unknown / 10.0, delay_crb::variance_index(fs, mask, snr + 10.0, false),
                                     1e-9 * unknown);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(2.0 * unknown), delay_crb::mae_index(fs, mask, snr, false, true), 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(2.0 * unknown / M_PI), delay_crb::mae_index(fs, mask, snr, false, false),
                                     1e-12);
        CPPUNIT_ASSERT_EQUAL(0.0, delay_crb::variance_index(fs, mask, std::numeric_limits<double>::infinity()));
    }

    void monte_carlo_of_ml_estimator_meets_the_bound()
    {
        // Fixed unit gain, known on-grid Doppler (the estimator's one-bin Doppler grid
        // holds it), off-grid delay: at 20 dB per pilot the fine periodogram + parabola
        // is efficient, so its variance should match the Doppler-known bound.
        const auto mask = pilot_mask::random(fs.n_symbols, fs.n_subcarriers, 32, 11);
        const double snr = 20.0, sigma = std::sqrt(std::pow(10.0, -snr / 10.0) / 2.0);
        const double idx = 20.3, nu = 4 * 31.25;
        periodogram_delay_estimator::settings s;
        s.search.oversample = 32;
        s.search.min_index = 18.0;
        s.search.max_index = 23.0;
        s.doppler_oversample = 1;
        periodogram_delay_estimator est(fs, mask, s);
        std::mt19937_64 gen(2024);
        std::normal_distribution<double> nd(0.0, sigma);
        std::uniform_real_distribution<double> ph(0.0, 2.0 * M_PI);
        const int trials = 2000;
        double sum = 0.0, sum2 = 0.0;
        std::vector<gr_complex> obs(mask.size());
        for (int t = 0; t < trials; ++t) {
            const std::complex<double> alpha = std::polar(1.0, ph(gen));
            for (int k = 0; k < mask.size(); ++k) {
                const auto& p = mask.positions()[k];
                const double cyc = -double(p.m) * idx / fs.n_subcarriers + nu * p.n * fs.symbol_interval_s;
                obs[k] = gr_complex(alpha * std::polar(1.0, 2.0 * M_PI * cyc) + std::complex<double>(nd(gen), nd(gen)));
            }
            const double e = est.estimate_index(obs.data()) - idx;
            sum += e;
            sum2 += e * e;
        }
        const double mse = sum2 / trials, bias = sum / trials;
        const double crb = delay_crb::variance_index(fs, mask, snr, true);
        // 2000 trials: the sample MSE is within ~±7% (2σ); allow 25% for the parabola's bias.
        CPPUNIT_ASSERT_MESSAGE("MSE " + std::to_string(mse) + " vs CRB " + std::to_string(crb),
                               mse > 0.85 * crb && mse < 1.25 * crb);
        CPPUNIT_ASSERT(std::abs(bias) < 0.2 * std::sqrt(crb) + 2e-3);
    }

    void pilot_energies_weigh_the_bound()
    {
        // Pilot k observed with noise σ²/p_k: the closed form, the numeric inverse and the
        // one-path multipath bound agree, and moving energy to the outer subcarriers (more
        // delay information per unit of energy) lowers the bound at the same total energy.
        std::vector<pilot_position> pos;
        std::vector<double> power;
        for (int k = 0; k < 16; ++k) {
            pos.push_back({ 2 * k, (4 * k + (k % 3) * 7) % 64 });
            power.push_back(k % 2 ? 1.6 : 0.4);
        }
        const pilot_mask equal(fs.n_symbols, fs.n_subcarriers, pos);
        const pilot_mask mask(fs.n_symbols, fs.n_subcarriers, pos, { 1.0f, 0.0f }, { { "kind", "explicit" } },
                              "powered", power);
        const double snr = 13.0, sigma2 = std::pow(10.0, -snr / 10.0), b2 = fs.bandwidth_hz * fs.bandwidth_hz;
        const double v = delay_crb::variance_index(fs, mask, snr, false);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(numeric_crb_tau(mask, sigma2) * b2, v, 1e-9 * v);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(v, delay_crb::multipath_variance_index(fs, mask, snr, { { 17.3, { 1.0, 0.0 } } }),
                                     1e-6 * v);
        CPPUNIT_ASSERT(std::abs(v - delay_crb::variance_index(fs, equal, snr, false)) > 1e-3 * v);
        // Pilots on subcarriers 0, 31, 32 and 63 of 8 symbols: the outer ones at energy 1.5,
        // the inner ones at 0.5 (mean 1).
        std::vector<pilot_position> edges;
        for (int k = 0; k < 8; ++k) {
            edges.push_back({ k, 0 });
            edges.push_back({ k, 63 });
            edges.push_back({ k, 31 });
            edges.push_back({ k, 32 });
        }
        const pilot_mask flat(fs.n_symbols, fs.n_subcarriers, edges);
        std::vector<double> outer;
        for (const auto& p : flat.positions())
            outer.push_back(p.m == 0 || p.m == 63 ? 1.5 : 0.5);
        const pilot_mask heavy(fs.n_symbols, fs.n_subcarriers, flat.positions(), { 1.0f, 0.0f },
                               { { "kind", "explicit" } }, "outer", outer);
        // Closed form of S with weights: centre 31.5, S = Σ p_k (m_k - 31.5)².
        const double s_flat = 16 * 31.5 * 31.5 + 16 * 0.5 * 0.5;
        const double s_heavy = 16 * 1.5 * 31.5 * 31.5 + 16 * 0.5 * 0.5 * 0.5;
        CPPUNIT_ASSERT_DOUBLES_EQUAL(s_flat, delay_crb::spread(flat, true), 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(s_heavy, delay_crb::spread(heavy, true), 1e-9);
        CPPUNIT_ASSERT(delay_crb::variance_index(fs, heavy, snr, true) < delay_crb::variance_index(fs, flat, snr, true));
    }

    void bad_input_is_refused()
    {
        const auto mask = pilot_mask::random(fs.n_symbols, fs.n_subcarriers, 32, 1);
        CPPUNIT_ASSERT_THROW(delay_crb::variance_index(fs, mask, std::nan("")), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(delay_crb::variance_index(fs, mask, 10.0, false, 0.0), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(delay_crb::variance_index(fs, mask, 10.0, false, -1.0), std::invalid_argument);
        // All pilots on one subcarrier: no delay information.
        CPPUNIT_ASSERT_THROW(delay_crb::variance_index(fs, pilot_mask::doppler(32, 64, 32), 10.0),
                             std::invalid_argument);
        // Subcarrier tied to symbol: known Doppler fine, unknown Doppler unidentifiable.
        std::vector<pilot_position> diag;
        for (int k = 0; k < 16; ++k)
            diag.push_back({ k, 2 * k });
        const pilot_mask d(fs.n_symbols, fs.n_subcarriers, diag);
        CPPUNIT_ASSERT(delay_crb::variance_index(fs, d, 10.0, true) > 0.0);
        CPPUNIT_ASSERT_THROW(delay_crb::variance_index(fs, d, 10.0, false), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(delay_crb::variance_index(fs, pilot_mask::random(16, 64, 8, 1), 10.0),
                             std::invalid_argument);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_baselines_crb);
