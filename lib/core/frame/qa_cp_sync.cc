// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: cp_sync (van de Beek) against its closed forms: a noiseless CP-OFDM stream with a
 * frequency offset gives the timing and the offset exactly; in noise the offset's variance
 * is (1/SNR + 1/(2·SNR²))/(4π²K); the correction undoes the offset, continuously across
 * calls; bad parameters are refused by name. */
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/frame/cp_sync.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {

// `symbols` CP-OFDM symbols of Gaussian samples (their spectrum: data on every subcarrier),
// unit power, shifted by `cfo` subcarrier spacings, in noise of variance sigma2.
std::vector<gr_complex> ofdm_stream(std::mt19937& g, int symbols, int m, int cp, double cfo, double sigma2)
{
    std::normal_distribution<float> n(0.0f, float(M_SQRT1_2));
    std::vector<gr_complex> x;
    for (int s = 0; s < symbols; ++s) {
        std::vector<gr_complex> body(static_cast<size_t>(m));
        for (auto& v : body)
            v = gr_complex(n(g), n(g));
        x.insert(x.end(), body.end() - cp, body.end());
        x.insert(x.end(), body.begin(), body.end());
    }
    const float sd = float(std::sqrt(sigma2));
    for (size_t k = 0; k < x.size(); ++k)
        x[k] = x[k] * gr_complex(std::polar(1.0, 2.0 * M_PI * cfo * double(k) / m)) + gr_complex(n(g), n(g)) * sd;
    return x;
}

} // namespace

class qa_cp_sync : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_cp_sync);
    CPPUNIT_TEST(test_noiseless_timing_and_offset_exact);
    CPPUNIT_TEST(test_variance_is_the_closed_form);
    CPPUNIT_TEST(test_correction_undoes_the_offset);
    CPPUNIT_TEST(test_bad_parameters_refused_by_name);
    CPPUNIT_TEST_SUITE_END();

    void test_noiseless_timing_and_offset_exact()
    {
        std::mt19937 g(1);
        const int m = 64, cp = 16, s = m + cp, symbols = 8;
        for (double cfo : { -0.49, -0.2, 0.0, 0.13, 0.4 })
            for (int start : { 0, 17, 79 }) {
                const auto x = ofdm_stream(g, symbols + 2, m, cp, cfo, 0.0);
                // the window begins `s − start` samples in, so a symbol starts at `start`
                const auto e = cp_sync(x.data() + (s - start) % s, symbols, m, cp, std::numeric_limits<double>::infinity());
                CPPUNIT_ASSERT_EQUAL(start % s, e.timing);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(cfo, e.cfo, 1e-5);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(cfo, cp_cfo(x.data(), symbols, m, cp), 1e-5);
            }
    }

    void test_variance_is_the_closed_form()
    {
        std::mt19937 g(2);
        const int m = 64, cp = 16, symbols = 8, trials = 2000;
        for (double snr_db : { 0.0, 10.0 }) {
            const double snr = std::pow(10.0, snr_db / 10.0), cfo = 0.1;
            double se = 0.0;
            for (int t = 0; t < trials; ++t) {
                const auto x = ofdm_stream(g, symbols, m, cp, cfo, 1.0 / snr);
                const double d = cp_cfo(x.data(), symbols, m, cp) - cfo;
                se += d * d;
            }
            const double got = se / trials, expect = cp_cfo_variance(snr, long(symbols) * cp);
            // 2 000 trials: the sample variance is within ±10 % (3σ) of its mean; 5 % more for
            // the high-K approximation
            CPPUNIT_ASSERT_MESSAGE("SNR " + std::to_string(snr_db) + " dB: variance " + std::to_string(got) +
                                       ", closed form " + std::to_string(expect),
                                   std::abs(got / expect - 1.0) < 0.15);
        }
    }

    void test_correction_undoes_the_offset()
    {
        std::mt19937 g(3);
        const int m = 64, cp = 16;
        const auto clean = ofdm_stream(g, 20, m, cp, 0.0, 0.0);
        std::vector<gr_complex> x(clean);
        for (size_t k = 0; k < x.size(); ++k)
            x[k] *= gr_complex(std::polar(1.0, 2.0 * M_PI * 0.3 * double(k) / m));
        // corrected in two calls: the phase continues across them
        const size_t half = x.size() / 2 + 3;
        cp_cfo_correct(x.data(), half, 0.3, m, 0);
        cp_cfo_correct(x.data() + half, x.size() - half, 0.3, m, half);
        double err = 0.0;
        for (size_t k = 0; k < x.size(); ++k)
            err += std::norm(x[k] - clean[k]);
        CPPUNIT_ASSERT(err / double(x.size()) < 1e-10);
    }

    void test_bad_parameters_refused_by_name()
    {
        std::vector<gr_complex> x(1000);
        assert_error([&] { cp_sync(x.data(), 0, 64, 16, 1.0); }, "symbols");
        assert_error([&] { cp_sync(x.data(), 2, 0, 16, 1.0); }, "m (the FFT size)");
        assert_error([&] { cp_sync(x.data(), 2, 64, 0, 1.0); }, "cp", "got 0");
        assert_error([&] { cp_sync(x.data(), 2, 64, 65, 1.0); }, "cp", "got 65");
        assert_error([&] { cp_sync(x.data(), 2, 64, 16, 0.0); }, "snr");
        assert_error([&] { cp_cfo(x.data(), 2, 64, 0); }, "cp");
        assert_error([&] { cp_cfo_correct(x.data(), 10, std::nan(""), 64); }, "cfo");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_cp_sync);
