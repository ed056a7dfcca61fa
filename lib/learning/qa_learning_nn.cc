// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: learning networks — Gumbel-Softmax numerics, distinct final masks,
 * soft-argmax stability, decoder shapes. */
#include "learning/classifier_decoder.h"
#include "learning/delay_decoder.h"
#include "learning/reconstruction_decoder.h"
#include "learning/semantic_encoder.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <set>

using namespace gr::sems;
using namespace gr::sems::nn;

namespace {
bool all_finite(const torch::Tensor& t) { return torch::isfinite(t).all().item<bool>(); }

// Every row is exactly one-hot: entries in {0, 1} and exactly one 1.
void assert_exact_one_hot(const torch::Tensor& s)
{
    auto ones = s.eq(1.0f), zeros = s.eq(0.0f);
    CPPUNIT_ASSERT((ones | zeros).all().item<bool>());
    CPPUNIT_ASSERT(ones.sum(1).eq(1).all().item<bool>());
}
} // namespace

class qa_learning_nn : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_learning_nn);
    CPPUNIT_TEST(gumbel_extremes_are_finite_and_one_hot);
    CPPUNIT_TEST(gumbel_gradient_flows);
    CPPUNIT_TEST(final_mask_is_distinct);
    CPPUNIT_TEST(encoder_forward_one_hot_at_floor);
    CPPUNIT_TEST(soft_argmax_stable_inside_grid);
    CPPUNIT_TEST(decoder_shapes_and_scale_invariance);
    CPPUNIT_TEST_SUITE_END();

