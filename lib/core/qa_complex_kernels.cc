// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the emulators' fused complex loops against a double-precision reference, and
 * their AVX2 and portable versions against each other (the same bits), at every length
 * around the vector width. */
#include "core/complex_kernels.h"
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
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_complex_kernels);
