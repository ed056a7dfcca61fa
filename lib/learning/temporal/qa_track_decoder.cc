// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: decisions over a track — the temporal model starts as the fusion of independent
 * frames, its streamed steps are its batch forward, tracks are drawn alone from (seed, index),
 * a tiny seeded run decides better with more frames, its bundle loads back with the same
 * answers, and bad settings and bundles are refused by name. */
#include "learning/networks/task_decoder.h"
#include "learning/temporal/temporal_model.h"
#include "learning/temporal/track_data.h"
#include "qa/qa_assert.h"
#include "qa/qa_files.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <gnuradio/sems/learning/temporal/track_trainer.h>
#include <gnuradio/sems/learning/training/trainer.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <ATen/CPUGeneratorImpl.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <unistd.h>

using namespace gr::sems;
using gr::sems::qa::assert_error;
namespace fsys = std::filesystem;

namespace {

std::string track_dir(const std::string& name) { return qa::temp_dir("track", name); }

// Pedestrians against drones heading anywhere, 16 Doppler-pattern pilots, around 0 dB: one
// frame is often wrong, a track of them much less so.
scene two_classes()
{
    random_spec r;
    r.classes = { target_class::pedestrian, target_class::drone };
    r.heading = heading_kind::any;
    return scene::random(r);
}

struct trained_track {
    std::string frame_dir, track_dir;
    track_training_result result;
};
// One frame bundle and one track bundle, shared by the tests of this suite.
const trained_track& shared_track_run()
{
    static std::unique_ptr<trained_track> t;
    if (!t) {
        t = std::make_unique<trained_track>();
        t->frame_dir = track_dir("frame");
        t->track_dir = track_dir("track");
        training_settings f;
        f.scene_spec = two_classes();
        f.mask_pattern = "doppler";
        f.n_pilots = 16;
        f.snr_min_db = -6.0;
        f.snr_max_db = 0.0;
        f.frames = 2000;
        f.epochs = 3;
        f.batch = 64;
        f.threads = 1;
        f.seed = 5;
        f.eval_snr_db = { -3.0 };
        f.out_dir = t->frame_dir;
        f.verbose = false;
        train(f, nullptr);
        track_training_settings s;
        s.frame_bundle = t->frame_dir;
        s.track_frames = 8;
        s.tracks = 400;
        s.snr_min_db = -6.0;
        s.snr_max_db = 0.0;
        s.epochs = 6;
        s.batch = 32;
        s.seed = 11;
        s.threads = 1;
        s.eval_snr_db = { -3.0 };
        s.eval_frames = { 1, 2, 4, 8 };
        s.temporal.hidden = 16;
        s.out_dir = t->track_dir;
        s.verbose = false;
        t->result = train_track(s, nullptr);
    }
    return *t;
}

double at_frames(const nlohmann::json& metrics, int frames, const char* key)
{
    for (const auto& row : metrics.at("by_snr").at(0).at("by_frames"))
        if (row.at("frames").get<int>() == frames)
            return row.at(key).get<double>();
    throw std::runtime_error("no row for " + std::to_string(frames) + " frames");
}

using qa::edit_json;
} // namespace

