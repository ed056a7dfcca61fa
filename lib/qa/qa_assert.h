// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: assertions shared by the CppUnit suites (test-only, not installed). */
#ifndef INCLUDED_SEMS_LIB_QA_QA_ASSERT_H
#define INCLUDED_SEMS_LIB_QA_QA_ASSERT_H

#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

/* CppUnit names a suite's registration after its source line (autoRegisterRegistry__<line>), so
 * two suites registered on the same line of two files collide where a unity build compiles the
 * files together (SEMS_UNITY_BUILD). Named after the suite here: the same registration in the
 * same default registry. */
#undef CPPUNIT_TEST_SUITE_REGISTRATION
#define CPPUNIT_TEST_SUITE_REGISTRATION(suite) static CPPUNIT_NS::AutoRegisterSuite<suite> suite##_registration

namespace gr {
namespace sems {
namespace qa {

/* CppUnit's assertion macros build their message and source line (several std::string, a
 * std::deque and, for CPPUNIT_ASSERT_DOUBLES_EQUAL, the delta printed with sprintf) on every
 * call, passed or not. In a loop over a frame's cells that was most of a test's time under
 * AddressSanitizer (one test: 210 s, of which the allocator and its stack traces took over
 * half). The macros below, which replace CppUnit's for every suite that includes this header,
 * decide first and build the same message only when the assertion fails: the same checks,
 * the same semantics (the same comparisons and template deduction, each argument evaluated
 * once), the same report; a message argument is evaluated only on failure. */
template <class T>
inline void lazy_assert_equal(const T& expected, const T& actual, const char* file, int line)
{
    if (!CppUnit::assertion_traits<T>::equal(expected, actual))
        CppUnit::assertEquals(expected, actual, CppUnit::SourceLine(file, line), "");
}

template <class T, class M>
inline void lazy_assert_equal_message(const T& expected, const T& actual, const char* file, int line, M message)
{
    if (!CppUnit::assertion_traits<T>::equal(expected, actual))
        CppUnit::assertEquals(expected, actual, CppUnit::SourceLine(file, line), message());
}

// CppUnit's own rule (TestAssert.cpp): finite values are equal within delta; otherwise its
// assertDoubleEquals decides (equal infinities pass, a NaN fails).
template <class M>
inline void lazy_assert_doubles_equal(double expected, double actual, double delta, const char* file, int line, M message)
{
    if (std::isfinite(expected) && std::isfinite(actual) && std::fabs(expected - actual) <= delta)
        return;
    CppUnit::assertDoubleEquals(expected, actual, delta, CppUnit::SourceLine(file, line), message());
}

template <class T>
inline void lazy_assert_less(const T& expected, const T& actual, const char* file, int line)
{
    if (!CppUnit::assertion_traits<T>::less(actual, expected))
        CppUnit::assertLess(expected, actual, CppUnit::SourceLine(file, line), "");
}

template <class T>
inline void lazy_assert_greater(const T& expected, const T& actual, const char* file, int line)
{
    if (!CppUnit::assertion_traits<T>::less(expected, actual))
        CppUnit::assertGreater(expected, actual, CppUnit::SourceLine(file, line), "");
}

} // namespace qa
} // namespace sems
} // namespace gr

#undef CPPUNIT_ASSERT
#define CPPUNIT_ASSERT(condition)                                                                                \
    ((condition) ? (void)0                                                                                      \
                 : CPPUNIT_NS::Asserter::fail(CPPUNIT_NS::Message("assertion failed", "Expression: " #condition), \
                                              CPPUNIT_SOURCELINE()))
#undef CPPUNIT_ASSERT_MESSAGE
#define CPPUNIT_ASSERT_MESSAGE(message, condition)                                                    \
    ((condition) ? (void)0                                                                           \
                 : CPPUNIT_NS::Asserter::fail(CPPUNIT_NS::Message("assertion failed",                \
                                                                  "Expression: " #condition,         \
                                                                  CPPUNIT_NS::message_to_string(message)), \
                                              CPPUNIT_SOURCELINE()))
#undef CPPUNIT_ASSERT_EQUAL
#define CPPUNIT_ASSERT_EQUAL(expected, actual) \
    (::gr::sems::qa::lazy_assert_equal((expected), (actual), __FILE__, __LINE__))
#undef CPPUNIT_ASSERT_EQUAL_MESSAGE
#define CPPUNIT_ASSERT_EQUAL_MESSAGE(message, expected, actual)                      \
    (::gr::sems::qa::lazy_assert_equal_message((expected), (actual), __FILE__, __LINE__, \
                                               [&] { return CPPUNIT_NS::message_to_string(message); }))
#undef CPPUNIT_ASSERT_DOUBLES_EQUAL
#define CPPUNIT_ASSERT_DOUBLES_EQUAL(expected, actual, delta)                                                 \
    (::gr::sems::qa::lazy_assert_doubles_equal((expected), (actual), (delta), __FILE__, __LINE__, \
                                               [] { return std::string(); }))
#undef CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE
#define CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE(message, expected, actual, delta)                     \
    (::gr::sems::qa::lazy_assert_doubles_equal((expected), (actual), (delta), __FILE__, __LINE__, \
                                               [&] { return CPPUNIT_NS::message_to_string(message); }))
#undef CPPUNIT_ASSERT_LESS
#define CPPUNIT_ASSERT_LESS(expected, actual) \
    (::gr::sems::qa::lazy_assert_less((expected), (actual), __FILE__, __LINE__))
#undef CPPUNIT_ASSERT_GREATER
#define CPPUNIT_ASSERT_GREATER(expected, actual) \
    (::gr::sems::qa::lazy_assert_greater((expected), (actual), __FILE__, __LINE__))

namespace gr {
namespace sems {
namespace qa {

// Asserts that f() throws std::invalid_argument whose message contains every needle:
// errors must name the file or parameter and the problem, so tests check the words.
template <typename F>
void assert_error(F f, const std::string& needle1, const std::string& needle2 = "")
{
    try {
        f();
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        for (const auto* needle : { &needle1, &needle2 })
            CPPUNIT_ASSERT_MESSAGE("message \"" + what + "\" lacks \"" + *needle + "\"",
                                   what.find(*needle) != std::string::npos);
        return;
    }
    CPPUNIT_FAIL("expected std::invalid_argument mentioning \"" + needle1 + "\"");
}

// Asserts that a model's values equal a closed form up to the model's one real power
// normalisation (the least-squares scale between them, real and positive) within
// `tolerance` times that scale, naming `what` in the message.
inline void assert_equal_up_to_power(const std::vector<std::complex<double>>& got,
                                     const std::vector<std::complex<double>>& want,
                                     double tolerance,
                                     const std::string& what = "")
{
    std::complex<double> num = 0.0;
    double den = 0.0;
    for (size_t i = 0; i < got.size(); ++i) {
        num += got[i] * std::conj(want[i]);
        den += std::norm(want[i]);
    }
    const std::complex<double> scale = num / den;
    CPPUNIT_ASSERT_MESSAGE(what + ": scale " + std::to_string(scale.real()) + " " + std::to_string(scale.imag()),
                           std::fabs(std::arg(scale)) < 1e-6 && scale.real() > 0.1);
    double worst = 0.0;
    for (size_t i = 0; i < got.size(); ++i)
        worst = std::max(worst, std::abs(got[i] - scale * want[i]));
    CPPUNIT_ASSERT_MESSAGE(what + ": worst error " + std::to_string(worst), worst < tolerance * scale.real());
}

} // namespace qa
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_QA_QA_ASSERT_H */
