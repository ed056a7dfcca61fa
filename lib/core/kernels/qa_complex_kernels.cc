// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the emulators' fused complex loops against a double-precision reference, and
 * their AVX2 and portable versions against each other (the same bits), at every length
 * around the vector width; the scatterer models' vectorised sine and cosine against libm. */
#include "core/kernels/complex_kernels.h"
#include "core/kernels/vector_math.h"
#include "qa/qa_assert.h"
#include <cmath>
#include <limits>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <complex>
#include <random>
#include <vector>

using namespace gr::sems;

namespace {

std::vector<gr_complex> random_vector(std::mt19937& g, size_t n)
{
    std::normal_distribution<float> nd;
    std::vector<gr_complex> v(n);
    for (auto& x : v)
        x = { nd(g), nd(g) };
    return v;
}

void assert_same_bits(const std::vector<gr_complex>& a, const std::vector<gr_complex>& b)
{
    CPPUNIT_ASSERT_EQUAL(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
        CPPUNIT_ASSERT_EQUAL(a[i].real(), b[i].real());
        CPPUNIT_ASSERT_EQUAL(a[i].imag(), b[i].imag());
    }
}

} // namespace

class qa_complex_kernels : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_complex_kernels);
    CPPUNIT_TEST(accumulate_rotated_is_the_product_sum);
    CPPUNIT_TEST(apply_row_sum_is_the_row_product);
    CPPUNIT_TEST(accumulate_rotator_is_the_linear_phase);
    CPPUNIT_TEST(add_horner_is_the_polynomial);
    CPPUNIT_TEST(apply_horner_is_add_horner_then_multiply);
    CPPUNIT_TEST(multiply_is_the_product);
    CPPUNIT_TEST(sincos_batch_is_libm_within_2_ulp);
    CPPUNIT_TEST_SUITE_END();

