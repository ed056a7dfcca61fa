// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the delay decoder — receptive field of the dilated stack, legacy bundle
 * settings, the refinement stage wired to the baselines' least-squares fit (and off in
 * training), its second starts (the grid peak with one path, the oracle-order reference with
 * several), the residual maps, and the trainer's refusal of a network that cannot see
 * from the first path to the last. */
#include "learning/networks/delay_decoder.h"
#include "learning/networks/grid_omp.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/baselines/ls_delay_estimator.h>
#include <gnuradio/sems/baselines/multipath_fit.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/learning/training/trainer.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <numeric>
#include <random>

using namespace gr::sems;
using namespace gr::sems::nn;

namespace {

const frame_settings fs{};

// 32 subcarriers (every other one, shifted) on symbol 5, in mask order.
std::vector<int64_t> one_symbol_positions()
{
    std::vector<int64_t> flat;
    for (int m = 1; m < fs.n_subcarriers; m += 2)
        flat.push_back(5 * fs.n_subcarriers + m);
    return flat;
}

// B noisy frames of a random scene with `paths` paths per target: the truths, the whole
// channel (B x 2 x N x M) and the sparse decoder grid of the pilots at `flat`.
struct noisy_frames {
    std::vector<frame_truth> truths;
    torch::Tensor all, grid;
};
noisy_frames scene_frames(int paths, uint64_t seed, int b, const std::vector<int64_t>& flat, double snr_db)
{
    random_spec r;
    r.paths_per_target = paths;
    channel_model cm(fs, scene::random(r), seed);
    std::vector<gr_complex> h(size_t(b) * fs.grid_size());
    noisy_frames out;
    out.truths = cm.generate(b, h.data());
    cm.add_noise(h.data(), h.size(), snr_db);
    out.all = torch::from_blob(h.data(), { b, fs.n_symbols, fs.n_subcarriers, 2 }, torch::kFloat)
                  .permute({ 0, 3, 1, 2 })
                  .contiguous(); // a copy: h may go
    out.grid = scatter_pilots(gather_pilots(out.all, flat), flat, fs.n_symbols, fs.n_subcarriers);
    return out;
}

// B noisy frames of a 3-path random scene as the sparse decoder grid (B x 2 x N x M).
torch::Tensor frames(int b, const std::vector<int64_t>& flat, double snr_db)
{
    return scene_frames(3, 11, b, flat, snr_db).grid;
}

delay_settings small(int refine_paths)
{
    delay_settings s;
    s.tau_min_index = -2.0;
    s.tau_max_index = 48.0;
    s.q = 201;
    s.refine_paths = refine_paths;
    s.refine_span_index = 7.0;
    s.refine_trust_index = 0.5;
    s.refine_global_fit = false; // the test of the second start sets it
    return s;
}

} // namespace

