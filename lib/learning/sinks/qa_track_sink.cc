// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the classifier sink in track mode, in a real flowgraph — each frame's decision is
 * the track classifier's after every frame of its track so far; a new track_id, a lost,
 * non-finite or out-of-order frame, and frames without a track each start the track again
 * (counted), two tracks are never mixed, and nothing crashes whatever the batch size. The
 * track bundle is trained here in seconds on the shipped paper classifier. */
#include "qa/qa_assert.h"
#include <gnuradio/blocks/message_debug.h>
#include <gnuradio/blocks/vector_source.h>
#include <gnuradio/sems/core/common/tags.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/sinks/classifier_sink.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <gnuradio/sems/learning/temporal/track_trainer.h>
#include <gnuradio/top_block.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <unistd.h>
#include <vector>

using namespace gr::sems;
namespace fsys = std::filesystem;

namespace {

// Seconds of training: tracks of 4 frames, one epoch, a GRU of 8.
track_training_settings tiny_settings(const std::string& frame_bundle, const std::string& out)
{
    track_training_settings s;
    s.frame_bundle = frame_bundle;
    s.track_frames = 4;
    s.tracks = 60;
    s.epochs = 1;
    s.threads = 1;
    s.eval_snr_db = { 10.0 };
    s.eval_frames = { 1, 4 };
    s.temporal.hidden = 8;
    s.out_dir = out;
    s.verbose = false;
    return s;
}

// A tiny track bundle on the shipped paper classifier (its own training scene, tracked).
const std::string& track_bundle()
{
    static std::string dir;
    if (dir.empty()) {
        const char* src = std::getenv("SEMS_SOURCE_DIR");
        dir = (fsys::temp_directory_path() / ("sems_qa_track_sink_" + std::to_string(::getpid()))).string();
        fsys::remove_all(dir);
        train_track(tiny_settings(std::string(src ? src : ".") + "/models/classifier", dir), nullptr);
    }
    return dir;
}

// A tiny track bundle whose pilots span a super-frame of two sets: the paper classifier's
// mask and the staggered pattern, its frame decoder the paper classifier's.
const std::string& super_frame_bundle()
{
    static std::string dir;
    if (dir.empty()) {
        const char* src = std::getenv("SEMS_SOURCE_DIR");
        const auto tmp = fsys::temp_directory_path();
        const std::string pid = std::to_string(::getpid());
        dir = (tmp / ("sems_qa_track_sink_sf_" + pid)).string();
        const auto frame_dir = (tmp / ("sems_qa_track_sink_sf_frame_" + pid)).string();
        fsys::remove_all(dir);
        fsys::remove_all(frame_dir);
        auto frame = model_bundle::load(std::string(src ? src : ".") + "/models/classifier");
        frame.super_frame = super_frame_mask(
            { frame.mask, pilot_mask::from_pattern("staggered", frame.frame, frame.mask.size()) });
        frame.save(frame_dir);
        fsys::copy_file(frame.weights_path(), fsys::path(frame_dir) / frame.weights_name);
        train_track(tiny_settings(frame_dir, dir), nullptr);
    }
    return dir;
}

// One frame of the stream: its index (the sems_frame tag), its track (none: no track_id in
// its truth) and whether a pilot is NaN.
struct frame_spec {
    uint64_t index;
    int64_t track; // -1: the truth has no track_id
    bool nan = false;
};

struct answer {
    uint64_t frame, track_frames;
    std::vector<float> probs;
};

struct track_run {
    std::vector<answer> answers;
    uint64_t tracks_started, track_gaps, skipped;
    uint64_t track_counters_after_reset; // tracks_started + track_gaps after reset_metrics()
};

std::vector<gr_complex> observation(uint64_t seed, int np)
{
    std::vector<gr_complex> o(static_cast<size_t>(np));
    for (int i = 0; i < np; ++i)
        o[static_cast<size_t>(i)] = gr_complex(std::cos(0.37f * float(seed * 7 + i)), std::sin(0.91f * float(seed + 3 * i)));
    return o;
}

track_run stream_track(const std::vector<frame_spec>& frames, int batch, const std::string& bundle_dir = track_bundle())
{
    const auto b = model_bundle::load(bundle_dir);
    const int np = b.mask.size();
    const frame_settings fs;
    auto sink = classifier_sink::make(bundle_dir, np, batch, 1, 0, fs.n_symbols, fs.n_subcarriers, "", 0.0,
                                      b.super_frames());
    std::vector<gr_complex> data;
    std::vector<gr::tag_t> tags;
    for (size_t f = 0; f < frames.size(); ++f) {
        auto o = observation(frames[f].index, np);
        if (frames[f].nan)
            o[1] = gr_complex(std::numeric_limits<float>::quiet_NaN(), 0.0f);
        data.insert(data.end(), o.begin(), o.end());
        gr::tag_t t;
        t.offset = f;
        t.key = pmt::intern(keys::frame_tag);
        t.value = pmt::from_uint64(frames[f].index);
        tags.push_back(t);
        pmt::pmt_t d = pmt::make_dict();
        d = pmt::dict_add(d, pmt::intern(keys::class_name), pmt::intern(b.class_names[f % b.class_names.size()]));
        if (frames[f].track >= 0)
            d = pmt::dict_add(d, pmt::intern(keys::track_id), pmt::from_uint64(uint64_t(frames[f].track)));
        t.key = pmt::intern(keys::truth_tag);
        t.value = d;
        tags.push_back(t);
    }
    auto tb = gr::make_top_block("track sink");
    auto src = gr::blocks::vector_source_c::make(data, false, np, tags);
    auto dbg = gr::blocks::message_debug::make();
    tb->connect(src, 0, sink, 0);
    tb->msg_connect(sink, keys::result_port, dbg, "store");
    tb->run();
    track_run r{ {}, sink->tracks_started(), sink->track_gaps(), sink->frames_skipped(), 0 };
    sink->reset_metrics();
    r.track_counters_after_reset = sink->tracks_started() + sink->track_gaps();
    for (int i = 0; i < dbg->num_messages(); ++i) {
        const auto m = dbg->get_message(i);
        answer a;
        a.frame = pmt::to_uint64(pmt::dict_ref(m, pmt::intern(keys::frame), pmt::PMT_NIL));
        const auto tf = pmt::dict_ref(m, pmt::intern(keys::track_frames), pmt::PMT_NIL);
        a.track_frames = pmt::is_null(tf) ? 0 : pmt::to_uint64(tf); // none from a per-frame bundle
        const auto p = pmt::dict_ref(m, pmt::intern(keys::probs), pmt::PMT_NIL);
        a.probs = pmt::f32vector_elements(p);
        r.answers.push_back(a);
    }
    return r;
}

std::vector<uint64_t> evidence_times(const track_run& r)
{
    std::vector<uint64_t> t;
    for (const auto& a : r.answers)
        t.push_back(a.track_frames);
    return t;
}
} // namespace

