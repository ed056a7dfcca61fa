// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the one steering-phasor function and the Doppler grid against their closed forms. */
#include <gnuradio/sems/core/array/steering.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>

using namespace gr::sems;
using gr::sems::qa::assert_error;

class qa_steering : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_steering);
    CPPUNIT_TEST(delay_phasor_is_the_subcarrier_phase_slope);
    CPPUNIT_TEST(doppler_phasor_is_exact_at_huge_symbol_indices);
    CPPUNIT_TEST(doppler_grid_spans_the_unambiguous_band);
    CPPUNIT_TEST_SUITE_END();

public:
    void delay_phasor_is_the_subcarrier_phase_slope()
    {
        const frame_settings fs;
        const double tau_s = 123e-9, index = fs.delay_index(tau_s);
        for (int m : { 0, 1, 17, 63 }) {
            const double phase = -2.0 * M_PI * m * fs.subcarrier_spacing_hz() * tau_s;
            const auto d = delay_phasor(m, index, fs.n_subcarriers);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::cos(phase), d.real(), 1e-12);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sin(phase), d.imag(), 1e-12);
        }
        // Periodic in the delay index with period M (the unambiguous delay 1/Δf).
        const auto a = delay_phasor(5, 3.25, 64), b = delay_phasor(5, 3.25 + 64, 64);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(a - b), 1e-12);
    }

    void doppler_phasor_is_exact_at_huge_symbol_indices()
    {
        // ν T = 0.125 cycles per symbol: at n = 8e12 + 3 the phase is exactly 3/8 of a cycle.
        const auto p = doppler_phasor(8e12 + 3, 125.0, 1e-3);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::cos(0.75 * M_PI), p.real(), 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sin(0.75 * M_PI), p.imag(), 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, std::abs(cis_cycles(-1e15 - 0.3)), 1e-15);
    }

    void doppler_grid_spans_the_unambiguous_band()
    {
        const frame_settings fs; // N = 32, T = 1 ms: ±500 Hz, resolution 31.25 Hz
        const auto g = doppler_grid(fs, 2);
        CPPUNIT_ASSERT_EQUAL(size_t(64), g.size());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-500.0, g.front(), 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(500.0 - 15.625, g.back(), 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, g[32], 1e-12);
        assert_error([&] { doppler_grid(fs, 0); }, "oversample", "0");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_steering);
