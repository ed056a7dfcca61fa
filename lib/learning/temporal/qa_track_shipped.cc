// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the shipped track bundle (models/classifier_kinematic_track) on fresh tracks — its
 * recorded scene's tracks with a seed its training never used, 31 frames (1 s) at 10 dB,
 * stepped frame by frame through track_classifier as the sink does — holds the accuracy its
 * training measured within three standard errors, and decides better over the track than from
 * its first frame. */
#include "qa/qa_assert.h"
#include "qa/qa_files.h"
#include "learning/temporal/track_data.h"
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <ATen/CPUGeneratorImpl.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>

using namespace gr::sems;

namespace {
constexpr uint64_t fresh_track_seed = 0x5e5f00d; // not a training seed
constexpr int fresh_tracks = 400;
constexpr int track_frames = 31; // 1 s of the paper's 32 ms frames

using gr::sems::qa::models_dir;
} // namespace

class qa_track_shipped : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_track_shipped);
    CPPUNIT_TEST(classifier_kinematic_track_bar);
    CPPUNIT_TEST_SUITE_END();

public:
    void classifier_kinematic_track_bar()
    {
        const auto b = model_bundle::load(models_dir() + "classifier_kinematic_track");
        track_classifier tc(b, 2);
        // What its training measured on its test tracks at 10 dB after 31 frames.
        double recorded = -1.0;
        for (const auto& s : b.track.at("metrics").at("by_snr"))
            if (s.at("snr_db").get<double>() == 10.0)
                for (const auto& r : s.at("by_frames"))
                    if (r.at("frames").get<int>() == track_frames)
                        recorded = r.at("accuracy").get<double>();
        CPPUNIT_ASSERT_MESSAGE("the bundle records no accuracy at 10 dB after 31 frames", recorded > 0.0);

        const auto sc = scene::from_json(b.track.at("training").at("scene"), b.directory + ": track.training.scene");
        const auto tracks = temporal::draw_tracks(b.frame, sc, b.mask, fresh_track_seed, 0, fresh_tracks, track_frames, b.class_names);
        auto gen = at::detail::createCPUGenerator(fresh_track_seed);
        const auto obs = temporal::observe_tracks(tracks, b.mask, 10.0, 10.0, gen).contiguous();
        const int np = b.mask.size(), e = tc.evidence_size(), c = tc.n_classes();
        int scored = 0, correct = 0, first_correct = 0;
        std::vector<float> p(static_cast<size_t>(c));
        for (int i = 0; i < fresh_tracks; ++i) {
            const int len = static_cast<int>(tracks.length[i].item<int64_t>());
            if (len < track_frames)
                continue; // scored after 31 frames: tracks that last them
            const auto* y = reinterpret_cast<const gr_complex*>(obs.data_ptr<float>()) + static_cast<size_t>(i) * track_frames * np;
            const auto ev = tc.evidence(y, track_frames);
            auto st = tc.begin();
            const int64_t label = tracks.label[i].item<int64_t>();
            for (int f = 0; f < track_frames; ++f) {
                tc.step(st, ev.data() + static_cast<size_t>(f) * e, p.data());
                const auto best = std::max_element(p.begin(), p.end()) - p.begin();
                if (f == 0)
                    first_correct += best == label;
                if (f == track_frames - 1)
                    correct += best == label;
            }
            ++scored;
        }
        const double acc = double(correct) / scored, first = double(first_correct) / scored;
        const double se = std::sqrt(recorded * (1.0 - recorded) / scored);
        std::cout << "\n  shipped " << b.directory << ": accuracy " << acc << " after 31 frames at 10 dB (first frame "
                  << first << ") on " << scored << " fresh tracks; its training measured " << recorded << std::flush;
        CPPUNIT_ASSERT(scored >= fresh_tracks * 3 / 4);
        CPPUNIT_ASSERT_MESSAGE("accuracy " + std::to_string(acc) + " below " + std::to_string(recorded) + " - 3 SE",
                               acc >= recorded - 3.0 * se);
        CPPUNIT_ASSERT_MESSAGE("31 frames " + std::to_string(acc) + " not above the first frame's " + std::to_string(first),
                               acc >= first + 0.1);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_track_shipped);
