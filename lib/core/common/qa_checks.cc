// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the shared finite / positive checks at their edges (NaN, ±Inf, 0, denormals). */
#include "core/common/checks.h"
#include "qa/qa_assert.h"
#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <limits>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

class qa_checks : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_checks);
    CPPUNIT_TEST(scalars_at_the_edges);
    CPPUNIT_TEST(complex_needs_both_parts);
    CPPUNIT_TEST(all_finite_finds_one_bad_element);
    CPPUNIT_TEST(callers_keep_their_messages);
    CPPUNIT_TEST_SUITE_END();

    static constexpr double inf = std::numeric_limits<double>::infinity();
    static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    static constexpr double tiny = std::numeric_limits<double>::denorm_min();

public:
    void scalars_at_the_edges()
    {
        CPPUNIT_ASSERT(checks::finite(0.0) && checks::finite(-1e308) && checks::finite(tiny));
        CPPUNIT_ASSERT(!checks::finite(nan) && !checks::finite(inf) && !checks::finite(-inf));
        CPPUNIT_ASSERT(checks::positive(tiny) && checks::positive(1e308));
        CPPUNIT_ASSERT(!checks::positive(0.0) && !checks::positive(-0.0) && !checks::positive(-tiny));
        CPPUNIT_ASSERT(!checks::positive(inf) && !checks::positive(nan));
        CPPUNIT_ASSERT(checks::non_negative(0.0) && checks::non_negative(-0.0) && checks::non_negative(tiny));
        CPPUNIT_ASSERT(!checks::non_negative(-tiny) && !checks::non_negative(inf) && !checks::non_negative(nan));
    }

    void complex_needs_both_parts()
    {
        CPPUNIT_ASSERT(checks::finite(gr_complex(1.0f, -2.0f)));
        CPPUNIT_ASSERT(!checks::finite(gr_complex(std::numeric_limits<float>::infinity(), 0.0f)));
        CPPUNIT_ASSERT(!checks::finite(std::complex<double>(0.0, nan)));
    }

    void all_finite_finds_one_bad_element()
    {
        std::vector<gr_complex> x(64, gr_complex(1.0f, 1.0f));
        CPPUNIT_ASSERT(checks::all_finite(x.data(), x.size()));
        x[63] = gr_complex(0.0f, std::numeric_limits<float>::quiet_NaN());
        CPPUNIT_ASSERT(!checks::all_finite(x.data(), x.size()));
        CPPUNIT_ASSERT(checks::all_finite(x.data(), 63)); // only the first n are read
        // The single-precision path reads exponent bits: the edges of "finite" on both parts.
        const float fmax = std::numeric_limits<float>::max(), tiny = std::numeric_limits<float>::denorm_min();
        for (gr_complex ok : { gr_complex(fmax, -fmax), gr_complex(-0.0f, tiny), gr_complex(-tiny, 0.0f) }) {
            x[63] = ok;
            CPPUNIT_ASSERT(checks::all_finite(x.data(), x.size()));
        }
        const float finf = std::numeric_limits<float>::infinity();
        for (gr_complex bad : { gr_complex(finf, 0.0f), gr_complex(0.0f, -finf),
                                gr_complex(-std::numeric_limits<float>::quiet_NaN(), 0.0f) }) {
            x[0] = bad;
            CPPUNIT_ASSERT(!checks::all_finite(x.data(), 1));
            x[0] = gr_complex(1.0f, 1.0f);
        }
        std::vector<double> d{ 1.0, 2.0, -inf };
        CPPUNIT_ASSERT(!checks::all_finite(d.data(), d.size()));
        CPPUNIT_ASSERT(checks::all_finite(d.data(), 2));
    }

    void callers_keep_their_messages()
    {
        // frame_settings takes its positivity from checks: NaN, Inf and 0 are refused by name.
        for (double bad : { 0.0, -1.0, nan, inf }) {
            frame_settings fs;
            fs.bandwidth_hz = bad;
            assert_error([&] { fs.validate(); }, "bandwidth_hz", "must be a positive finite number");
        }
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_checks);