public:
    void tearDown() override { detail::complex_kernels_choose(detail::kernel_choice::fastest); }

    void accumulate_rotated_is_the_product_sum()
    {
        std::mt19937 g(5);
        for (int n : { 0, 1, 3, 4, 5, 7, 8, 13, 80 }) {
            const auto x = random_vector(g, n), d = random_vector(g, n), start = random_vector(g, n);
            const gr_complex c(0.3f, -0.9f);
            std::vector<gr_complex> fast = start, portable = start;
            detail::accumulate_rotated(fast.data(), x.data(), d.data(), c, n);
            detail::complex_kernels_choose(detail::kernel_choice::portable);
            detail::accumulate_rotated(portable.data(), x.data(), d.data(), c, n);
            detail::complex_kernels_choose(detail::kernel_choice::fastest);
            assert_same_bits(fast, portable);
            for (int k = 0; k < n; ++k) {
                const std::complex<double> ref = std::complex<double>(start[k]) +
                                                 std::complex<double>(x[k]) * std::complex<double>(c) *
                                                     std::complex<double>(d[k]);
                CPPUNIT_ASSERT(std::abs(std::complex<double>(fast[k]) - ref) < 1e-5 * (1.0 + std::abs(ref)));
            }
        }
    }

    void accumulate_rotator_is_the_linear_phase()
    {
        std::mt19937 g(7);
        const std::complex<double> p = std::polar(0.9, 2.1), step = std::polar(1.0, 3e-3);
        for (int n : { 0, 1, 3, 4, 5, 27, 80 }) {
            const auto x = random_vector(g, n), start = random_vector(g, n);
            std::vector<gr_complex> fast = start, portable = start;
            detail::accumulate_rotator(fast.data(), x.data(), n, p, step);
            detail::complex_kernels_choose(detail::kernel_choice::portable);
            detail::accumulate_rotator(portable.data(), x.data(), n, p, step);
            detail::complex_kernels_choose(detail::kernel_choice::fastest);
            assert_same_bits(fast, portable);
            for (int k = 0; k < n; ++k) {
                const std::complex<double> ref = std::complex<double>(start[k]) +
                                                 std::complex<double>(x[k]) * p * std::pow(step, k);
                CPPUNIT_ASSERT(std::abs(std::complex<double>(fast[k]) - ref) < 2e-6 * (1.0 + std::abs(ref)));
            }
        }
    }

    void apply_row_sum_is_the_row_product()
    {
        std::mt19937 g(6);
        for (int rows : { 1, 2, 3, 10 })
            for (int n : { 1, 4, 6, 64, 67 }) {
                const int stride = n + 3; // rows apart in memory, as a frame's rows of M + padding
                const auto d = random_vector(g, size_t(rows) * stride), c = random_vector(g, rows),
                           x = random_vector(g, n);
                std::vector<gr_complex> fast(n), portable(n), in_place = x;
                detail::apply_row_sum(fast.data(), x.data(), d.data(), stride, c.data(), rows, n);
                detail::apply_row_sum(in_place.data(), in_place.data(), d.data(), stride, c.data(), rows, n);
                assert_same_bits(fast, in_place); // y may alias x
                detail::complex_kernels_choose(detail::kernel_choice::portable);
                detail::apply_row_sum(portable.data(), x.data(), d.data(), stride, c.data(), rows, n);
                detail::complex_kernels_choose(detail::kernel_choice::fastest);
                assert_same_bits(fast, portable);
                // What a CPU without AVX2 runs (VOLK's passes): the same row to float rounding.
                std::vector<gr_complex> volk_row(n), h_row(n), h_portable(n);
                detail::complex_kernels_choose(detail::kernel_choice::without_avx2);
                detail::apply_row_sum(volk_row.data(), x.data(), d.data(), stride, c.data(), rows, n);
                detail::row_sum(h_row.data(), d.data(), stride, c.data(), rows, n);
                detail::complex_kernels_choose(detail::kernel_choice::portable);
                detail::row_sum(h_portable.data(), d.data(), stride, c.data(), rows, n);
                detail::complex_kernels_choose(detail::kernel_choice::fastest);
                std::vector<gr_complex> h_fast(n);
                detail::row_sum(h_fast.data(), d.data(), stride, c.data(), rows, n);
                assert_same_bits(h_fast, h_portable);
                for (int k = 0; k < n; ++k) {
                    CPPUNIT_ASSERT(std::abs(volk_row[k] - fast[k]) < 1e-5f * (1.0f + std::abs(fast[k])) * rows);
                    CPPUNIT_ASSERT(std::abs(h_row[k] - h_portable[k]) < 1e-5f * (1.0f + std::abs(h_portable[k])) * rows);
                }
                for (int k = 0; k < n; ++k) {
                    std::complex<double> h = 0.0;
                    for (int l = 0; l < rows; ++l)
                        h += std::complex<double>(c[l]) * std::complex<double>(d[size_t(l) * stride + k]);
                    const std::complex<double> ref = std::complex<double>(x[k]) * h;
                    CPPUNIT_ASSERT(std::abs(std::complex<double>(fast[k]) - ref) < 1e-5 * (1.0 + std::abs(ref)) * rows);
                }
            }
    }

    // h += e·Σ_p u^p c_p on [k0, k1): the same bits from both versions, and the double-precision
    // polynomial to float rounding, at every length around the vector widths (4 and 32).
    void add_horner_is_the_polynomial()
    {
        std::mt19937 g(9);
        std::uniform_real_distribution<float> ud(-1.0f, 1.0f);
        for (int order : { 0, 1, 5, 14 })
            for (int k0 : { 0, 3 })
                for (int len : { 0, 1, 3, 4, 5, 31, 32, 33, 36, 61, 64 }) {
                    const int n = k0 + len + 2; // a subcarrier each side of the band stays untouched
                    const auto e = random_vector(g, n), start = random_vector(g, n);
                    auto c = random_vector(g, order + 1);
                    std::vector<float> u2(2 * n);
                    for (int k = 0; k < n; ++k)
                        u2[2 * k] = u2[2 * k + 1] = ud(g);
                    std::vector<gr_complex> fast = start, portable = start;
                    detail::add_horner(fast.data(), e.data(), u2.data(), c.data(), order, k0, k0 + len);
                    detail::complex_kernels_choose(detail::kernel_choice::portable);
                    detail::add_horner(portable.data(), e.data(), u2.data(), c.data(), order, k0, k0 + len);
                    detail::complex_kernels_choose(detail::kernel_choice::fastest);
                    assert_same_bits(fast, portable);
                    for (int k = 0; k < n; ++k) {
                        std::complex<double> poly(0.0, 0.0), scale(0.0, 0.0);
                        double power = 1.0, size = 0.0;
                        for (int p = 0; p <= order; ++p, power *= u2[2 * k]) {
                            poly += power * std::complex<double>(c[p]);
                            size += std::fabs(power) * std::abs(std::complex<double>(c[p]));
                        }
                        scale = k >= k0 && k < k0 + len ? std::complex<double>(e[k]) : 0.0;
                        const std::complex<double> ref = std::complex<double>(start[k]) + scale * poly;
                        const double tol = 1e-6 * (1.0 + std::abs(std::complex<double>(start[k])) +
                                                   std::abs(scale) * size * (order + 2));
                        CPPUNIT_ASSERT(std::abs(std::complex<double>(fast[k]) - ref) < tol);
                    }
                }
    }

    // y = x·(h + e·Σ_p u^p c_p) in one pass: the same bits as add_horner on the whole row then
    // multiply (h = 0 when null: add_horner on a zeroed row), from both versions, also in place.
    void apply_horner_is_add_horner_then_multiply()
    {
        std::mt19937 g(10);
        std::uniform_real_distribution<float> ud(-1.0f, 1.0f);
        for (int order : { 0, 1, 4, 14 })
            for (int n : { 0, 1, 3, 4, 5, 31, 32, 33, 36, 64, 100 })
                for (bool with_h : { false, true }) {
                    const auto e = random_vector(g, n), x = random_vector(g, n), c = random_vector(g, order + 1);
                    const auto h = with_h ? random_vector(g, n) : std::vector<gr_complex>(n, gr_complex(0.0f, 0.0f));
                    std::vector<float> u2(2 * n);
                    for (int k = 0; k < n; ++k)
                        u2[2 * k] = u2[2 * k + 1] = ud(g);
                    for (auto choice : { detail::kernel_choice::fastest, detail::kernel_choice::portable }) {
                        detail::complex_kernels_choose(choice);
                        std::vector<gr_complex> want = h, got(n), in_place = x;
                        detail::add_horner(want.data(), e.data(), u2.data(), c.data(), order, 0, n);
                        detail::multiply(want.data(), x.data(), want.data(), n);
                        const gr_complex* hp = with_h ? h.data() : nullptr;
                        detail::apply_horner(got.data(), x.data(), hp, e.data(), u2.data(), c.data(), order, n);
                        detail::apply_horner(in_place.data(), in_place.data(), hp, e.data(), u2.data(), c.data(), order, n);
                        detail::complex_kernels_choose(detail::kernel_choice::fastest);
                        assert_same_bits(want, got);
                        assert_same_bits(want, in_place);
                    }
                }
    }

    void multiply_is_the_product()
    {
        std::mt19937 g(11);
        for (int n : { 0, 1, 3, 4, 5, 7, 8, 13, 64, 80 }) {
            const auto x = random_vector(g, n), h = random_vector(g, n);
            std::vector<gr_complex> fast(n), portable(n);
            detail::multiply(fast.data(), x.data(), h.data(), n);
            detail::complex_kernels_choose(detail::kernel_choice::portable);
            detail::multiply(portable.data(), x.data(), h.data(), n);
            detail::complex_kernels_choose(detail::kernel_choice::fastest);
            assert_same_bits(fast, portable);
            for (int k = 0; k < n; ++k) {
                const std::complex<double> ref = std::complex<double>(x[k]) * std::complex<double>(h[k]);
                CPPUNIT_ASSERT(std::abs(std::complex<double>(fast[k]) - ref) < 1e-6 * (1.0 + std::abs(ref)));
            }
            std::vector<gr_complex> in_place = x; // y may alias x
            detail::multiply(in_place.data(), in_place.data(), h.data(), n);
            assert_same_bits(fast, in_place);
        }
    }

    // The scatterer models' phases: within 2 ulp of 1 (4.4e-16) of libm over the arguments they
    // meet (|κ r| up to thousands of rad), beyond the reduction's range and at the odd values.
    void sincos_batch_is_libm_within_2_ulp()
    {
        std::mt19937_64 g(3);
        std::vector<double> x;
        for (double range : { 1.0, 10.0, 300.0, 1e4, 1e6, 1e9 }) {
            std::uniform_real_distribution<double> ud(-range, range);
            for (int i = 0; i < 4001; ++i)
                x.push_back(ud(g));
        }
        for (double v : { 0.0, -0.0, M_PI_4, M_PI_2, M_PI, -M_PI, 1e6, -1e6, 1e6 + 1.0, 5e-324 })
            x.push_back(v);
        std::vector<double> s(x.size()), c(x.size());
        detail::sincos_batch(x.data(), s.data(), c.data(), x.size());
        for (size_t i = 0; i < x.size(); ++i) {
            CPPUNIT_ASSERT_MESSAGE("sin " + std::to_string(x[i]), std::fabs(s[i] - std::sin(x[i])) <= 4.5e-16);
            CPPUNIT_ASSERT_MESSAGE("cos " + std::to_string(x[i]), std::fabs(c[i] - std::cos(x[i])) <= 4.5e-16);
        }
        const double odd[] = { std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity() };
        double os[2], oc[2];
        detail::sincos_batch(odd, os, oc, 2);
        CPPUNIT_ASSERT(std::isnan(os[0]) && std::isnan(oc[0]) && std::isnan(os[1]) && std::isnan(oc[1]));
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_complex_kernels);
