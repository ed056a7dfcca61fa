// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: assertions shared by the CppUnit suites (test-only, not installed). */
#ifndef INCLUDED_SEMS_LIB_QA_QA_ASSERT_H
#define INCLUDED_SEMS_LIB_QA_QA_ASSERT_H

#include <cppunit/TestAssert.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

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
