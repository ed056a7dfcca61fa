// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: pilots across frames — a track's frame t of track j is read at set (j + t) mod F,
 * a bundle whose mask spans a super-frame decodes each frame at its own set (and refuses a
 * batch that does not say which), a super-frame learned with the temporal decoder writes a
 * bundle of F sets of N_p pilots that loads back, and bad super-frame settings are refused
 * by name. Frame bundles: the shipped paper classifier. */
#include "learning/temporal/track_data.h"
#include "qa/qa_assert.h"
#include "qa/qa_files.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <gnuradio/sems/learning/temporal/track_trainer.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>

using namespace gr::sems;
using gr::sems::qa::assert_error;
namespace fsys = std::filesystem;

namespace {

std::string super_frame_dir(const std::string& name) { return qa::temp_dir("super_frame", name); }

std::string paper_classifier()
{
    const char* src = std::getenv("SEMS_SOURCE_DIR");
    return std::string(src ? src : ".") + "/models/classifier";
}

// The paper classifier's files with a mask of two sets: its own (set 0) and `other` (set 1).
std::string two_set_bundle(const pilot_mask& other, const std::string& name)
{
    const auto dir = super_frame_dir(name);
    auto b = model_bundle::load(paper_classifier());
    b.super_frame = super_frame_mask({ b.mask, other });
    b.save(dir);
    fsys::copy_file(b.weights_path(), fsys::path(dir) / b.weights_name, fsys::copy_options::overwrite_existing);
    return dir;
}

// Standard complex normal observations, seeded: unlike a smooth sequence they leave the range
// gate's strongest delay bin nearly tied, so a decoder that computed a set's frames on another
// grid than that set's own (more columns, other rounding) would pick other bins and answer otherwise.
std::vector<gr_complex> observations(int batch, int np, unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<float> g;
    std::vector<gr_complex> o(static_cast<size_t>(batch) * np);
    for (auto& x : o)
        x = gr_complex(g(rng), g(rng));
    return o;
}

// A tiny super-frame of two sets learned with its temporal decoder on the paper classifier.
track_training_settings tiny_super_frame(const std::string& out)
{
    track_training_settings s;
    s.frame_bundle = paper_classifier();
    s.super_frames = 2;
    s.track_frames = 4;
    s.tracks = 60;
    s.mask_tracks = 24;
    s.mask_epochs = 2;
    s.epochs = 1;
    s.batch = 16;
    s.seed = 7;
    s.threads = 1;
    s.eval_snr_db = { 10.0 };
    s.eval_frames = { 1, 4 };
    s.temporal.hidden = 8;
    s.out_dir = out;
    s.verbose = false;
    return s;
}
} // namespace