public:
    void gumbel_extremes_are_finite_and_one_hot()
    {
        torch::manual_seed(1);
        const int r = 8, k = 64;
        auto logits = torch::where(torch::rand({ r, k }) > 0.5, torch::full({ r, k }, 1e4), torch::full({ r, k }, -1e4));
        for (double temp : { 1e-3, 0.1, 1.0, 10.0 })
            for (double u : { 0.0, 1.0, 0.5 }) {
                auto s = gumbel_softmax_st(logits, temp, torch::full({ r, k }, u));
                CPPUNIT_ASSERT(all_finite(s));
                assert_exact_one_hot(s);
                // Soft sample too: finite, rows sum to 1.
                auto soft = gumbel_softmax_st(logits, temp, torch::full({ r, k }, u), false);
                CPPUNIT_ASSERT(all_finite(soft));
                CPPUNIT_ASSERT(torch::allclose(soft.sum(1), torch::ones({ r }), 1e-5, 1e-5));
            }
        // Uniform draws at their bounds mixed within one matrix, and huge equal logits.
        auto u = torch::where(torch::rand({ r, k }) > 0.5, torch::zeros({ r, k }), torch::ones({ r, k }));
        auto s = gumbel_softmax_st(torch::full({ r, k }, 1e4), 0.1, u);
        CPPUNIT_ASSERT(all_finite(s));
        assert_exact_one_hot(s);
        CPPUNIT_ASSERT_THROW(gumbel_softmax_st(logits, 0.0), std::invalid_argument);
    }

    void gumbel_gradient_flows()
    {
        auto logits = (torch::randn({ 4, 32 }) * 1e4).requires_grad_(true);
        auto w = torch::randn({ 4, 32 });
        auto s = gumbel_softmax_st(logits, 0.1, torch::full({ 4, 32 }, 1.0));
        (s * w).sum().backward();
        CPPUNIT_ASSERT(logits.grad().defined());
        CPPUNIT_ASSERT(all_finite(logits.grad()));
        // Moderate logits: a non-zero straight-through gradient.
        auto z = torch::zeros({ 2, 16 }, torch::requires_grad());
        auto s2 = gumbel_softmax_st(z, 1.0);
        (s2 * torch::randn({ 2, 16 })).sum().backward();
        CPPUNIT_ASSERT(z.grad().abs().sum().item<double>() > 0.0);
    }

    void final_mask_is_distinct()
    {
        // Every head wants the same element: the greedy assignment still gives distinct ones.
        auto same = torch::zeros({ 32, 2048 });
        same.select(1, 7).fill_(1e4);
        auto idx = greedy_distinct_assignment(same);
        CPPUNIT_ASSERT_EQUAL(size_t(32), std::set<int64_t>(idx.begin(), idx.end()).size());
        CPPUNIT_ASSERT(std::find(idx.begin(), idx.end(), 7) != idx.end());
        // N_p = N*M: every element exactly once.
        auto full = greedy_distinct_assignment(torch::randn({ 16, 16 }) * 1e4);
        CPPUNIT_ASSERT_EQUAL(size_t(16), std::set<int64_t>(full.begin(), full.end()).size());
        CPPUNIT_ASSERT_THROW(greedy_distinct_assignment(torch::zeros({ 5, 4 })), std::invalid_argument);
        // A fresh encoder (both score forms): exactly N_p distinct in-range positions.
        for (bool factorized : { true, false }) {
            torch::manual_seed(3);
            encoder_settings es;
            es.factorized = factorized;
            semantic_encoder enc(32, 32, 64, es);
            auto f = enc->final_indices();
            std::set<int64_t> u(f.begin(), f.end());
            CPPUNIT_ASSERT_EQUAL(size_t(32), u.size());
            CPPUNIT_ASSERT(*u.begin() >= 0 && *u.rbegin() < 32 * 64);
        }
    }

    void encoder_forward_one_hot_at_floor()
    {
        torch::manual_seed(4);
        encoder_settings es;
        semantic_encoder enc(8, 4, 8, es);
        auto s = enc->sample(es.temperature_floor);
        CPPUNIT_ASSERT_EQUAL(int64_t(8), s.size(0));
        CPPUNIT_ASSERT_EQUAL(int64_t(32), s.size(1));
        assert_exact_one_hot(s);
        auto mask = semantic_encoder_module::mask_from_selection(s, 4, 8);
        CPPUNIT_ASSERT_EQUAL(8.0, mask.sum().item<double>());
        auto pen = enc->collision_penalty(es.temperature_floor);
        CPPUNIT_ASSERT(all_finite(pen) && pen.item<double>() >= -1e-6);
    }

    void soft_argmax_stable_inside_grid()
    {
        torch::manual_seed(5);
        const int q = 101;
        auto grid = torch::linspace(-2.0, 48.0, q);
        for (int window : { 0, 4 }) {
            auto logits = torch::where(torch::rand({ 16, q }) > 0.5, torch::full({ 16, q }, 1e4),
                                       torch::full({ 16, q }, -1e4))
                              .requires_grad_(true);
            auto tau = soft_argmax(logits, grid, window);
            CPPUNIT_ASSERT(all_finite(tau));
            CPPUNIT_ASSERT(tau.min().item<double>() >= -2.0 && tau.max().item<double>() <= 48.0);
            tau.sum().backward();
            CPPUNIT_ASSERT(all_finite(logits.grad()));
            // One dominant logit, at the ends and in the middle: exactly that grid point.
            for (int k : { 0, 50, q - 1 }) {
                auto one = torch::full({ 1, q }, -1e4);
                one[0][k] = 1e4;
                const double got = soft_argmax(one, grid, window).item<double>();
                CPPUNIT_ASSERT_DOUBLES_EQUAL(grid[k].item<double>(), got, 1e-4);
            }
            // Two equal peaks next to each other: the midpoint.
            auto two = torch::full({ 1, q }, -1e4);
            two[0][20] = 1e4;
            two[0][21] = 1e4;
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.5 * (grid[20].item<double>() + grid[21].item<double>()),
                                         soft_argmax(two, grid, window).item<double>(), 1e-4);
        }
    }

    void decoder_shapes_and_scale_invariance()
    {
        torch::manual_seed(6);
        const int n = 8, m = 16, np = 12;
        auto grid = torch::zeros({ 3, 2, n, m });
        auto idx = torch::randperm(n * m).slice(0, 0, np);
        grid.view({ 3, 2, n * m }).index_copy_(2, idx, torch::randn({ 3, 2, np }));
        classifier_settings cs;
        cs.n_classes = 3;
        classifier_decoder_module cls(n, m, np, cs);
        cls.eval();
        auto out = cls.forward(grid);
        CPPUNIT_ASSERT_EQUAL(int64_t(3), out.logits.size(1));
        CPPUNIT_ASSERT_EQUAL(int64_t(16), out.features.size(1));
        // Per-frame normalisation: 1e-20 and 1e20 amplitudes give the same (finite) answer.
        for (double a : { 1e-20, 1e20 }) {
            auto o = cls.forward(grid * a);
            CPPUNIT_ASSERT(all_finite(o.logits));
            CPPUNIT_ASSERT(torch::allclose(o.logits, out.logits, 1e-3, 1e-3));
        }
        delay_settings ds;
        ds.q = 81;
        ds.refine_paths = 0;
        delay_decoder_module del(n, m, np, ds);
        del.eval();
        auto d = del.forward(grid);
        CPPUNIT_ASSERT_EQUAL(int64_t(81), d.logits.size(1));
        CPPUNIT_ASSERT(d.delay_index.min().item<double>() >= ds.tau_min_index);
        CPPUNIT_ASSERT(d.delay_index.max().item<double>() <= ds.tau_max_index);
        // All-zero frame (no signal): finite.
        CPPUNIT_ASSERT(all_finite(del.forward(torch::zeros({ 1, 2, n, m })).delay_index));
        reconstruction_decoder_module rec(n, m, np, reconstruction_settings{});
        CPPUNIT_ASSERT(rec.forward(grid).channel.sizes() == grid.sizes());
        // Scatter then gather is the identity in mask order.
        std::vector<int64_t> flat = { 3, 17, 40, 99 };
        auto obs = torch::randn({ 2, 4, 2 });
        CPPUNIT_ASSERT(torch::equal(gather_pilots(scatter_pilots(obs, flat, n, m), flat), obs));
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_learning_nn);
