// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the assertion macros of qa_assert.h, which decide before they build a message, fail
 * exactly where CppUnit's fail and report what CppUnit reports: the expression, both values,
 * the delta, the user's message and the source line. Compiled into qa_sems_core. */
#include "qa/qa_assert.h"
#include <cppunit/Exception.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

namespace {

// The report of a failed assertion, or "" when it passed.
std::string report(const std::function<void()>& f)
{
    try {
        f();
    } catch (const CppUnit::Exception& e) {
        return e.message().details() + " | " + e.message().shortDescription() + " | line " +
               std::to_string(e.sourceLine().lineNumber());
    }
    return "";
}

bool has(const std::string& text, const std::string& needle) { return text.find(needle) != std::string::npos; }

} // namespace

class qa_lazy_asserts : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_lazy_asserts);
    CPPUNIT_TEST(passing_assertions_report_nothing);
    CPPUNIT_TEST(failing_assertions_report_what_cppunit_reports);
    CPPUNIT_TEST(doubles_keep_cppunit_rules_for_infinities_and_nan);
    CPPUNIT_TEST(arguments_are_evaluated_once_and_messages_only_on_failure);
    CPPUNIT_TEST_SUITE_END();

public:
    void passing_assertions_report_nothing()
    {
        const int one = 1;
        CPPUNIT_ASSERT_EQUAL(std::string(), report([&] { CPPUNIT_ASSERT(one == 1); }));
        CPPUNIT_ASSERT_EQUAL(std::string(), report([&] { CPPUNIT_ASSERT_MESSAGE("m", one == 1); }));
        CPPUNIT_ASSERT_EQUAL(std::string(), report([&] { CPPUNIT_ASSERT_EQUAL(1, one); }));
        CPPUNIT_ASSERT_EQUAL(std::string(), report([&] { CPPUNIT_ASSERT_EQUAL_MESSAGE("m", 1, one); }));
        CPPUNIT_ASSERT_EQUAL(std::string(), report([&] { CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, 1.05, 0.1); }));
        CPPUNIT_ASSERT_EQUAL(std::string(), report([&] { CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE("m", 1.0, 1.05, 0.1); }));
        CPPUNIT_ASSERT_EQUAL(std::string(), report([&] { CPPUNIT_ASSERT_LESS(2, one); }));
        CPPUNIT_ASSERT_EQUAL(std::string(), report([&] { CPPUNIT_ASSERT_GREATER(0, one); }));
    }

    void failing_assertions_report_what_cppunit_reports()
    {
        const int one = 1;
        const int line = __LINE__ + 1;
        auto r = report([&] { CPPUNIT_ASSERT(one == 2); });
        CPPUNIT_ASSERT_MESSAGE(r, has(r, "Expression: one == 2") && has(r, "assertion failed") &&
                                      has(r, "line " + std::to_string(line)));
        r = report([&] { CPPUNIT_ASSERT_MESSAGE("frame " + std::to_string(7), one == 2); });
        CPPUNIT_ASSERT_MESSAGE(r, has(r, "Expression: one == 2") && has(r, "frame 7"));
        r = report([&] { CPPUNIT_ASSERT_EQUAL(2, one); });
        CPPUNIT_ASSERT_MESSAGE(r, has(r, "Expected: 2") && has(r, "Actual  : 1") && has(r, "equality assertion failed"));
        r = report([&] { CPPUNIT_ASSERT_EQUAL_MESSAGE("cell " + std::to_string(3), 2, one); });
        CPPUNIT_ASSERT_MESSAGE(r, has(r, "Expected: 2") && has(r, "Actual  : 1") && has(r, "cell 3"));
        r = report([&] { CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, 1.25, 0.1); });
        CPPUNIT_ASSERT_MESSAGE(r, has(r, "Expected: 1") && has(r, "Actual  : 1.25") && has(r, "Delta   : 0.1"));
        r = report([&] { CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE("snr", 1.0, 1.25, 0.1); });
        CPPUNIT_ASSERT_MESSAGE(r, has(r, "Delta   : 0.1") && has(r, "snr"));
        r = report([&] { CPPUNIT_ASSERT_LESS(1, one); });
        CPPUNIT_ASSERT_MESSAGE(r, has(r, "less assertion failed") && has(r, "Expected less than: 1"));
        r = report([&] { CPPUNIT_ASSERT_GREATER(1, one); });
        CPPUNIT_ASSERT_MESSAGE(r, has(r, "greater assertion failed") && has(r, "Expected greater than: 1"));
    }

    void doubles_keep_cppunit_rules_for_infinities_and_nan()
    {
        const double inf = std::numeric_limits<double>::infinity();
        const double nan = std::numeric_limits<double>::quiet_NaN();
        CPPUNIT_ASSERT_EQUAL(std::string(), report([&] { CPPUNIT_ASSERT_DOUBLES_EQUAL(inf, inf, 0.0); }));
        CPPUNIT_ASSERT(!report([&] { CPPUNIT_ASSERT_DOUBLES_EQUAL(inf, -inf, 1.0); }).empty());
        CPPUNIT_ASSERT(!report([&] { CPPUNIT_ASSERT_DOUBLES_EQUAL(nan, nan, 1.0); }).empty());
        CPPUNIT_ASSERT(!report([&] { CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, nan, inf); }).empty());
        CPPUNIT_ASSERT(!report([&] { CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, 1.0, nan); }).empty());
    }

    void arguments_are_evaluated_once_and_messages_only_on_failure()
    {
        int evaluated = 0, messages = 0;
        auto value = [&] { return ++evaluated; };
        auto message = [&] { ++messages; return std::string("m"); };
        CPPUNIT_ASSERT_EQUAL(1, value());
        CPPUNIT_ASSERT_EQUAL_MESSAGE(message(), 2, value());
        CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE(message(), 3.0, value(), 0.0);
        CPPUNIT_ASSERT_MESSAGE(message(), value() == 4);
        CPPUNIT_ASSERT_EQUAL(4, evaluated);
        CPPUNIT_ASSERT_EQUAL(0, messages);
        report([&] { CPPUNIT_ASSERT_EQUAL_MESSAGE(message(), 0, value()); });
        CPPUNIT_ASSERT_EQUAL(5, evaluated);
        CPPUNIT_ASSERT_EQUAL(1, messages);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_lazy_asserts);