class qa_super_frame : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_super_frame);
    CPPUNIT_TEST(frames_are_read_at_their_set);
    CPPUNIT_TEST(bundle_decodes_each_frame_at_its_set);
    CPPUNIT_TEST(learned_super_frame_loads_back);
    CPPUNIT_TEST(bad_super_frame_settings_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    // Frame t of track j of a draw with sets {A, B} is the draw with A alone when (j + t) is
    // even and with B alone when it is odd, bit for bit (the same channel, another gather).
    void frames_are_read_at_their_set()
    {
        random_spec r;
        r.classes = { target_class::pedestrian, target_class::drone };
        r.tracks = track_draw_spec{};
        r.tracks->frames_min = 3;
        r.tracks->frames_max = 5;
        const auto sc = scene::random(r);
        const frame_settings fs;
        const std::vector<std::string> names = { "pedestrian", "car", "drone" };
        const auto a = pilot_mask::from_pattern("doppler", fs, 16), b = pilot_mask::from_pattern("staggered", fs, 16);
        const auto both = temporal::draw_tracks(fs, sc, super_frame_mask({ a, b }), 3, 2, 4, 5, names);
        const auto only_a = temporal::draw_tracks(fs, sc, a, 3, 2, 4, 5, names);
        const auto only_b = temporal::draw_tracks(fs, sc, b, 3, 2, 4, 5, names);
        CPPUNIT_ASSERT(torch::equal(both.length, only_a.length));
        CPPUNIT_ASSERT(torch::equal(both.label, only_a.label));
        int read_b = 0;
        for (int j = 0; j < 4; ++j)
            for (int t = 0; t < both.length[j].item<int>(); ++t) {
                const int set = (2 + j + t) % 2; // track index 2 + j
                CPPUNIT_ASSERT_EQUAL(set, both.set[j][t].item<int>());
                const auto& want = set ? only_b : only_a;
                CPPUNIT_ASSERT(torch::equal(both.obs[j][t], want.obs[j][t]));
                read_b += set;
            }
        CPPUNIT_ASSERT(read_b > 0);
        CPPUNIT_ASSERT(!torch::equal(only_a.obs, only_b.obs)); // the two sets see different elements
        // F = 1 reads every frame at set 0: the one-frame draw, bit for bit.
        CPPUNIT_ASSERT(torch::equal(temporal::draw_tracks(fs, sc, super_frame_mask(a), 3, 2, 4, 5, names).obs, only_a.obs));
    }

    // Frames of set 1 of a two-set bundle get the answers of a bundle whose one mask is set 1;
    // a batch without sets, or naming set 2, is refused naming F.
    void bundle_decodes_each_frame_at_its_set()
    {
        const auto paper = model_bundle::load(paper_classifier());
        const frame_settings fs = paper.frame;
        const auto other = pilot_mask::from_pattern("staggered", fs, paper.mask.size());
        const auto two = model_bundle::load(two_set_bundle(other, "two_sets"));
        CPPUNIT_ASSERT_EQUAL(2, two.super_frames());
        CPPUNIT_ASSERT(two.mask == paper.mask);
        CPPUNIT_ASSERT(two.mask_of_set(1) == other);
        // The set-1 reference: the same weights on `other` alone.
        auto one = model_bundle::load(paper_classifier());
        const auto one_dir = super_frame_dir("set1_alone");
        one.mask = other;
        one.save(one_dir);
        fsys::copy_file(one.weights_path(), fsys::path(one_dir) / one.weights_name, fsys::copy_options::overwrite_existing);

        const int np = paper.mask.size(), batch = 6;
        const auto obs = observations(batch, np, 3);
        const std::vector<int> sets = { 0, 1, 1, 0, 1, 0 };
        const bundle_decoder dec_two(two, 1), dec_paper(paper, 1), dec_other(model_bundle::load(one_dir), 1);
        CPPUNIT_ASSERT_EQUAL(2, dec_two.super_frames());
        const auto got = dec_two.classify(obs.data(), batch, sets.data());
        const auto want0 = dec_paper.classify(obs.data(), batch), want1 = dec_other.classify(obs.data(), batch);
        const size_t c = paper.class_names.size();
        // The references decode each set's frames as one batch, in the batch's order, as the
        // two-set decoder does: on these nearly tied inputs the range gate's strongest bin can
        // change with the batch's rounding (another batch size, another BLAS or FFT path on
        // another CPU), so a reference over other rows could differ without any fault.
        const auto rows_of = [&](int set) {
            std::vector<gr_complex> picked;
            for (int i = 0; i < batch; ++i)
                if (sets[size_t(i)] == set)
                    picked.insert(picked.end(), obs.begin() + i * np, obs.begin() + (i + 1) * np);
            return picked;
        };
        const auto obs0 = rows_of(0), obs1 = rows_of(1);
        const int n0 = int(obs0.size()) / np, n1 = int(obs1.size()) / np;
        const auto ref0 = dec_paper.classify(obs0.data(), n0), ref1 = dec_other.classify(obs1.data(), n1);
        double apart = 0.0;
        for (int i = 0, i0 = 0, i1 = 0; i < batch; ++i) {
            const bool one = sets[size_t(i)] == 1;
            const auto& want = one ? ref1 : ref0;
            const size_t row = size_t(one ? i1++ : i0++);
            for (size_t k = 0; k < c; ++k) {
                CPPUNIT_ASSERT_DOUBLES_EQUAL(want[row * c + k], got[i * c + k], 1e-5);
                apart = std::max(apart, double(std::abs(want0[i * c + k] - want1[i * c + k])));
            }
        }
        CPPUNIT_ASSERT(apart > 1e-3); // the sets give different answers: the test can tell them apart
        // The evidence follows the same sets (frame 1 is the first of set 1).
        const auto ev = dec_two.evidence(obs.data(), batch, false, sets.data());
        const auto ev1 = dec_other.evidence(obs1.data(), n1);
        const size_t e = static_cast<size_t>(dec_two.evidence_size());
        for (size_t k = 0; k < e; ++k)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(ev1[k], ev[1 * e + k], 1e-4);
        assert_error([&] { dec_two.classify(obs.data(), batch); }, "super-frame of 2 frames");
        const std::vector<int> bad = { 0, 2, 0, 0, 0, 0 };
        assert_error([&] { dec_two.classify(obs.data(), batch, bad.data()); }, "names set 2");
        // One frame's mask: sets of 0 change nothing, bit for bit.
        const std::vector<int> zeros(batch, 0);
        CPPUNIT_ASSERT(dec_paper.classify(obs.data(), batch, zeros.data()) == want0);
    }

    // A learned super-frame: F sets of N_p distinct pilots off the guards, the learner's
    // history from its starting point (epoch 0, every set at the frame bundle's mask), and a
    // bundle that loads back with F sets and a frame decoder of its own.
    void learned_super_frame_loads_back()
    {
        const auto dir = super_frame_dir("learned");
        const auto res = train_track(tiny_super_frame(dir), nullptr);
        const auto b = model_bundle::load(dir);
        const auto paper = model_bundle::load(paper_classifier());
        CPPUNIT_ASSERT_EQUAL(2, b.super_frames());
        for (int f = 0; f < 2; ++f) {
            CPPUNIT_ASSERT_EQUAL(paper.mask.size(), b.mask_of_set(f).size());
            b.mask_of_set(f).check_frame(b.frame, "learned set");
        }
        const auto& history = b.track.at("training").at("super_frame_history");
        CPPUNIT_ASSERT_EQUAL(3, int(history.size()));
        CPPUNIT_ASSERT_EQUAL(0, history.at(0).at("epoch").get<int>());
        CPPUNIT_ASSERT_EQUAL(2, b.track.at("training").at("super_frames").get<int>());
        CPPUNIT_ASSERT(fsys::exists(fsys::path(dir) / b.weights_name));
        track_classifier tc(b, 1);
        CPPUNIT_ASSERT_EQUAL(2, tc.super_frames());
        const auto obs = observations(2, tc.n_pilots(), 5);
        const std::vector<int> sets = { 0, 1 };
        auto st = tc.begin();
        const auto ev = tc.evidence(obs.data(), 2, sets.data());
        std::vector<float> p(static_cast<size_t>(tc.n_classes()));
        tc.step(st, ev.data(), p.data());
        double sum = 0.0;
        for (float x : p)
            sum += x;
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, sum, 1e-5);
        CPPUNIT_ASSERT(!res.metrics.at("by_snr").empty());
        // A random start has no epoch 0 (no repeated mask to keep).
        auto random_start = tiny_super_frame(super_frame_dir("random_start"));
        random_start.mask_start = "random";
        const auto rr = train_track(random_start, nullptr);
        const auto& rh = rr.bundle.track.at("training").at("super_frame_history");
        CPPUNIT_ASSERT_EQUAL(2, int(rh.size()));
        CPPUNIT_ASSERT_EQUAL(1, rh.at(0).at("epoch").get<int>());
        CPPUNIT_ASSERT_EQUAL(2, model_bundle::load(random_start.out_dir).super_frames());
        // A super-frame bundle is not a frame bundle to learn another super-frame from.
        auto again = tiny_super_frame(super_frame_dir("again"));
        again.frame_bundle = dir;
        assert_error([&] { train_track(again, nullptr); }, "already a track bundle");
    }

    void bad_super_frame_settings_are_refused()
    {
        auto s = tiny_super_frame(super_frame_dir("bad"));
        s.super_frames = 0;
        assert_error([&] { s.validate(); }, "super_frames: must be in [1, ");
        s.super_frames = limits::max_super_frames + 1;
        assert_error([&] { s.validate(); }, "super_frames");
        s.super_frames = 2;
        s.out_dir.clear();
        assert_error([&] { s.validate(); }, "out_dir");
        s = tiny_super_frame(super_frame_dir("bad"));
        s.mask_tracks = 0;
        assert_error([&] { s.validate(); }, "mask_tracks");
        s.mask_tracks = 49; // 48 training tracks of 60
        assert_error([&] { s.validate(); }, "mask_tracks: must be in [1, 48]");
        s = tiny_super_frame(super_frame_dir("bad"));
        s.mask_epochs = 0;
        assert_error([&] { s.validate(); }, "mask_epochs");
        s = tiny_super_frame(super_frame_dir("bad"));
        s.mask_lr = std::nan("");
        assert_error([&] { s.validate(); }, "mask_lr");
        s = tiny_super_frame(super_frame_dir("bad"));
        s.mask_start = "best";
        assert_error([&] { s.validate(); }, "mask_start: must be \"frame\" or \"random\", got \"best\"");
        // A frame bundle whose mask already spans a super-frame.
        s = tiny_super_frame(super_frame_dir("bad"));
        s.frame_bundle = two_set_bundle(pilot_mask::from_pattern("doppler", model_bundle::load(paper_classifier()).frame,
                                                                 32),
                                        "frame_two_sets");
        assert_error([&] { train_track(s, nullptr); }, "already spans 2 frames");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_super_frame);
