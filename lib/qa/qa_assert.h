// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: assertions shared by the CppUnit suites (test-only, not installed). */
#ifndef INCLUDED_SEMS_LIB_QA_QA_ASSERT_H
#define INCLUDED_SEMS_LIB_QA_QA_ASSERT_H

#include <cppunit/TestAssert.h>
#include <stdexcept>
#include <string>

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

} // namespace qa
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_QA_QA_ASSERT_H */