class qa_track_sink : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_track_sink);
    CPPUNIT_TEST(decisions_follow_the_track_classifier);
    CPPUNIT_TEST(new_tracks_gaps_and_order_start_again);
    CPPUNIT_TEST(per_frame_bundles_are_not_in_track_mode);
    CPPUNIT_TEST(super_frame_sets_follow_the_frame_index);
    CPPUNIT_TEST_SUITE_END();

public:
    // Two tracks of 3 and 5 frames: every answer is the track classifier's after the frames
    // of its track so far, for any batch size (the batches never cut a track's state; the
    // frame count is a multiple of each, so no result is left to stop(), classifier_sink.h).
    void decisions_follow_the_track_classifier()
    {
        std::vector<frame_spec> frames;
        for (uint64_t i = 0; i < 8; ++i)
            frames.push_back({ 100 + i, i < 3 ? 5 : 6 });
        const auto b = model_bundle::load(track_bundle());
        track_classifier tc(b, 1);
        std::vector<std::vector<float>> want;
        auto st = tc.begin();
        for (size_t f = 0; f < frames.size(); ++f) {
            if (f == 3)
                st = tc.begin();
            const auto o = observation(frames[f].index, b.mask.size());
            const auto ev = tc.evidence(o.data(), 1);
            std::vector<float> p(static_cast<size_t>(tc.n_classes()));
            tc.step(st, ev.data(), p.data());
            want.push_back(p);
        }
        for (int batch : { 1, 2, 4, 8 }) {
            const auto r = stream_track(frames, batch);
            CPPUNIT_ASSERT_EQUAL(size_t(8), r.answers.size());
            CPPUNIT_ASSERT(evidence_times(r) == std::vector<uint64_t>({ 1, 2, 3, 1, 2, 3, 4, 5 }));
            CPPUNIT_ASSERT_EQUAL(uint64_t(2), r.tracks_started);
            CPPUNIT_ASSERT_EQUAL(uint64_t(0), r.track_gaps);
            for (size_t f = 0; f < 8; ++f)
                for (size_t c = 0; c < want[f].size(); ++c)
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(want[f][c], r.answers[f].probs[c], 1e-5);
        }
    }

    // A lost frame (index 3 missing), a non-finite one (skipped, so its successor follows a
    // gap), an out-of-order one (index 2 after 9), a new track_id, and frames without a
    // track_id (one track of their own): each starts the decision again, and is counted.
    void new_tracks_gaps_and_order_start_again()
    {
        const std::vector<frame_spec> frames = {
            { 0, 1 }, { 1, 1 }, { 2, 1 },       // track 1
            { 4, 1 }, { 5, 1 },                  // frame 3 lost: a gap
            { 6, 1, true }, { 7, 1 }, { 8, 1 },  // frame 6 non-finite: skipped, then a gap
            { 9, 1 }, { 2, 1 }, { 3, 1 },        // out of order: a gap
            { 10, 2 }, { 11, 2 },                // a new track
            { 12, -1 }, { 13, -1 }, { 14, -1 },  // no track_id: a track of their own
        };
        const auto r = stream_track(frames, 3);
        CPPUNIT_ASSERT_EQUAL(uint64_t(1), r.skipped);
        CPPUNIT_ASSERT(evidence_times(r) ==
                       std::vector<uint64_t>({ 1, 2, 3, 1, 2, 1, 2, 3, 1, 2, 1, 2, 1, 2, 3 }));
        CPPUNIT_ASSERT_EQUAL(uint64_t(3), r.track_gaps);
        CPPUNIT_ASSERT_EQUAL(uint64_t(6), r.tracks_started);
        CPPUNIT_ASSERT_EQUAL(uint64_t(0), r.track_counters_after_reset); // reset_metrics() restarts them too
    }

    void per_frame_bundles_are_not_in_track_mode()
    {
        const char* src = std::getenv("SEMS_SOURCE_DIR");
        const auto b = model_bundle::load(std::string(src ? src : ".") + "/models/classifier");
        auto sink = classifier_sink::make(b.directory, b.mask.size(), 8, 1, 0);
        CPPUNIT_ASSERT(!sink->track_mode());
        CPPUNIT_ASSERT(classifier_sink::make(track_bundle(), b.mask.size(), 8, 1, 0)->track_mode());
        CPPUNIT_ASSERT_THROW(classifier_sink::make(track_bundle(), b.mask.size(), 8, 1, 0, 32, 64, "", -1.0),
                             std::invalid_argument);
        CPPUNIT_ASSERT_THROW(classifier_sink::make(track_bundle(), b.mask.size(), 8, 1, 0, 32, 64, "",
                                                   std::numeric_limits<double>::quiet_NaN()),
                             std::invalid_argument);
    }

    // A track bundle whose mask spans two frames (a hand-made pair of sets under a temporal
    // decoder trained on them): the sink reads the frame of stream index i
    // at set i mod 2 (the pilot mapper's and extractor's rule), for any batch size; reading
    // every frame at set 0 would answer otherwise. Its frame decoder alone (the bundle without
    // its track record) answers each frame at the same set.
    void super_frame_sets_follow_the_frame_index()
    {
        std::vector<frame_spec> frames;
        for (uint64_t i = 0; i < 6; ++i)
            frames.push_back({ 101 + i, 4 });
        const auto b = model_bundle::load(super_frame_bundle());
        CPPUNIT_ASSERT_EQUAL(2, b.super_frames());
        track_classifier tc(b, 1);
        // The answers when the frames are decoded `batch` at a time, as the sink does (a full
        // batch, then the rest at the end), each frame at set index mod 2 (by_index) or all at
        // set 0. The frames of a batch are decoded together: on these inputs the range gate's
        // strongest bin is nearly tied, and another batch's rounding (another BLAS or FFT path,
        // as on another CPU) could move it without any fault.
        auto want_at = [&](bool by_index, int batch) {
            std::vector<std::vector<float>> want;
            auto st = tc.begin();
            for (size_t first = 0; first < frames.size(); first += size_t(batch)) {
                const size_t n = std::min(frames.size() - first, size_t(batch));
                std::vector<gr_complex> obs;
                std::vector<int> sets;
                for (size_t f = first; f < first + n; ++f) {
                    const auto o = observation(frames[f].index, b.mask.size());
                    obs.insert(obs.end(), o.begin(), o.end());
                    sets.push_back(by_index ? int(frames[f].index % 2) : 0);
                }
                const auto ev = tc.evidence(obs.data(), int(n), sets.data());
                const size_t e = ev.size() / n;
                for (size_t i = 0; i < n; ++i) {
                    std::vector<float> p(static_cast<size_t>(tc.n_classes()));
                    tc.step(st, ev.data() + i * e, p.data());
                    want.push_back(p);
                }
            }
            return want;
        };
        for (int batch : { 1, 3, 6 }) {
            const auto want = want_at(true, batch), at_set0 = want_at(false, batch);
            double apart = 0.0;
            for (size_t f = 0; f < want.size(); ++f)
                for (size_t c = 0; c < want[f].size(); ++c)
                    apart = std::max(apart, double(std::abs(want[f][c] - at_set0[f][c])));
            CPPUNIT_ASSERT(apart > 1e-4);
            const auto r = stream_track(frames, batch, super_frame_bundle());
            CPPUNIT_ASSERT_EQUAL(size_t(6), r.answers.size());
            CPPUNIT_ASSERT_EQUAL(uint64_t(1), r.tracks_started);
            for (size_t f = 0; f < 6; ++f)
                for (size_t c = 0; c < want[f].size(); ++c)
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(want[f][c], r.answers[f].probs[c], 1e-5);
        }
        // A sink told another F than the bundle's is refused naming both.
        for (int wrong : { 1, 3 }) {
            try {
                classifier_sink::make(super_frame_bundle(), b.mask.size(), 2, 1, 0, 32, 64, "", 0.0, wrong);
                CPPUNIT_FAIL("a sink of super_frames = " + std::to_string(wrong) + " took a bundle of 2");
            } catch (const std::invalid_argument& e) {
                const std::string what = e.what();
                CPPUNIT_ASSERT(what.find("super_frames = " + std::to_string(wrong)) != std::string::npos);
                CPPUNIT_ASSERT(what.find("spans 2") != std::string::npos);
            }
        }
        // The frame decoder alone, in a per-frame sink.
        const auto frame_dir = (fsys::temp_directory_path() / ("sems_qa_track_sink_sf_alone_" + std::to_string(::getpid()))).string();
        fsys::remove_all(frame_dir);
        auto fb = b;
        fb.track = nlohmann::json();
        fb.save(frame_dir);
        fsys::copy_file(b.weights_path(), fsys::path(frame_dir) / b.weights_name);
        const bundle_decoder dec(model_bundle::load(frame_dir), 1);
        const auto r = stream_track(frames, 2, frame_dir);
        CPPUNIT_ASSERT_EQUAL(size_t(6), r.answers.size());
        for (size_t f = 0; f < 6; ++f) {
            const auto o = observation(frames[f].index, b.mask.size());
            const int set = int(frames[f].index % 2);
            const auto p = dec.classify(o.data(), 1, &set);
            for (size_t c = 0; c < p.size(); ++c)
                CPPUNIT_ASSERT_DOUBLES_EQUAL(p[c], r.answers[f].probs[c], 1e-5);
        }
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_track_sink);