class qa_track_decoder : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_track_decoder);
    CPPUNIT_TEST(untrained_model_is_the_fusion);
    CPPUNIT_TEST(steps_are_the_batch_forward);
    CPPUNIT_TEST(tracks_are_drawn_alone);
    CPPUNIT_TEST(more_frames_decide_better);
    CPPUNIT_TEST(bundle_gives_the_trainer_answers);
    CPPUNIT_TEST(bad_settings_are_refused);
    CPPUNIT_TEST(bad_track_bundles_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    // Before training, logits_t = Σ_{i≤t} log p(c | frame i): the product of the posteriors.
    void untrained_model_is_the_fusion()
    {
        torch::manual_seed(3);
        nn::temporal_model m(10, 3, nn::temporal_settings{});
        m->eval();
        auto ev = torch::randn({ 4, 6, 10 });
        ev.slice(2, 7, 10).copy_(torch::log_softmax(ev.slice(2, 7, 10), -1));
        torch::NoGradGuard ng;
        auto logits = m->forward(ev);
        auto fused = ev.slice(2, 7, 10).cumsum(1);
        CPPUNIT_ASSERT(torch::allclose(logits, fused, 1e-6, 1e-6));
    }

    // One step per frame from a kept state gives the batch forward's decisions, frame by frame.
    void steps_are_the_batch_forward()
    {
        torch::manual_seed(4);
        nn::temporal_settings s;
        s.hidden = 12;
        nn::temporal_model m(9, 4, s);
        {
            torch::NoGradGuard ng;
            for (auto& p : m->parameters())
                p.normal_(0.0, 0.3); // any weights, the head and λ included
        }
        m->eval(); // dropout is for training only
        auto ev = torch::randn({ 3, 7, 9 });
        torch::NoGradGuard ng;
        auto whole = m->forward(ev);
        auto hidden = torch::zeros({ 3, 12 });
        auto fused = torch::zeros({ 3, 4 });
        for (int t = 0; t < 7; ++t) {
            auto one = m->step(ev.select(1, t), hidden, fused);
            CPPUNIT_ASSERT(torch::equal(one, whole.select(1, t)));
        }
    }

    // Tracks 5..7 drawn alone are tracks 5..7 of a draw of 0..9, bit for bit.
    void tracks_are_drawn_alone()
    {
        random_spec r;
        r.classes = { target_class::pedestrian, target_class::drone };
        r.tracks = track_draw_spec{};
        r.tracks->frames_min = 2;
        r.tracks->frames_max = 6;
        const auto sc = scene::random(r);
        const frame_settings fs;
        const auto mask = pilot_mask::doppler(fs.n_symbols, fs.n_subcarriers, 16);
        const std::vector<std::string> names{ "pedestrian", "drone" };
        const auto all = temporal::draw_tracks(fs, sc, mask, 9, 0, 10, 6, names);
        const auto some = temporal::draw_tracks(fs, sc, mask, 9, 5, 3, 6, names);
        CPPUNIT_ASSERT(torch::equal(all.obs.slice(0, 5, 8), some.obs));
        CPPUNIT_ASSERT(torch::equal(all.length.slice(0, 5, 8), some.length));
        CPPUNIT_ASSERT(torch::equal(all.label.slice(0, 5, 8), some.label));
        CPPUNIT_ASSERT(all.length.min().item<int64_t>() >= 1 && all.length.max().item<int64_t>() <= 6);
        // Past a track's end its frames are zero; inside, not.
        for (int64_t i = 0; i < 10; ++i) {
            const int64_t len = all.length[i].item<int64_t>();
            CPPUNIT_ASSERT(all.obs[i].slice(0, 0, len).abs().sum().item<double>() > 0.0);
            CPPUNIT_ASSERT_EQUAL(0.0, all.obs[i].slice(0, len, 6).abs().sum().item<double>());
        }
        // The noise leaves the frames past the end at zero.
        auto gen = at::detail::createCPUGenerator(1);
        const auto noisy = temporal::observe_tracks(all, mask, 0.0, 0.0, gen);
        for (int64_t i = 0; i < 10; ++i)
            CPPUNIT_ASSERT_EQUAL(0.0, noisy[i].slice(0, all.length[i].item<int64_t>(), 6).abs().sum().item<double>());
        assert_error([&] { temporal::draw_tracks(fs, two_classes(), mask, 9, 0, 2, 6, names); }, "random.tracks");
        assert_error([&] { temporal::draw_tracks(fs, sc, mask, 9, 0, 2, 6, { "pedestrian", "car" }); }, "\"drone\"");
    }

    // Eight frames of a track decide better than one, and the learned decision is not worse
    // than the fusion it starts from by more than the test's noise.
    void more_frames_decide_better()
    {
        const auto& m = shared_track_run().result.metrics;
        const double one = at_frames(m, 1, "accuracy"), eight = at_frames(m, 8, "accuracy");
        const double fusion8 = at_frames(m, 8, "fusion_accuracy");
        CPPUNIT_ASSERT_MESSAGE("1 frame " + std::to_string(one) + ", 8 frames " + std::to_string(eight),
                               eight >= one + 0.08);
        CPPUNIT_ASSERT_MESSAGE("8 frames " + std::to_string(eight) + ", fusion " + std::to_string(fusion8),
                               eight >= fusion8 - 0.05);
        CPPUNIT_ASSERT(one > 0.55); // the frame decoder is better than chance
    }

    // The written track bundle, loaded by track_classifier and stepped frame by frame, gives
    // the decision of the model it was trained_track as; the fusion beside it is the softmax of the
    // summed frame log-probabilities.
    void bundle_gives_the_trainer_answers()
    {
        const auto& t = shared_track_run();
        const auto b = model_bundle::load(t.track_dir);
        CPPUNIT_ASSERT(track_classifier::is_track_bundle(b));
        CPPUNIT_ASSERT(!track_classifier::is_track_bundle(model_bundle::load(t.frame_dir)));
        track_classifier tc(b, 1);
        CPPUNIT_ASSERT_EQUAL(2, tc.n_classes());
        CPPUNIT_ASSERT_EQUAL(16, tc.n_pilots());
        // A few frames of one track at 0 dB through the classifier and through the model itself.
        random_spec r = *two_classes().random_settings();
        r.tracks = track_draw_spec{};
        r.tracks->frames_min = r.tracks->frames_max = 5;
        const auto tracks = temporal::draw_tracks(b.frame, scene::random(r), b.mask, 77, 0, 3, 5, b.class_names);
        auto gen = at::detail::createCPUGenerator(2);
        const auto obs = temporal::observe_tracks(tracks, b.mask, 0.0, 0.0, gen);
        nn::temporal_model model(tc.evidence_size(), 2, tc.settings());
        nn::load_module(model.ptr(), t.track_dir + "/" + track_classifier::weights_file);
        model->eval();
        for (int64_t i = 0; i < 3; ++i) {
            const int64_t len = tracks.length[i].item<int64_t>();
            auto frames = obs[i].slice(0, 0, len).contiguous();
            const auto ev = tc.evidence(reinterpret_cast<const gr_complex*>(frames.data_ptr<float>()), static_cast<int>(len));
            torch::Tensor want;
            {
                torch::NoGradGuard ng;
                want = torch::softmax(model->forward(torch::from_blob(const_cast<float*>(ev.data()),
                                                                      { 1, len, tc.evidence_size() })),
                                      -1)[0];
            }
            auto st = tc.begin();
            std::vector<float> sum(2, 0.0f);
            for (int64_t f = 0; f < len; ++f) {
                float p[2], q[2];
                tc.step(st, ev.data() + f * tc.evidence_size(), p, q);
                CPPUNIT_ASSERT_EQUAL(uint64_t(f + 1), st.frames);
                if (f < tc.settings().fusion_frames) { // the fusion decides the first frames
                    CPPUNIT_ASSERT_EQUAL(q[0], p[0]);
                } else {
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(want[f][0].item<float>(), p[0], 1e-5);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(want[f][1].item<float>(), p[1], 1e-5);
                }
                for (int c = 0; c < 2; ++c)
                    sum[c] += ev[f * tc.evidence_size() + tc.evidence_size() - 2 + c];
                const double q0 = 1.0 / (1.0 + std::exp(double(sum[1]) - double(sum[0])));
                CPPUNIT_ASSERT_DOUBLES_EQUAL(q0, q[0], 1e-5);
            }
        }
        // The record says what it was trained_track on.
        CPPUNIT_ASSERT_EQUAL(8, b.track.at("frames").get<int>());
        CPPUNIT_ASSERT_EQUAL(std::string("gru_fusion"), b.track.at("temporal").at("kind").get<std::string>());
    }

    void bad_settings_are_refused()
    {
        track_training_settings s;
        s.frame_bundle = "x";
        s.track_frames = 0;
        assert_error([&] { s.validate(); }, "track_frames", "got 0");
        s.track_frames = limits::max_track_frames + 1;
        assert_error([&] { s.validate(); }, "track_frames", std::to_string(limits::max_track_frames));
        s.track_frames = 8;
        s.eval_frames = { 1, 9 };
        assert_error([&] { s.validate(); }, "eval_frames", "9 frames");
        s.eval_frames = { 1 };
        s.tracks = 5;
        assert_error([&] { s.validate(); }, "tracks");
        s.tracks = 100;
        s.frame_bundle.clear();
        assert_error([&] { s.validate(); }, "frame_bundle");
        // A track bundle is not a frame bundle, and a frame bundle trained_track on per-frame scenes needs tracks.
        s.frame_bundle = shared_track_run().track_dir;
        s.verbose = false;
        assert_error([&] { train_track(s, nullptr); }, "already a track bundle");
        s.frame_bundle = shared_track_run().frame_dir;
        s.scene_spec = two_classes();
        assert_error([&] { train_track(s, nullptr); }, "random.tracks");
    }

    void bad_track_bundles_are_refused()
    {
        const auto& t = shared_track_run();
        assert_error([&] { track_classifier(model_bundle::load(t.frame_dir)); }, "no \"track\" record");
        const std::string dir = track_dir("bad");
        auto broken = [&](const std::function<void(nlohmann::json&)>& f) {
            fsys::remove_all(dir);
            fsys::copy(t.track_dir, dir, fsys::copy_options::recursive);
            edit_json(dir + "/bundle.json", f);
            return model_bundle::load(dir);
        };
        assert_error([&] { track_classifier(broken([](auto& j) { j["track"]["temporal"]["kind"] = "lstm"; })); },
                     "track.temporal", "lstm");
        assert_error([&] { track_classifier(broken([](auto& j) { j["track"]["temporal"]["settings"]["hidden"] = 17; })); },
                     "temporal.pt");
        assert_error([&] { track_classifier(broken([](auto& j) { j["track"]["weights_file"] = "../x.pt"; })); },
                     "track.weights_file");
        assert_error([&] { track_classifier(broken([](auto& j) { j["track"]["lenght"] = 3; })); }, "track.lenght",
                     "unknown key");
        assert_error([&] { broken([](auto& j) { j["track"] = 3; }); }, "track", "JSON object");
        fsys::remove_all(dir);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_track_decoder);