class qa_learning_delay : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_learning_delay);
    CPPUNIT_TEST(receptive_field_closed_form);
    CPPUNIT_TEST(legacy_settings_keep_the_old_network);
    CPPUNIT_TEST(refinement_is_the_anchored_least_squares_fit);
    CPPUNIT_TEST(single_path_refinement_takes_the_better_fit);
    CPPUNIT_TEST(multipath_refinement_takes_the_reference_when_it_fits_better);
    CPPUNIT_TEST(residual_maps_remove_the_strongest_atom);
    CPPUNIT_TEST(residual_maps_match_the_operator_form);
    CPPUNIT_TEST(folded_network_matches_the_modules);
    CPPUNIT_TEST(bad_settings_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    void receptive_field_closed_form()
    {
        delay_settings s;
        s.kernel = 3;
        s.depth = 6;
        s.dilation_growth = 2;
        // stem 3 + Σ_i 2·(3 − 1)·2^i, i = 0..5 = 3 + 4·63
        CPPUNIT_ASSERT_EQUAL(255, s.receptive_field_points());
        s.kernel = 5;
        s.depth = 2;
        s.dilation_growth = 1; // the legacy network: ±1.3 index at 0.125 spacing
        CPPUNIT_ASSERT_EQUAL(21, s.receptive_field_points());
        s.tau_min_index = 0.0;
        s.tau_max_index = 50.0;
        s.q = 401;
        CPPUNIT_ASSERT_DOUBLES_EQUAL(21 * 0.125, s.receptive_field_index(), 1e-12);
    }

    void legacy_settings_keep_the_old_network()
    {
        // A bundle written before the dilated decoder: none of the new keys.
        const nlohmann::json old = { { "tau_min_index", -2.0 }, { "tau_max_index", 42.0 }, { "q", 353 },
                                     { "projections", 2 },      { "width", 8 },           { "depth", 2 },
                                     { "kernel", 5 },           { "window", 8 } };
        const auto s = delay_settings::from_json(old, "old bundle.json");
        CPPUNIT_ASSERT_EQUAL(1, s.dilation_growth);
        CPPUNIT_ASSERT_EQUAL(false, s.phase_reference);
        CPPUNIT_ASSERT_EQUAL(0, s.residual_maps);
        CPPUNIT_ASSERT_EQUAL(0, s.refine_paths);
        CPPUNIT_ASSERT_EQUAL(false, s.refine_global_peak);
        CPPUNIT_ASSERT_EQUAL(false, s.refine_global_fit);
        CPPUNIT_ASSERT_EQUAL(true, delay_settings{}.refine_global_fit); // new networks have it
        // Its parameters have the old shapes (the stem sees 3P channels).
        delay_decoder_module d(fs.n_symbols, fs.n_subcarriers, 32, s);
        CPPUNIT_ASSERT(d.named_parameters()["stem.weight"].sizes() == torch::IntArrayRef({ 8, 6, 5 }));
        // New settings survive the bundle round trip.
        auto n = small(3);
        n.residual_maps = 2;
        const auto back = delay_settings::from_json(n.to_json(), "round trip");
        CPPUNIT_ASSERT_EQUAL(2, back.residual_maps);
        CPPUNIT_ASSERT_EQUAL(3, back.refine_paths);
        CPPUNIT_ASSERT_EQUAL(2, back.dilation_growth);
        CPPUNIT_ASSERT_EQUAL(true, back.phase_reference);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(7.0, back.refine_span_index, 0.0);
        CPPUNIT_ASSERT_EQUAL(true, back.refine_global_peak);
        CPPUNIT_ASSERT_EQUAL(0.0, back.refine_global_min_fraction);
        CPPUNIT_ASSERT_EQUAL(false, back.refine_global_fit);
        n.refine_global_peak = false;
        n.refine_global_min_fraction = 0.15;
        n.refine_global_fit = true;
        const auto back2 = delay_settings::from_json(n.to_json(), "round trip");
        CPPUNIT_ASSERT_EQUAL(false, back2.refine_global_peak);
        CPPUNIT_ASSERT_EQUAL(true, back2.refine_global_fit);
        CPPUNIT_ASSERT_EQUAL(0.15, back2.refine_global_min_fraction);
    }

    void single_path_refinement_takes_the_better_fit()
    {
        // An untrained network answers far from the path on most frames; the trust region
        // keeps those answers. With refine_global_peak the fit from the matched filter's
        // grid peak replaces them: on 40 dB single-path frames every answer is the path.
        const auto flat = one_symbol_positions();
        const int b = 32;
        const auto fr = scene_frames(1, 21, b, flat, 40.0);
        const auto& truths = fr.truths;
        const auto& all = fr.all;
        const auto& grid = fr.grid;
        // Every other subcarrier: delays 32 indices apart alias, so the dictionary stays below.
        auto s = small(1);
        s.tau_min_index = -1.0;
        s.tau_max_index = 30.0;
        s.q = 249;
        torch::NoGradGuard ng;
        auto errors = [&](bool global) {
            s.refine_global_peak = global;
            torch::manual_seed(4);
            delay_decoder_module d(fs.n_symbols, fs.n_subcarriers, 32, s);
            d.set_pilot_positions(fs, flat);
            d.eval();
            const auto out = d.forward(grid).delay_index.to(torch::kDouble);
            std::vector<double> e;
            for (int i = 0; i < b; ++i)
                e.push_back(std::abs(out[i].item<double>() - truths[size_t(i)].delay_index));
            return e;
        };
        const auto local = errors(false), global = errors(true);
        // A share no one-path fit can explain: the second fit never runs.
        s.refine_global_min_fraction = 0.999999;
        const auto skipped = errors(true);
        s.refine_global_min_fraction = 0.0;
        CPPUNIT_ASSERT(skipped == local);
        int far = 0, inside = 0;
        for (int i = 0; i < b; ++i) {
            if (truths[size_t(i)].delay_index > s.tau_max_index)
                continue; // outside the dictionary: not this test's question
            ++inside;
            far += local[size_t(i)] > 0.5;
            CPPUNIT_ASSERT_MESSAGE("frame " + std::to_string(i) + ": error " + std::to_string(global[size_t(i)]),
                                   global[size_t(i)] < 0.02);
        }
        CPPUNIT_ASSERT(inside >= 16);
        CPPUNIT_ASSERT_MESSAGE("untrained network far on " + std::to_string(far) + " frames", far >= inside / 2);
    }

    void multipath_refinement_takes_the_reference_when_it_fits_better()
    {
        // 32 random subcarriers of one symbol (no aliasing inside the window), 3-path frames
        // at 40 dB. An untrained network answers far from the direct path on most frames and
        // the trust region keeps those answers; with refine_global_fit the oracle-order
        // reference's fit replaces them where it explains the pilots better. Every answer is
        // then the network's refined one or exactly the reference's earliest delay.
        std::vector<int> sub(fs.n_subcarriers);
        std::iota(sub.begin(), sub.end(), 0);
        std::mt19937 rng(7);
        std::shuffle(sub.begin(), sub.end(), rng);
        sub.resize(32);
        std::sort(sub.begin(), sub.end());
        std::vector<int64_t> flat;
        std::vector<pilot_position> pos;
        for (int m : sub) {
            flat.push_back(5 * fs.n_subcarriers + m);
            pos.push_back({ 5, m });
        }
        const int b = 40;
        const auto fr = scene_frames(3, 23, b, flat, 40.0);
        const auto& truths = fr.truths;
        const auto& all = fr.all;
        const auto& grid = fr.grid;
        auto s = small(3);
        torch::NoGradGuard ng;
        auto answers = [&](bool global) {
            s.refine_global_fit = global;
            torch::manual_seed(4);
            delay_decoder_module d(fs.n_symbols, fs.n_subcarriers, 32, s);
            d.set_pilot_positions(fs, flat);
            d.eval();
            const auto out = d.forward(grid).delay_index.to(torch::kDouble);
            std::vector<double> a;
            for (int i = 0; i < b; ++i)
                a.push_back(out[i].item<double>());
            return a;
        };
        const auto off = answers(false), on = answers(true);
        // A share no fit can explain: the reference never runs.
        s.refine_global_min_fraction = 0.999999;
        CPPUNIT_ASSERT(answers(true) == off);
        s.refine_global_min_fraction = 0.0;
        // The reference the decoder builds: the same window, its grid spacing, the same order.
        ls_delay_estimator::settings ls;
        ls.search.oversample = 4; // 1 / spacing: (48 + 2) / 200
        ls.search.min_index = s.tau_min_index;
        ls.search.max_index = s.tau_max_index;
        ls.n_paths = 3;
        ls.fit.tolerance = 1e-7;
        const ls_delay_estimator reference(fs, pilot_mask(fs.n_symbols, fs.n_subcarriers, pos), ls);
        int far_off = 0, good_on = 0, moved = 0;
        for (int i = 0; i < b; ++i) {
            const double truth = truths[size_t(i)].delay_index;
            far_off += std::abs(off[size_t(i)] - truth) > 0.5;
            good_on += std::abs(on[size_t(i)] - truth) < 0.05;
            if (on[size_t(i)] == off[size_t(i)])
                continue;
            ++moved;
            const auto y = all[i].permute({ 1, 2, 0 }).contiguous(); // N x M x 2
            std::vector<gr_complex> obs;
            for (auto f : flat)
                obs.push_back(reinterpret_cast<const gr_complex*>(y.data_ptr<float>())[f]);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(reference.estimate_index(obs.data()), on[size_t(i)], 2e-3);
        }
        CPPUNIT_ASSERT_MESSAGE("untrained network far on " + std::to_string(far_off) + " frames", far_off >= b / 4);
        CPPUNIT_ASSERT_MESSAGE("reference taken on " + std::to_string(moved) + " frames", moved >= far_off - 2);
        CPPUNIT_ASSERT_MESSAGE("direct path within 0.05 on " + std::to_string(good_on) + " of " + std::to_string(b),
                               good_on >= b - 3);
    }

    void refinement_is_the_anchored_least_squares_fit()
    {
        const auto flat = one_symbol_positions();
        const auto grid = frames(24, flat, 30.0);
        torch::manual_seed(3);
        delay_decoder_module plain(fs.n_symbols, fs.n_subcarriers, 32, small(0));
        torch::manual_seed(3);
        delay_decoder_module refined(fs.n_symbols, fs.n_subcarriers, 32, small(3));
        torch::NoGradGuard ng;
        // Training mode: never refined, even with positions set.
        refined.set_pilot_positions(fs, flat);
        CPPUNIT_ASSERT(torch::equal(plain.forward(grid).delay_index, refined.forward(grid).delay_index));
        plain.eval();
        refined.eval();
        const auto est = plain.forward(grid).delay_index.to(torch::kDouble);
        const auto out = refined.forward(grid).delay_index.to(torch::kDouble);
        // The same answer from the baselines' fit on the decoder's normalised pilots.
        std::vector<pilot_position> pos;
        for (auto f : flat)
            pos.push_back({ int(f / fs.n_subcarriers), int(f % fs.n_subcarriers) });
        const multipath_fitter fitter(fs, pilot_mask(fs.n_symbols, fs.n_subcarriers, pos));
        auto obs = gather_pilots(normalise_frames(grid, 32), flat).contiguous();
        const auto* po = reinterpret_cast<const gr_complex*>(obs.data_ptr<float>());
        int moved = 0;
        for (int i = 0; i < 24; ++i) {
            const double e = est[i].item<double>();
            const double first = fitter.refine_anchored(po + i * 32, e, 3, 7.0).delay_index.front();
            const double expect = std::abs(first - e) < 0.5 ? first : e;
            CPPUNIT_ASSERT_DOUBLES_EQUAL(expect, out[i].item<double>(), 1e-4);
            CPPUNIT_ASSERT(std::abs(out[i].item<double>() - e) < 0.5); // the trust region
            moved += std::abs(out[i].item<double>() - e) > 1e-6;
        }
        CPPUNIT_ASSERT(moved > 0); // the stage did something
        // Without positions no refinement happens (and the eval answer is the network's).
        torch::manual_seed(3);
        delay_decoder_module unset(fs.n_symbols, fs.n_subcarriers, 32, small(3));
        unset.forward(grid); // the same batch-norm statistics as the two above
        unset.eval();
        CPPUNIT_ASSERT(torch::allclose(unset.forward(grid).delay_index.to(torch::kDouble), est));
    }

    void residual_maps_remove_the_strongest_atom()
    {
        // One noiseless on-grid path: once its atom is removed nothing is left to correlate;
        // with two paths the first map still shows the weaker one at its delay.
        const auto flat = one_symbol_positions();
        auto s = small(0);
        s.residual_maps = 2;
        delay_decoder_module d(fs.n_symbols, fs.n_subcarriers, 32, s);
        auto grid_of = [&](const std::vector<double>& delays) {
            target_spec t;
            t.range_m = delays[0] * fs.range_per_delay_index_m();
            t.paths.clear();
            for (size_t l = 0; l < delays.size(); ++l)
                t.paths.push_back({ (delays[l] - delays[0]) * fs.range_per_delay_index_m(), l == 0 ? 1.0 : 0.1 });
            channel_model cm(fs, scene::fixed({ t }, std::nullopt, 0, fading_kind::none), 1);
            std::vector<gr_complex> h(fs.grid_size());
            cm.generate(1, h.data());
            auto all = torch::from_blob(h.data(), { 1, fs.n_symbols, fs.n_subcarriers, 2 }, torch::kFloat)
                           .permute({ 0, 3, 1, 2 })
                           .contiguous();
            return scatter_pilots(gather_pilots(all, flat), flat, fs.n_symbols, fs.n_subcarriers);
        };
        // Delay 20 is on the 0.25 grid: the first map is round-off.
        const auto one = d.residual_maps_of(grid_of({ 20.0 }));
        CPPUNIT_ASSERT(one.sizes() == torch::IntArrayRef({ 1, 2, 201 }));
        const auto peak = d.residual_maps_of(grid_of({ 20.0 })).abs().max().item<double>();
        CPPUNIT_ASSERT(peak < 1e-3);
        // A path 10 dB weaker 3 indices behind: the first map peaks there (delay 23 = q 100).
        const auto two = d.residual_maps_of(grid_of({ 20.0, 23.0 }));
        CPPUNIT_ASSERT_EQUAL(int64_t(100), two[0][0].argmax().item<int64_t>());
        CPPUNIT_ASSERT(two[0][1].max().item<double>() < 1e-3); // both removed: nothing left
    }

    void residual_maps_match_the_operator_form()
    {
        // grid_omp_maps (plain loops) against the LibTorch form it replaced (complex double,
        // a batched solve per round), on noisy 3-path frames and trained-looking projections.
        torch::manual_seed(5);
        const auto flat = one_symbol_positions();
        auto s = small(0);
        s.residual_maps = 3;
        delay_decoder_module d(fs.n_symbols, fs.n_subcarriers, 32, s);
        const auto grid = frames(24, flat, 10.0);
        // Both correlations: the exact loop, and the fused one where the CPU has AVX2 + FMA.
        std::vector<torch::Tensor> gots;
        for (const bool fused : { false, true })
            if (grid_omp_use_fused(fused) == fused)
                gots.push_back(d.residual_maps_of(grid));
        grid_omp_use_fused(true);

        torch::NoGradGuard ng;
        const auto params = d.named_parameters();
        const auto buffers = d.named_buffers();
        const auto pr = params["proj_re"].select(0, 0), pi = params["proj_im"].select(0, 0); // N
        const auto x = normalise_frames(grid, 32);                                             // B x 2 x N x M
        const auto xr = torch::matmul(pr, x.select(1, 0)) - torch::matmul(pi, x.select(1, 1)); // B x M
        const auto xi = torch::matmul(pr, x.select(1, 1)) + torch::matmul(pi, x.select(1, 0));
        const auto support = (x.abs().sum(1).sum(1) > 0).to(torch::kDouble);
        const double scale = 1.0 / std::sqrt(32.0);
        const auto y = torch::complex(xr.to(torch::kDouble), xi.to(torch::kDouble));
        const auto steer = torch::complex(buffers["dict_cos"].to(torch::kDouble), -buffers["dict_sin"].to(torch::kDouble));
        const auto sup = torch::complex(support, torch::zeros_like(support));
        auto mag = (torch::matmul(y, steer.conj()) * scale).abs();
        std::vector<torch::Tensor> chosen, want;
        for (int k = 0; k < s.residual_maps; ++k) {
            chosen.push_back(mag.argmax(1));
            auto idx = torch::stack(chosen, 1);
            auto a = steer.t().index_select(0, idx.flatten()).view({ idx.size(0), idx.size(1), fs.n_subcarriers });
            a = (a * sup.unsqueeze(1)).transpose(1, 2);
            auto ah = a.conj().transpose(1, 2);
            auto g = torch::matmul(ah, a);
            g = g + 1e-9 * torch::eye(g.size(-1), g.options()) *
                        (1.0 + torch::real(g.diagonal(0, 1, 2)).amax(-1)).view({ -1, 1, 1 });
            auto b = torch::linalg::solve(g, torch::matmul(ah, y.unsqueeze(-1)), true);
            mag = (torch::matmul(y - torch::matmul(a, b).squeeze(-1), steer.conj()) * scale).abs();
            want.push_back(mag);
        }
        const auto ref = torch::stack(want, 1).to(torch::kFloat);
        const double top = ref.abs().max().item<double>();
        CPPUNIT_ASSERT_MESSAGE("largest map value " + std::to_string(top), top > 0.01); // not all zero (~0.1)
        for (const auto& got : gots) {
            CPPUNIT_ASSERT(got.sizes() == ref.sizes());
            const double err = (got - ref).abs().max().item<double>();
            CPPUNIT_ASSERT_MESSAGE("max difference " + std::to_string(err) + " of " + std::to_string(top),
                                   err <= 1e-5 * top);
        }
        if (gots.size() == 2) { // fused against exact: double rounding only, then float
            const double err = (gots[0] - gots[1]).abs().max().item<double>();
            CPPUNIT_ASSERT_MESSAGE("fused against exact " + std::to_string(err), err <= 1e-6 * top);
        }
    }

    void folded_network_matches_the_modules()
    {
        // At inference a small network runs as plain loops with its BatchNorms folded in
        // (folded_conv1d.h); with autograd on it runs LibTorch's modules. Both on the same
        // frames, with BatchNorm statistics and affine parameters far from the identity, a
        // dilated stack (depth 3: dilations 1, 2, 4) and the fast bundle's width.
        torch::manual_seed(9);
        auto s = small(0);
        s.q = 89;
        s.width = 4;
        s.depth = 3;
        s.residual_maps = 2;
        delay_decoder_module d(fs.n_symbols, fs.n_subcarriers, 32, s);
        {
            torch::NoGradGuard ng;
            for (auto& p : d.named_parameters())
                if (p.key().find("bn") != std::string::npos)
                    p.value().copy_(torch::rand_like(p.value()) * 2.0 - 0.5);
            for (auto& b : d.named_buffers()) {
                if (b.key().find("running_mean") != std::string::npos)
                    b.value().copy_(torch::randn_like(b.value()));
                if (b.key().find("running_var") != std::string::npos)
                    b.value().copy_(torch::rand_like(b.value()) * 3.0 + 0.1);
            }
        }
        d.eval();
        const auto grid = frames(16, one_symbol_positions(), 20.0);
        const auto compare = [&](const std::string& what) {
            const auto modules = d.forward(grid).logits; // autograd on: LibTorch's modules
            torch::Tensor loops;
            {
                torch::NoGradGuard ng;
                loops = d.forward(grid).logits;
            }
            CPPUNIT_ASSERT(loops.sizes() == modules.sizes());
            const double err = (loops - modules.detach()).abs().max().item<double>();
            const double top = modules.detach().abs().max().item<double>();
            CPPUNIT_ASSERT_MESSAGE(what + ": max difference " + std::to_string(err) + " of " + std::to_string(top),
                                   err <= 1e-5 * top && top > 0.1);
        };
        compare("as built");
        // A changed weight or statistic reaches the loops (the folded copy is rebuilt).
        {
            torch::NoGradGuard ng;
            d.named_buffers()["blocks.1.bn2.running_mean"].add_(0.7);
            d.named_parameters()["head.bias"].add_(-1.5);
            d.named_parameters()["blocks.2.conv1.weight"].mul_(-2.0);
        }
        compare("after changing three tensors");
    }

    void bad_settings_are_refused()
    {
        delay_settings s; // refine_paths = -1: "from the training scene", unresolved
        qa::assert_error([&] { delay_decoder_module(fs.n_symbols, fs.n_subcarriers, 32, s); }, "refine_paths");
        auto bad = small(1).to_json();
        bad["refine_global_min_fraction"] = 1.5;
        qa::assert_error([&] { delay_settings::from_json(bad, "b.json"); }, "b.json", "refine_global_min_fraction");
        auto r = small(3);
        delay_decoder_module d(fs.n_symbols, fs.n_subcarriers, 32, r);
        auto flat = one_symbol_positions();
        qa::assert_error([&] { d.set_pilot_positions(fs, { 1, 2, 3 }); }, "3 pilot positions", "32");
        std::reverse(flat.begin(), flat.end());
        qa::assert_error([&] { d.set_pilot_positions(fs, flat); }, "mask order");
        frame_settings other = fs;
        other.n_subcarriers = 128;
        qa::assert_error([&] { d.set_pilot_positions(other, one_symbol_positions()); }, "128");
        nlohmann::json j = small(3).to_json();
        j["residual_maps"] = 9;
        qa::assert_error([&] { delay_settings::from_json(j, "x/bundle.json"); }, "x/bundle.json", "residual_maps");
        j = small(3).to_json();
        j["phase_reference"] = 1;
        qa::assert_error([&] { delay_settings::from_json(j, "x/bundle.json"); }, "phase_reference");
        // The trainer refuses a network that cannot see from the first path to the last.
        training_settings t;
        t.task = task_kind::delay;
        random_spec rs;
        rs.paths_per_target = 3; // excess up to 30 m = 6 delay indices
        t.scene_spec = scene::random(rs);
        t.frames = 40;
        t.epochs = 1;
        t.batch = 8;
        t.threads = 1;
        t.verbose = false;
        t.delay.depth = 1;
        t.delay.kernel = 3;
        t.delay.dilation_growth = 1;
        qa::assert_error([&] { train(t, nullptr); }, "receptive field", "twice the largest excess delay");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_learning_delay);
