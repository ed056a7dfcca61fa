// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a fault inside a sink's work() (a failing decoder, a bookkeeping
 * logic_error) never escapes: the flowgraph runs to its end, the frames the fault
 * touched are counted as skipped and faulted, and every frame is accounted for
 * (frames in = answered + skipped). Faults are injected through sink_core's test hook
 * into the real sinks (shipped bundles) in a real flowgraph. */
#include "qa/qa_assert.h"
#include "qa/qa_files.h"
#include "learning/sinks/classifier_sink_impl.h"
#include "learning/sinks/delay_estimator_sink_impl.h"
#include <gnuradio/blocks/message_debug.h>
#include <gnuradio/blocks/vector_source.h>
#include <gnuradio/sems/core/common/tags.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/top_block.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <vector>

using namespace gr::sems;

namespace {
using gr::sems::qa::models_dir;

struct fault_run {
    uint64_t frames, scored, skipped, faulted;
    size_t results; // result messages
};

// Streams `n_frames` frames (every 7th non-finite, all with a truth) through `sink`
// while `inject` decides which decode calls fail.
template <typename Sink>
fault_run stream_with_faults(std::shared_ptr<Sink> sink, int np, int n_frames, std::function<void(int)> inject)
{
    std::vector<gr_complex> data(static_cast<size_t>(n_frames) * np);
    std::vector<gr::tag_t> tags;
    for (int f = 0; f < n_frames; ++f) {
        for (int i = 0; i < np; ++i)
            data[static_cast<size_t>(f) * np + i] = gr_complex(std::cos(0.3f * (f + i)), std::sin(0.7f * i));
        if (f % 7 == 3)
            data[static_cast<size_t>(f) * np] = gr_complex(std::numeric_limits<float>::quiet_NaN(), 0.0f);
        gr::tag_t t;
        t.offset = f;
        t.key = pmt::intern(keys::truth_tag);
        pmt::pmt_t d = pmt::make_dict();
        d = pmt::dict_add(d, pmt::intern(keys::class_id), pmt::from_long(f % 3));
        d = pmt::dict_add(d, pmt::intern(keys::delay_index), pmt::from_double(10.0));
        t.value = d;
        tags.push_back(t);
    }
    sink->core_for_test().set_fault_injection(std::move(inject));
    auto tb = gr::make_top_block("faults");
    auto src = gr::blocks::vector_source_c::make(data, false, np, tags);
    auto dbg = gr::blocks::message_debug::make();
    tb->connect(src, 0, sink, 0);
    tb->msg_connect(sink, keys::result_port, dbg, "store");
    tb->run(); // returns: the sink thread survived every fault
    return { sink->frames(), sink->frames_scored(), sink->frames_skipped(), sink->frames_faulted(),
             static_cast<size_t>(dbg->num_messages()) };
}
} // namespace

class qa_sink_faults : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_sink_faults);
    CPPUNIT_TEST(classifier_survives_decoder_faults);
    CPPUNIT_TEST(delay_sink_survives_logic_errors);
    CPPUNIT_TEST(recover_accounts_for_frames_in_flight);
    CPPUNIT_TEST_SUITE_END();

public:
    void classifier_survives_decoder_faults()
    {
        const std::string dir = models_dir() + "classifier";
        const int np = model_bundle::load(dir).mask.size();
        const int n_frames = 200, batch = 8;
        auto sink = gnuradio::make_block_sptr<classifier_sink_impl>(dir, np, batch, 1, 0, 32, 64, "", 0.0, 1, 1, "");
        int calls = 0;
        std::vector<int> failed_batches;
        auto r = stream_with_faults(sink, np, n_frames, [&](int b) {
            ++calls;
            if (calls % 3 == 0) { // a LibTorch error would come out as a std::exception too
                failed_batches.push_back(b);
                throw std::runtime_error("injected inference failure");
            }
        });
        uint64_t faulted = 0;
        for (int b : failed_batches)
            faulted += b;
        const uint64_t nonfinite = (n_frames + 3) / 7; // f % 7 == 3
        CPPUNIT_ASSERT(!failed_batches.empty());
        CPPUNIT_ASSERT_EQUAL(uint64_t(n_frames), r.frames);
        CPPUNIT_ASSERT_EQUAL(faulted, r.faulted);
        CPPUNIT_ASSERT_EQUAL(nonfinite + faulted, r.skipped);
        CPPUNIT_ASSERT_EQUAL(uint64_t(n_frames) - r.skipped, r.scored);
        // message_debug stops listening before the sink's stop() sends the last partial
        // batch (see python/sems/testing/sink_testing.py): at most one batch is not seen.
        CPPUNIT_ASSERT(r.results <= r.scored && r.results + batch >= r.scored);
        CPPUNIT_ASSERT_EQUAL(r.frames, r.scored + r.skipped); // every frame accounted for
    }

    void delay_sink_survives_logic_errors()
    {
        const std::string dir = models_dir() + "delay_single";
        const int np = model_bundle::load(dir).mask.size();
        const int n_frames = 97, batch = 5;
        auto sink = gnuradio::make_block_sptr<delay_estimator_sink_impl>(dir, np, batch, 1, 10, 32, 64, "");
        int calls = 0;
        uint64_t faulted = 0;
        auto r = stream_with_faults(sink, np, n_frames, [&](int b) {
            if (++calls % 2 == 1) {
                faulted += b;
                throw std::logic_error("injected bookkeeping failure");
            }
        });
        CPPUNIT_ASSERT_EQUAL(uint64_t(n_frames), r.frames);
        CPPUNIT_ASSERT_EQUAL(faulted, r.faulted);
        CPPUNIT_ASSERT_EQUAL(r.frames, r.scored + r.skipped);
        CPPUNIT_ASSERT(r.results <= r.scored && r.results + batch >= r.scored);
    }

    void recover_accounts_for_frames_in_flight()
    {
        // After an exception escaped push() (caught by the block's work()), recover()
        // counts every frame that entered and never came out, once.
        const std::string dir = models_dir() + "classifier";
        const int np = model_bundle::load(dir).mask.size();
        auto sink = gnuradio::make_block_sptr<classifier_sink_impl>(dir, np, 16, 1, 0, 32, 64, "", 0.0, 1, 1, "");
        auto& core = sink->core_for_test();
        std::vector<gr_complex> frames(static_cast<size_t>(5) * np, gr_complex(1.0f, 0.0f));
        core.push(frames.data(), 5, 0, {}); // 5 pending in a batch of 16
        CPPUNIT_ASSERT_EQUAL(uint64_t(0), core.frames());
        core.recover("test", "simulated");
        CPPUNIT_ASSERT_EQUAL(uint64_t(5), core.frames());
        CPPUNIT_ASSERT_EQUAL(uint64_t(5), core.frames_faulted());
        core.recover("test", "simulated"); // nothing left in flight
        CPPUNIT_ASSERT_EQUAL(uint64_t(5), core.frames());
        core.push(frames.data(), 5, 5, {});
        core.finish();
        CPPUNIT_ASSERT_EQUAL(uint64_t(10), core.frames());
        CPPUNIT_ASSERT_EQUAL(uint64_t(5), core.frames_skipped());
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_sink_faults);
