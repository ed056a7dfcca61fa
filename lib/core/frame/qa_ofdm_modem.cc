// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: ofdm_modem against its closed forms: one subcarrier is a tone of amplitude
 * 1/sqrt(M) with the prefix repeating the symbol's tail; the modem is unitary (Parseval) and
 * demodulate inverts modulate; bad sizes are refused by name. */
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/frame/ofdm_modem.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <random>
#include <string>
#include <tuple>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

class qa_ofdm_modem : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_ofdm_modem);
    CPPUNIT_TEST(one_subcarrier_is_a_tone_with_its_prefix);
    CPPUNIT_TEST(unitary_and_inverted);
    CPPUNIT_TEST(bad_sizes_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    // X = δ[k0]: x[i] = e^{j2π k0 (i − L)/M} / sqrt(M) for every sample, the prefix included.
    void one_subcarrier_is_a_tone_with_its_prefix()
    {
        for (const auto& [m, cp, k0] : std::vector<std::tuple<int, int, int>>{ { 64, 16, 5 }, { 12, 3, 11 }, { 128, 0, 0 } }) {
            ofdm_modem o(m, cp);
            CPPUNIT_ASSERT_EQUAL(m + cp, o.symbol_len());
            std::vector<gr_complex> x(static_cast<size_t>(m)), s(static_cast<size_t>(m + cp));
            x[size_t(k0)] = 1.0f;
            o.modulate(x.data(), s.data());
            for (int i = 0; i < m + cp; ++i) {
                const auto want = std::polar(1.0 / std::sqrt(double(m)), 2.0 * M_PI * k0 * (i - cp) / m);
                CPPUNIT_ASSERT_MESSAGE("M " + std::to_string(m) + " sample " + std::to_string(i),
                                       std::abs(std::complex<double>(s[size_t(i)]) - want) < 1e-6);
            }
        }
    }

    // Σ|x|² over the prefix-free window = Σ|X|², and demodulate(modulate(X)) = X.
    void unitary_and_inverted()
    {
        std::mt19937 g(3);
        std::normal_distribution<float> n;
        const int m = 96, cp = 24;
        ofdm_modem o(m, cp);
        std::vector<gr_complex> x(static_cast<size_t>(m)), s(static_cast<size_t>(m + cp)), y(static_cast<size_t>(m));
        for (auto& v : x)
            v = gr_complex(n(g), n(g));
        o.modulate(x.data(), s.data());
        o.demodulate(s.data(), y.data());
        double ex = 0.0, es = 0.0;
        for (int k = 0; k < m; ++k) {
            ex += std::norm(x[size_t(k)]);
            es += std::norm(s[size_t(cp + k)]);
            CPPUNIT_ASSERT(std::abs(y[size_t(k)] - x[size_t(k)]) < 1e-5f * (1.0f + std::abs(x[size_t(k)])));
        }
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, es / ex, 1e-6);
        for (int i = 0; i < cp; ++i) // the prefix is the symbol's tail
            CPPUNIT_ASSERT(s[size_t(i)] == s[size_t(m + i)]);
    }

    void bad_sizes_are_refused()
    {
        assert_error([] { ofdm_modem(0, 0); }, "n_subcarriers", "0");
        assert_error([] { ofdm_modem(64, -1); }, "cp_len", "-1");
        assert_error([] { ofdm_modem(64, 65); }, "cp_len", "65");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_ofdm_modem);
