// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: learning networks — Gumbel-Softmax and Gumbel top-k numerics, distinct
 * masks, soft-argmax stability, decoder shapes, the spectral classifier's phase
 * invariance and its zero-Doppler (MTI) stage. */
#include "learning/networks/classifier_decoder.h"
#include "learning/networks/delay_decoder.h"
#include "learning/networks/reconstruction_decoder.h"
#include "learning/training/semantic_encoder.h"
#include "learning/networks/spectral_classifier_decoder.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/channel/channel_model.h>
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
    CPPUNIT_TEST(topk_distinct_and_finite_at_extremes);
    CPPUNIT_TEST(topk_encoder_mask_is_exactly_np_distinct);
    CPPUNIT_TEST(topk_mask_equals_the_dense_column_sums);
    CPPUNIT_TEST(encoder_never_selects_a_guard);
    CPPUNIT_TEST(mti_removes_static_path_exactly);
    CPPUNIT_TEST(spectral_decoder_phase_invariant_on_any_mask);
    CPPUNIT_TEST(spectral_decoder_inference_paths_match);
    CPPUNIT_TEST(spectral_range_gate_closed_forms);
    CPPUNIT_TEST(spectral_range_gate_by_fft_on_large_frames);
    CPPUNIT_TEST(tone_fit_closed_forms);
    CPPUNIT_TEST(tone_fit_counts_subcarriers_with_enough_pilots);
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
            es.kind = "gumbel_heads";
            es.factorized = factorized;
            semantic_encoder enc(32, 32, 64, es);
            auto f = enc->final_indices();
            std::set<int64_t> u(f.begin(), f.end());
            CPPUNIT_ASSERT_EQUAL(size_t(32), u.size());
            CPPUNIT_ASSERT(*u.begin() >= 0 && *u.rbegin() < 32 * 64);
        }
    }

    void encoder_never_selects_a_guard()
    {
        // Guards at DC-like and edge columns; N_p = every usable element is the hardest case.
        const int n = 4, m = 8;
        const std::vector<int> guards = { 0, 3, 7 };
        const int usable = n * (m - 3);
        for (const char* kind : { "gumbel_topk", "gumbel_heads" })
            for (int np : { 5, usable }) {
                torch::manual_seed(11);
                encoder_settings es;
                es.kind = kind;
                es.free_scores = true;
                semantic_encoder enc(np, n, m, es, false, guards);
                for (double temp : { 1e-3, 1.0 })
                    for (bool hard : { true, false }) {
                        const auto sel = enc->sample(temp, hard);
                        CPPUNIT_ASSERT(all_finite(sel));
                        const auto grid = sel.sum(0).view({ n, m });
                        for (int g : guards)
                            CPPUNIT_ASSERT_EQUAL(0.0f, grid.select(1, g).abs().sum().item<float>());
                        // The gradient reaches the scores and stays finite.
                        if (hard) {
                            for (auto& p : enc->parameters())
                                p.mutable_grad() = torch::Tensor();
                            (sel * torch::randn_like(sel)).sum().backward();
                            for (auto& p : enc->parameters())
                                if (p.grad().defined())
                                    CPPUNIT_ASSERT(all_finite(p.grad()));
                        }
                    }
                const auto f = enc->final_indices();
                CPPUNIT_ASSERT_EQUAL(size_t(np), std::set<int64_t>(f.begin(), f.end()).size());
                for (auto i : f)
                    CPPUNIT_ASSERT(std::find(guards.begin(), guards.end(), int(i % m)) == guards.end());
            }
        encoder_settings es;
        CPPUNIT_ASSERT_THROW(semantic_encoder(usable + 1, n, m, es, false, guards), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(semantic_encoder(4, n, m, es, false, std::vector<int>{ 8 }), std::invalid_argument);
    }

    void encoder_forward_one_hot_at_floor()
    {
        for (const char* kind : { "gumbel_topk", "gumbel_heads" }) {
            torch::manual_seed(4);
            encoder_settings es;
            es.kind = kind;
            semantic_encoder enc(8, 4, 8, es);
            // Hard from the start: exact one-hot rows at the start temperature too.
            for (double t : { es.temperature_start, es.temperature_floor }) {
                auto s = enc->sample(t);
                CPPUNIT_ASSERT_EQUAL(int64_t(8), s.size(0));
                CPPUNIT_ASSERT_EQUAL(int64_t(32), s.size(1));
                assert_exact_one_hot(s);
                auto mask = semantic_encoder_module::mask_from_selection(s, 4, 8);
                CPPUNIT_ASSERT_EQUAL(8.0, mask.sum().item<double>());
            }
            // The soft warm-up sample: rows are distributions, not one-hot.
            auto soft = enc->sample(1.0, false);
            CPPUNIT_ASSERT(torch::allclose(soft.sum(1), torch::ones({ 8 }), 1e-5, 1e-5));
            CPPUNIT_ASSERT(soft.max().item<double>() < 1.0);
            auto pen = enc->collision_penalty(es.temperature_floor);
            CPPUNIT_ASSERT(all_finite(pen) && pen.item<double>() >= -1e-6);
        }
    }

    void topk_distinct_and_finite_at_extremes()
    {
        torch::manual_seed(11);
        const int n = 256, k = 32;
        auto huge = torch::where(torch::rand({ n }) > 0.5, torch::full({ n }, 1e4), torch::full({ n }, -1e4));
        for (const auto& z : { huge, torch::zeros({ n }), torch::full({ n }, 1e4), torch::randn({ n }) * 1e4 })
            for (double temp : { 1e-3, 0.1, 1.0, 1e3 })
                for (double u : { -1.0, 0.0, 1.0, 0.5 }) {
                    auto zz = z.clone().requires_grad_(true);
                    auto uni = u < 0 ? torch::Tensor() : torch::full({ n }, u);
                    auto s = gumbel_topk_st(zz, k, temp, uni);
                    CPPUNIT_ASSERT(all_finite(s));
                    assert_exact_one_hot(s);
                    // k distinct elements: the column sums are 0/1 and add up to k.
                    auto cols = s.sum(0);
                    CPPUNIT_ASSERT((cols.eq(0.0f) | cols.eq(1.0f)).all().item<bool>());
                    CPPUNIT_ASSERT_EQUAL(double(k), cols.sum().item<double>());
                    (s * torch::randn({ k, n })).sum().backward();
                    CPPUNIT_ASSERT(all_finite(zz.grad()));
                    auto soft = gumbel_topk_st(z, k, temp, uni, false);
                    CPPUNIT_ASSERT(all_finite(soft));
                    CPPUNIT_ASSERT(torch::allclose(soft.sum(1), torch::ones({ k }), 1e-4, 1e-4));
                }
        // The picks are the k largest of z + g: with g equal everywhere, the k largest of z.
        auto z = torch::randn({ n });
        auto s = gumbel_topk_st(z, k, 1.0, torch::full({ n }, 0.5));
        auto picked = std::get<1>(s.sum(0).topk(k)).sort();
        auto want = std::get<1>(z.topk(k)).sort();
        CPPUNIT_ASSERT(torch::equal(std::get<0>(picked), std::get<0>(want)));
        // Moderate scores: a non-zero gradient reaches them.
        auto z0 = torch::zeros({ 64 }, torch::requires_grad());
        (gumbel_topk_st(z0, 8, 1.0) * torch::randn({ 8, 64 })).sum().backward();
        CPPUNIT_ASSERT(z0.grad().abs().sum().item<double>() > 0.0);
        CPPUNIT_ASSERT_THROW(gumbel_topk_st(z, 0, 1.0), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(gumbel_topk_st(z, n + 1, 1.0), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(gumbel_topk_st(z, k, 0.0), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(gumbel_topk_st(torch::full({ n }, NAN), k, 1.0), std::invalid_argument);
    }

    // The O(K) mask equals the dense k x K selection's column sums: exactly forward, and its
    // relaxed values and gradients to float rounding, with guard elements (−inf) and at the
    // extremes of temperature and score; the same draws from the global generator.
    void topk_mask_equals_the_dense_column_sums()
    {
        torch::manual_seed(5);
        const int n = 300, k = 40;
        auto guarded = torch::randn({ n });
        guarded.slice(0, 0, 20).fill_(-std::numeric_limits<float>::infinity());
        for (const auto& z : { torch::randn({ n }), guarded, torch::randn({ n }) * 30.0 })
            for (double temp : { 1e-2, 0.3, 1.0, 1e2 })
                for (bool hard : { true, false }) {
                    const auto uni = torch::rand({ n });
                    auto zd = z.clone().requires_grad_(true), zm = z.clone().requires_grad_(true);
                    const auto dense = gumbel_topk_st(zd, k, temp, uni, hard).sum(0);
                    const auto mask = gumbel_topk_mask_st(zm, k, temp, uni, hard);
                    CPPUNIT_ASSERT(all_finite(mask));
                    // Float rounding of the logits (z + g)/τ, of size R, is about R·2^-23 in each
                    // exponent: the two orders of summation agree to that, relative to the scale.
                    const auto finite = z.masked_select(torch::isfinite(z));
                    const double reach = 1.0 + (finite.abs().max().item<double>() + 15.0) / temp;
                    auto agree = [&](const torch::Tensor& x, const torch::Tensor& y, const char* what) {
                        const double scale = x.abs().max().item<double>();
                        const double diff = (x - y).abs().max().item<double>();
                        CPPUNIT_ASSERT_MESSAGE(std::string(what) + " at temperature " + std::to_string(temp) +
                                                   " differ by " + std::to_string(diff) + " at scale " +
                                                   std::to_string(scale),
                                               diff <= 64 * 1.19e-7 * reach * scale + 1e-7);
                    };
                    if (hard)
                        CPPUNIT_ASSERT(torch::equal(dense, mask));
                    else
                        agree(dense, mask, "relaxed column sums");
                    const auto w = torch::randn({ n });
                    (dense * w).sum().backward();
                    (mask * w).sum().backward();
                    CPPUNIT_ASSERT(all_finite(zm.grad()));
                    agree(zd.grad(), zm.grad(), "gradients");
                }
        torch::manual_seed(9);
        const auto a = gumbel_topk_st(torch::randn({ n }), k, 1.0).sum(0);
        torch::manual_seed(9);
        const auto b = gumbel_topk_mask_st(torch::randn({ n }), k, 1.0);
        CPPUNIT_ASSERT(torch::equal(a, b));
        CPPUNIT_ASSERT_THROW(gumbel_topk_mask_st(torch::randn({ n }), 0, 1.0), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(gumbel_topk_mask_st(torch::randn({ n }), k, -1.0), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(gumbel_topk_mask_st(torch::full({ n }, NAN), k, 1.0), std::invalid_argument);
    }

    void topk_encoder_mask_is_exactly_np_distinct()
    {
        for (bool free : { false, true }) {
            torch::manual_seed(12);
            encoder_settings es;
            es.free_scores = free;
            semantic_encoder enc(32, 32, 64, es);
            // Fresh (all-zero scores), then extreme scores: every row wants the same subcarrier.
            for (double scale : { 0.0, 1e4 }) {
                {
                    torch::NoGradGuard ng;
                    for (auto& p : enc->parameters())
                        p.copy_(torch::randn(p.sizes()) * scale);
                    if (scale > 0)
                        enc->named_parameters()["subcarrier_scores"][5].fill_(1e6);
                }
                auto f = enc->final_indices();
                std::set<int64_t> u(f.begin(), f.end());
                CPPUNIT_ASSERT_EQUAL(size_t(32), u.size());
                CPPUNIT_ASSERT(*u.begin() >= 0 && *u.rbegin() < 32 * 64);
                auto mask = semantic_encoder_module::mask_from_selection(enc->sample(1e-3), 32, 64);
                CPPUNIT_ASSERT(all_finite(mask));
                CPPUNIT_ASSERT((mask.eq(0.0f) | mask.eq(1.0f)).all().item<bool>());
                CPPUNIT_ASSERT_EQUAL(32.0, mask.sum().item<double>());
                if (scale > 0) // subcarrier 5 over all 32 symbols
                    CPPUNIT_ASSERT_EQUAL(32.0, mask.select(1, 5).sum().item<double>());
            }
        }
        encoder_settings bad;
        bad.kind = "magic";
        CPPUNIT_ASSERT_THROW(semantic_encoder(4, 4, 4, bad), std::invalid_argument);
    }

    void mti_removes_static_path_exactly()
    {
        // A noiseless frame of the channel model: one static path (clutter: zero Doppler)
        // plus a moving target with micro-Doppler, on a random mask.
        frame_settings fs;
        channel_path clutter;
        clutter.delay_s = fs.delay_from_range(73.0);
        clutter.gain = { 3.0, -2.0 }; // 10x the target's power
        channel_path target;
        target.delay_s = fs.delay_from_range(120.0);
        target.doppler_hz = fs.doppler_from_velocity(7.0);
        target.md_rate_hz = 100.0;
        target.md_amplitude_m = 0.01;
        target.gain = { 0.6, 0.8 };
        const int n = fs.n_symbols, m = fs.n_subcarriers, g = fs.grid_size();
        auto grid_of = [&](const std::vector<channel_path>& paths) {
            std::vector<gr_complex> h(g);
            frame_channel(fs, paths, 1234).fill(h.data());
            auto t = torch::from_blob(h.data(), { n, m, 2 }, torch::kFloat).clone();
            return t.permute({ 2, 0, 1 }).unsqueeze(0).contiguous(); // 1 x 2 x N x M
        };
        torch::manual_seed(13);
        auto mask = torch::zeros({ n * m });
        mask.index_fill_(0, torch::randperm(n * m).slice(0, 0, 400), 1.0f);
        mask = mask.view({ n, m });
        const auto both = grid_of({ clutter, target }) * mask;
        const auto only_static = grid_of({ clutter }) * mask;
        const auto only_target = grid_of({ target }) * mask;
        // The static path alone: removed (float rounding of |H| ~ 3.6 only).
        CPPUNIT_ASSERT(remove_zero_doppler(only_static, mask).abs().max().item<double>() < 1e-5);
        // Static + moving: exactly what the moving target alone gives.
        CPPUNIT_ASSERT(torch::allclose(remove_zero_doppler(both, mask), remove_zero_doppler(only_target, mask), 0, 1e-5));
        // ... which is not zero, and zero off the mask.
        CPPUNIT_ASSERT(remove_zero_doppler(only_target, mask).abs().max().item<double>() > 0.1);
        CPPUNIT_ASSERT_EQUAL(0.0, (remove_zero_doppler(both, mask) * (1 - mask)).abs().max().item<double>());
        // The decoder with mti = "mean" sees the same profile with and without the clutter;
        // with "none" it does not.
        classifier_settings cs;
        cs.mti = "mean";
        spectral_classifier_decoder_module mti(n, m, 400, cs);
        CPPUNIT_ASSERT(torch::allclose(mti.profile(both, mask), mti.profile(only_target, mask), 1e-3, 1e-3));
        cs.mti = "none";
        spectral_classifier_decoder_module raw(n, m, 400, cs);
        CPPUNIT_ASSERT(!torch::allclose(raw.profile(both, mask), raw.profile(only_target, mask), 1e-2, 1e-2));
    }

    // The inference shortcuts compute what the training path computes: the occupied
    // columns only (dense grid and compact grid), the small convolutions as dense circulant
    // products (refreshed when the weights change), the large ones through conv1d.
    void spectral_decoder_inference_paths_match()
    {
        torch::manual_seed(15);
        const int n = 32, m = 64, np = 32;
        auto mask = torch::zeros({ n, m });
        mask.select(1, 14).slice(0, 0, 15).fill_(1.0f);
        mask.select(1, 17).slice(0, 15, 32).fill_(1.0f);
        const auto cols = torch::tensor({ 14, 17 }, torch::kLong);
        for (int range_bins : { 0, -1 })
        for (int width : { 4, 16 }) { // 4: both convolutions dense; 16: the second through conv1d
            for (const char* mti : { "none", "both" }) {
                classifier_settings cs;
                cs.width = width;
                cs.mti = mti;
                cs.doppler_bins = 32;
                cs.range_bins = range_bins;
                spectral_classifier_decoder_module dec(n, m, np, cs);
                dec.eval();
                if (range_bins != 0) { // the gate's phases need the compact columns' subcarriers
                    torch::NoGradGuard ng;
                    CPPUNIT_ASSERT_THROW(dec.forward(torch::zeros({ 1, 2, n, 2 }), mask.index_select(1, cols).contiguous()),
                                         std::invalid_argument);
                }
                dec.set_compact_columns({ 14, 17 });
                {
                    torch::NoGradGuard ng; // trained-looking BatchNorm statistics (folded at inference)
                    for (auto& b : dec.named_buffers()) {
                        if (b.key().find("running_mean") != std::string::npos)
                            b.value().uniform_(-1.0, 1.0);
                        if (b.key().find("running_var") != std::string::npos)
                            b.value().uniform_(0.5, 2.0);
                    }
                }
                auto mask_used = mask;
                auto grid = torch::randn({ 5, 2, n, m }) * mask;
                if (range_bins != 0) {
                    // The gate picks the delay bin by energy. On this mask the two subcarriers
                    // share no symbol, so by Parseval the energy is the same in every bin (the
                    // cross term Σ_n y14[n] y17*[n] is empty) and rounding picks the bin: the
                    // two paths may differ. With a few shared symbols the energy has one
                    // maximum and the paths must agree.
                    auto shared = mask.clone();
                    shared.select(1, 14).slice(0, 15, 20).fill_(1.0f);
                    grid = torch::randn({ 5, 2, n, m }) * shared;
                    mask_used = shared;
                }
                grid.requires_grad_(true); // the reference: the dense path with autograd on
                const auto ref = dec.forward(grid, mask_used).logits.detach();
                torch::NoGradGuard ng;
                const auto dense = dec.forward(grid.detach(), mask_used).logits;
                const auto compact = dec.forward(grid.detach().index_select(3, cols).contiguous(),
                                                 mask_used.index_select(1, cols).contiguous()).logits;
                const double rtol = 1e-4, atol = 1e-5;
                const auto diff = [&](const torch::Tensor& a) {
                    return "range_bins " + std::to_string(range_bins) + " width " + std::to_string(width) + " mti " +
                           mti + ": max |diff| " + std::to_string((a - ref).abs().max().item<double>());
                };
                CPPUNIT_ASSERT_MESSAGE(diff(dense), torch::allclose(dense, ref, rtol, atol));
                CPPUNIT_ASSERT_MESSAGE(diff(compact), torch::allclose(compact, ref, rtol, atol));
                // New weights: the cached dense matrices follow them.
                for (auto& p : dec.parameters())
                    p.add_(0.1 * torch::randn_like(p));
                grid.requires_grad_(false);
                torch::Tensor ref2;
                {
                    torch::AutoGradMode on(true);
                    auto g2 = grid.detach().clone().requires_grad_(true);
                    ref2 = dec.forward(g2, mask_used).logits.detach();
                }
                CPPUNIT_ASSERT(!torch::allclose(ref2, ref, 1e-3, 1e-3));
                CPPUNIT_ASSERT(torch::allclose(dec.forward(grid, mask_used).logits, ref2, rtol, atol));
            }
        }
    }

    void spectral_decoder_phase_invariant_on_any_mask()
    {
        torch::manual_seed(14);
        const int n = 16, m = 24, np = 40;
        for (const int range_bins : { 0, -1 })
        for (const char* mti : { "none", "mean", "both" }) {
            classifier_settings cs;
            cs.mti = mti;
            cs.doppler_bins = 32;
            cs.range_bins = range_bins;
            spectral_classifier_decoder_module dec(n, m, np, cs);
            dec.eval();
            for (int trial = 0; trial < 3; ++trial) {
                auto mask = torch::zeros({ n * m });
                mask.index_fill_(0, torch::randperm(n * m).slice(0, 0, np), 1.0f);
                mask = mask.view({ n, m });
                auto grid = torch::randn({ 4, 2, n, m }) * mask;
                auto out = dec.forward(grid, mask);
                CPPUNIT_ASSERT_EQUAL(int64_t(3), out.logits.size(1));
                CPPUNIT_ASSERT_EQUAL(int64_t(16), out.features.size(1));
                // A phase per subcarrier (the target's delay: without the range gate any
                // phase per subcarrier, with it a delay ramp exp(-j2π m l0 / L) on the gate's
                // grid, which moves the target to another delay bin) and one per frame (its
                // gain), and a gain of 1e-20 or 1e20: the same answer.
                const auto mm = torch::arange(m, torch::kDouble).view({ 1, 1, 1, m });
                const auto l0 = torch::randint(0, 2 * m, { 4, 1, 1, 1 }, torch::kLong).to(torch::kDouble);
                auto per_subcarrier = range_bins == 0 ? torch::rand({ 4, 1, 1, m }) * 2 * M_PI
                                                      : (-2 * M_PI / (2 * m) * torch::remainder(mm * l0, 2 * m)).to(torch::kFloat);
                auto phase = per_subcarrier + torch::rand({ 4, 1, 1, 1 }) * 2 * M_PI;
                auto re = grid.select(1, 0).unsqueeze(1), im = grid.select(1, 1).unsqueeze(1);
                auto c = torch::cos(phase), s = torch::sin(phase);
                auto rotated = torch::cat({ re * c - im * s, re * s + im * c }, 1);
                for (double a : { 1.0, 1e-20, 1e20 }) {
                    auto o = dec.forward(rotated * a, mask);
                    CPPUNIT_ASSERT(all_finite(o.logits));
                    CPPUNIT_ASSERT(torch::allclose(o.logits, out.logits, 1e-3, 1e-3));
                }
            }
            // The per-frame mask form gives the same as the shared one.
            auto mask = torch::zeros({ n, m });
            mask.select(1, 3).fill_(1.0f);
            auto grid = torch::randn({ 2, 2, n, m }) * mask;
            CPPUNIT_ASSERT(torch::allclose(dec.forward(grid, mask).logits,
                                           dec.forward(grid, mask.unsqueeze(0).expand({ 2, n, m })).logits, 1e-5, 1e-5));
            CPPUNIT_ASSERT_THROW(dec.forward(grid), std::invalid_argument);
            CPPUNIT_ASSERT_THROW(dec.forward(grid, torch::ones({ n + 1, m })), std::invalid_argument);
        }
        classifier_settings bad;
        bad.doppler_bins = n - 1;
        CPPUNIT_ASSERT_THROW(spectral_classifier_decoder_module(n, m, np, bad), std::invalid_argument);
        bad = classifier_settings{};
        bad.range_bins = -2;
        CPPUNIT_ASSERT_THROW(spectral_classifier_decoder_module(n, m, np, bad), std::invalid_argument);
        bad = classifier_settings{};
        bad.mti = "median";
        CPPUNIT_ASSERT_THROW(spectral_classifier_decoder_module(n, m, np, bad), std::invalid_argument);
    }

    void spectral_range_gate_closed_forms()
    {
        // One target on an on-grid Doppler bin k0 and delay bin l0 (noiseless):
        // y[n,m] = exp(j2π k0 n / K) exp(-j2π m l0 / L) on the mask's elements.
        const int n = 16, m = 12, k = 32, l = 2 * m, k0 = 5, l0 = 7;
        classifier_settings gated, pooled;
        gated.doppler_bins = pooled.doppler_bins = k;
        gated.range_bins = -1; // resolves to 2·M
        pooled.range_bins = 0;
        spectral_classifier_decoder_module g(n, m, 2 * n, gated), p(n, m, 2 * n, pooled);
        CPPUNIT_ASSERT_EQUAL(l, g.settings().range_bins);
        CPPUNIT_ASSERT_EQUAL(l, g.describe()["settings"]["range_bins"].get<int>());
        auto frame = [&](const torch::Tensor& mask) {
            const auto nn = torch::arange(n, torch::kDouble).view({ n, 1 });
            const auto mm = torch::arange(m, torch::kDouble).view({ 1, m });
            const auto ph = 2 * M_PI * (torch::remainder(nn * k0, k) / k - torch::remainder(mm * l0, l) / l);
            return torch::stack({ torch::cos(ph), torch::sin(ph) }, 0).to(torch::kFloat).unsqueeze(0) * mask;
        };
        // One subcarrier: the gate has nothing to combine, the profiles are equal.
        auto one = torch::zeros({ n, m });
        one.select(1, 4).fill_(1.0f);
        CPPUNIT_ASSERT(torch::allclose(g.profile(frame(one), one), p.profile(frame(one), one), 1e-5, 1e-5));
        // Two subcarriers: coherent |2F|² against pooled 2|F|², the same shape after the
        // per-frame normalisation; the peak at k0 in both.
        auto two = one.clone();
        two.select(1, 9).fill_(1.0f);
        const auto pg = g.profile(frame(two), two), pp = p.profile(frame(two), two);
        CPPUNIT_ASSERT(torch::allclose(pg, pp, 1e-4, 1e-4));
        CPPUNIT_ASSERT_EQUAL(int64_t(k0), pg.flatten().argmax().item<int64_t>());
        // A mask that carries a gradient (the encoder's, while it learns) gives the same
        // profile as the fixed mask, whose empty subcarriers the decoder skips.
        auto learning = two.clone().requires_grad_(true);
        CPPUNIT_ASSERT(torch::allclose(g.profile(frame(two), learning), pg, 1e-5, 1e-5));
    }

    // From 128 subcarriers the range gate is an inverse FFT (with the subcarriers folded
    // modulo L when L < M). Its profile against the gate's formula evaluated directly in
    // double precision, R[k,l] = Σ_m F[k,m] exp(+j2π m l / L) on a random frame, with L = 2·M
    // and with L = 100 < M; on a compact grid of a few subcarriers; and its gradient.
    void spectral_range_gate_by_fft_on_large_frames()
    {
        const int n = 8, m = 320, k = 16;
        torch::manual_seed(3);
        for (const int range_bins : { -1, 100 }) {
            classifier_settings cs;
            cs.doppler_bins = k;
            cs.range_bins = range_bins;
            cs.mti = "none";
            cs.chirp_bins = 0;
            spectral_classifier_decoder_module dec(n, m, n * m, cs);
            const int l = dec.settings().range_bins;
            auto expected = [&](const torch::Tensor& grid, const torch::Tensor& mask) {
                const auto y = torch::complex(grid.select(1, 0), grid.select(1, 1)).to(torch::kComplexDouble) *
                               mask.to(torch::kDouble); // B x N x M
                const auto kn = torch::remainder(torch::arange(k, torch::kLong).unsqueeze(1) *
                                                 torch::arange(n, torch::kLong).unsqueeze(0), k).to(torch::kDouble);
                const auto dft = torch::polar(torch::ones_like(kn), -2 * M_PI * kn / k); // K x N
                const auto ml = torch::remainder(torch::arange(m, torch::kLong).unsqueeze(1) *
                                                 torch::arange(l, torch::kLong).unsqueeze(0), l).to(torch::kDouble);
                const auto gate = torch::polar(torch::ones_like(ml), 2 * M_PI * ml / l); // M x L
                const auto r = torch::matmul(torch::matmul(dft, y), gate); // B x K x L
                const auto p = r.abs().square();
                const auto best = p.sum(1).argmax(1);
                auto sk = p.gather(2, best.view({ -1, 1, 1 }).expand({ p.size(0), k, 1 })).squeeze(2);
                return torch::log(sk / sk.mean(1, true) + 1e-3).unsqueeze(1).to(torch::kFloat);
            };
            const auto mask = (torch::rand({ n, m }) < 0.5).to(torch::kFloat);
            const auto grid = torch::randn({ 3, 2, n, m }) * mask;
            const auto what = "range_bins " + std::to_string(range_bins);
            CPPUNIT_ASSERT_MESSAGE(what, torch::allclose(dec.profile(grid, mask), expected(grid, mask), 1e-4, 1e-4));
            // Pilots on three subcarriers only: the decoder transforms those columns, and
            // the FFT puts them back on their subcarriers.
            auto few = torch::zeros({ n, m });
            for (int c : { 5, 170, 311 })
                few.select(1, c).fill_(1.0f);
            const auto sparse = torch::randn({ 3, 2, n, m }) * few;
            CPPUNIT_ASSERT_MESSAGE(what, torch::allclose(dec.profile(sparse, few), expected(sparse, few), 1e-4, 1e-4));
            // While a mask is learned the gradient flows through the FFT to every element.
            auto learning = mask.clone().requires_grad_(true);
            auto g = grid.clone().requires_grad_(true);
            dec.profile(g * learning, learning).sum().backward();
            CPPUNIT_ASSERT_MESSAGE(what, g.grad().defined() && torch::isfinite(g.grad()).all().item<bool>() &&
                                             g.grad().abs().sum().item<double>() > 0);
        }
    }

    // The tone/chirp fit against closed forms (noiseless): a pure tone anywhere between the
    // DFT bins is explained entirely at α = 0 (share 1, feature log 1e-4) and not by the
    // other rates (for a tone of N samples against a chirp of edge phase π α (N/2)², the
    // share is |Σ_n exp(-jπ α c_n²)|² / N², maximised over f); a chirp of the fit's largest
    // rate is explained at that rate only; with and without the range gate, on one
    // subcarrier and on a mask spread over several (each with the target's delay phase); a
    // zero frame and extreme gains stay finite.
    void tone_fit_closed_forms()
    {
        const int n = 32, m = 12;
        for (const int range_bins : { 0, -1 }) {
            classifier_settings cs;
            cs.range_bins = range_bins;
            cs.chirp_bins = 5;
            cs.chirp_sweep_bins = 2.0;
            spectral_classifier_decoder_module dec(n, m, 2 * n, cs);
            dec.eval();
            const auto rates = cs.chirp_rates(n);
            CPPUNIT_ASSERT_EQUAL(size_t(5), rates.size());
            CPPUNIT_ASSERT_EQUAL(0.0, rates[2]);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(2.0 / (n * n), rates[4], 1e-15);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(-rates[4], rates[0], 1e-15);
            auto mask = torch::zeros({ n, m });
            mask.select(1, 3).fill_(1.0f);
            mask.select(1, 8).slice(0, 0, n, 2).fill_(1.0f); // a second subcarrier on every other symbol
            const double delay = 2.3;                         // delay index (off the gate's grid)
            auto frame = [&](double f, double alpha) {
                const auto nn = torch::arange(n, torch::kDouble).view({ n, 1 });
                const auto mm = torch::arange(m, torch::kDouble).view({ 1, m });
                const auto c = nn - 0.5 * (n - 1);
                const auto ph = 2 * M_PI * f * nn + M_PI * alpha * c.square() - 2 * M_PI * mm * delay / m + 0.7;
                return torch::stack({ torch::cos(ph), torch::sin(ph) }, 0).to(torch::kFloat).unsqueeze(0) * mask;
            };
            // The share a pure tone leaves to the rate α (maximised over f on a fine grid).
            auto tone_share = [&](double alpha) {
                double best = 0.0;
                const auto c = torch::arange(n, torch::kDouble) - 0.5 * (n - 1);
                for (int i = -200; i <= 200; ++i) {
                    const auto ph = 2 * M_PI * (i * 1e-4) * torch::arange(n, torch::kDouble) + M_PI * alpha * c.square();
                    const double re = torch::cos(ph).sum().item<double>(), im = torch::sin(ph).sum().item<double>();
                    best = std::max(best, (re * re + im * im) / (double(n) * n));
                }
                return best;
            };
            torch::NoGradGuard ng;
            for (const double f : { 0.0, 0.123456, -0.31, 0.4999 }) {
                const auto t = dec.tone_features(frame(f, 0.0), mask);
                CPPUNIT_ASSERT_EQUAL(int64_t(5), t.size(1));
                // share 1 at α = 0: log(1e-4), to the search's precision (share > 1 - 2e-5)
                CPPUNIT_ASSERT_MESSAGE("range_bins " + std::to_string(range_bins) + ", tone at f " + std::to_string(f) + ": " + c10::str(t),
                                       t[0][2].item<double>() < std::log(3e-5 + 1e-4));
                for (int j : { 0, 1, 3, 4 }) {
                    const double want = std::log(1.0 - tone_share(rates[j]) + 1e-4);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(want, t[0][j].item<double>(), 0.02);
                }
            }
            // A chirp of the largest rate (edge phase π/2), at an off-grid frequency.
            const auto t = dec.tone_features(frame(0.2, rates[4]), mask);
            CPPUNIT_ASSERT(t[0][4].item<double>() < std::log(3e-5 + 1e-4));
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::log(1.0 - tone_share(rates[4]) + 1e-4), t[0][2].item<double>(), 0.02);
            CPPUNIT_ASSERT(t[0][2].item<double>() > std::log(0.05));
            // Extremes: a zero frame (share 0: log(1 + 1e-4)) and gains of 1e-20 and 1e20.
            const auto z = dec.tone_features(torch::zeros({ 1, 2, n, m }), mask);
            CPPUNIT_ASSERT(all_finite(z));
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::log(1.0 + 1e-4), z.max().item<double>(), 1e-6);
            for (const double a : { 1e-20, 1e20 }) {
                const auto ta = dec.tone_features(frame(0.123456, 0.0) * a, mask);
                CPPUNIT_ASSERT(all_finite(ta));
                CPPUNIT_ASSERT(torch::allclose(ta, dec.tone_features(frame(0.123456, 0.0), mask), 1e-3, 1e-3));
            }
        }
        // Off: no features and the legacy network (no tone layers in the state).
        classifier_settings off;
        off.chirp_bins = 0;
        spectral_classifier_decoder_module legacy(n, m, 2 * n, off);
        CPPUNIT_ASSERT(!legacy.tone_features(torch::zeros({ 1, 2, n, m }), torch::ones({ n, m })).defined());
        for (const auto& p : legacy.named_parameters())
            CPPUNIT_ASSERT(p.key().find("tone") == std::string::npos);
        for (const int bad : { 2, -1 }) {
            off.chirp_bins = bad;
            CPPUNIT_ASSERT_THROW(spectral_classifier_decoder_module(n, m, 2 * n, off), std::invalid_argument);
        }
        off.chirp_bins = 3;
        off.chirp_sweep_bins = 0.0;
        CPPUNIT_ASSERT_THROW(spectral_classifier_decoder_module(n, m, 2 * n, off), std::invalid_argument);
    }

    // chirp_min_pilots: some chirp with a gain and phase of its own explains one pilot (and,
    // at the best frequency, two) exactly, so a noise frame on one- or two-pilot subcarriers
    // reads as a pure tone unless they are left out. With the rule they add nothing: the
    // features equal those of the mask without them; subcarriers with exactly the minimum count.
    void tone_fit_counts_subcarriers_with_enough_pilots()
    {
        const int n = 32, m = 12;
        torch::manual_seed(11);
        const auto noise = torch::randn({ 1, 2, n, m });
        // The fit's features of `frame` (default: the noise) on `mask`.
        auto features = [&](int min_pilots, const torch::Tensor& mask, const torch::Tensor& frame = {}) {
            classifier_settings cs;
            cs.chirp_bins = 5;
            cs.chirp_min_pilots = min_pilots;
            spectral_classifier_decoder_module dec(n, m, 2 * n, cs);
            dec.eval();
            torch::NoGradGuard ng;
            return dec.tone_features((frame.defined() ? frame : noise) * mask, mask);
        };
        const double explained = std::log(3e-5 + 1e-4), nothing = std::log(1.0 + 1e-4);
        // One pilot per subcarrier (one symbol): all "explained" when counted, nothing when not.
        auto one_symbol = torch::zeros({ n, m });
        one_symbol.select(0, 5).fill_(1.0f);
        CPPUNIT_ASSERT_MESSAGE(c10::str(features(1, one_symbol)), features(1, one_symbol).max().item<double>() < explained);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(nothing, features(3, one_symbol).min().item<double>(), 1e-6);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(nothing, features(3, one_symbol).max().item<double>(), 1e-6);
        // Two pilots per subcarrier: left out with 3, counted with 2.
        auto two_symbols = one_symbol.clone();
        two_symbols.select(0, 17).fill_(1.0f);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(nothing, features(3, two_symbols).max().item<double>(), 1e-6);
        CPPUNIT_ASSERT(features(2, two_symbols).max().item<double>() < nothing - 0.05);
        // A full subcarrier with a noisy tone plus one-pilot subcarriers of noise: with the
        // rule, the features of the full subcarrier alone (the search starts from the same
        // profile peak, the tone's); without, larger shares (smaller features) at every rate.
        auto full = torch::zeros({ n, m });
        full.select(1, 3).fill_(1.0f);
        auto mixed = full.clone();
        mixed.select(0, 9).slice(0, 5, m).fill_(1.0f);
        const auto ph = 2 * M_PI * 0.2137 * torch::arange(n, torch::kFloat);
        auto frame = noise.clone();
        frame.select(3, 3) = torch::stack({ torch::cos(ph), torch::sin(ph) }, 0).unsqueeze(0) + 0.3 * noise.select(3, 3);
        const auto alone = features(3, full, frame), with_rule = features(3, mixed, frame),
                   without_rule = features(1, mixed, frame);
        CPPUNIT_ASSERT_MESSAGE(c10::str(with_rule) + " vs " + c10::str(alone), torch::allclose(with_rule, alone, 1e-5, 1e-5));
        CPPUNIT_ASSERT_MESSAGE(c10::str(without_rule) + " vs " + c10::str(alone),
                               (without_rule < alone - 0.01).all().item<bool>());
        // Exactly the minimum counts: three pilots on one subcarrier, min 3 vs min 4.
        auto three = torch::zeros({ n, m });
        three.select(1, 7).slice(0, 0, 3).fill_(1.0f);
        CPPUNIT_ASSERT(features(3, three).max().item<double>() < nothing - 1e-3);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(nothing, features(4, three).max().item<double>(), 1e-6);
        // A minimum below 1 is refused.
        classifier_settings bad;
        bad.chirp_min_pilots = 0;
        CPPUNIT_ASSERT_THROW(spectral_classifier_decoder_module(n, m, 2 * n, bad), std::invalid_argument);
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
