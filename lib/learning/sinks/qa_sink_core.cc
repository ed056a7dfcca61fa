// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the sinks' shared bookkeeping (sink_core) with a fake task, no network:
 * batches, order, frame indices, truth, skipped frames and metrics messages are exact
 * whatever the sizes of the work() calls. */
#include "learning/sinks/sink_core.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/common/tags.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace gr::sems;

namespace {

constexpr int np = 3;

// Answers each frame with its first value's real part; scores "truth value == answer".
class fake_task : public gr::sems::detail::sink_task
{
public:
    std::vector<int> batches;
    uint64_t correct = 0;

    std::vector<uint64_t> indices; // of every decoded frame, in order

    std::vector<pmt::pmt_t> decode(const gr_complex* obs, int batch, const std::vector<gr::sems::detail::frame_meta>& meta) override
    {
        batches.push_back(batch);
        if (static_cast<int>(meta.size()) != batch)
            throw std::logic_error("fake_task: " + std::to_string(meta.size()) + " frames described for a batch of " +
                                   std::to_string(batch));
        for (const auto& m : meta)
            indices.push_back(m.index);
        std::vector<pmt::pmt_t> out;
        for (int i = 0; i < batch; i++)
            out.push_back(pmt::dict_add(pmt::make_dict(), pmt::intern(keys::label),
                                        pmt::from_double(obs[i * np].real())));
        return out;
    }
    bool score(pmt::pmt_t& result, const pmt::pmt_t& truth) override
    {
        double t;
        if (!gr::sems::detail::dict_number(truth, keys::class_id, t))
            return false;
        const bool ok = t == pmt::to_double(pmt::dict_ref(result, pmt::intern(keys::label), pmt::PMT_NIL));
        result = pmt::dict_add(result, pmt::intern(keys::correct), pmt::from_bool(ok));
        correct += ok;
        return true;
    }
    pmt::pmt_t add_metrics(pmt::pmt_t d) const override
    {
        return pmt::dict_add(d, pmt::intern(keys::accuracy), pmt::from_uint64(correct));
    }
    void reset_metrics() override { correct = 0; }
};

struct message {
    std::string port;
    pmt::pmt_t msg;
};

// `frames` frames; frame i holds the value i (NaN for those in `bad`), a frame tag
// 100 + i on frames >= `tag_from`, and a truth {class: i} (wrong, i+1, for odd i).
struct stream {
    std::vector<gr_complex> data;
    std::vector<gr::tag_t> tags;

    stream(int frames, std::vector<int> bad, int tag_from)
    {
        for (int i = 0; i < frames; i++) {
            const bool nan = std::find(bad.begin(), bad.end(), i) != bad.end();
            for (int p = 0; p < np; p++)
                data.push_back(nan && p == 1 ? gr_complex(std::nanf(""), 0) : gr_complex(float(i), float(p)));
            if (i >= tag_from)
                tags.push_back(tag(i, keys::frame_tag, pmt::from_uint64(100 + i)));
            tags.push_back(tag(i, keys::truth_tag,
                               pmt::dict_add(pmt::make_dict(), pmt::intern(keys::class_id),
                                             pmt::from_long(i + (i % 2)))));
        }
    }
    static gr::tag_t tag(uint64_t offset, const char* key, pmt::pmt_t value)
    {
        gr::tag_t t;
        t.offset = offset;
        t.key = pmt::intern(key);
        t.value = value;
        return t;
    }
};

// Feeds the stream in chunks of `chunk` frames, then ends it; returns the messages.
std::vector<message> run(const stream& s, int batch, int k, int chunk, fake_task& task)
{
    std::vector<message> out;
    gr::sems::detail::sink_core core(np, batch, k, task, [&](const pmt::pmt_t& port, const pmt::pmt_t& msg) {
        out.push_back({ pmt::symbol_to_string(port), msg });
    });
    const int frames = static_cast<int>(s.data.size() / np);
    for (int first = 0; first < frames; first += chunk) {
        const int n = std::min(chunk, frames - first);
        std::vector<gr::tag_t> tags;
        for (const auto& t : s.tags)
            if (t.offset >= uint64_t(first) && t.offset < uint64_t(first + n))
                tags.push_back(t);
        core.push(s.data.data() + size_t(first) * np, n, first, tags);
    }
    core.finish();
    return out;
}

uint64_t u64(const pmt::pmt_t& d, const char* key) { return pmt::to_uint64(pmt::dict_ref(d, pmt::intern(key), pmt::PMT_NIL)); }

} // namespace

class qa_sink_core : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_sink_core);
    CPPUNIT_TEST(batches_do_not_depend_on_call_sizes);
    CPPUNIT_TEST(results_in_order_with_index_and_truth);
    CPPUNIT_TEST(skipped_frames_keep_their_place);
    CPPUNIT_TEST(metrics_every_k_and_at_the_end);
    CPPUNIT_TEST_SUITE_END();

public:
    void batches_do_not_depend_on_call_sizes()
    {
        const stream s(23, { 5 }, 0);
        for (int chunk : { 1, 2, 7, 23 }) {
            fake_task task;
            run(s, 4, 0, chunk, task);
            // 22 good frames: five full batches of 4, the partial batch of 2 at the end.
            CPPUNIT_ASSERT(task.batches == std::vector<int>({ 4, 4, 4, 4, 4, 2 }));
        }
    }

    void results_in_order_with_index_and_truth()
    {
        // Frames 0..3 untagged (counted from 0), then tagged 104, 105, ...
        const stream s(10, {}, 4);
        fake_task task;
        const auto msgs = run(s, 3, 0, 4, task);
        std::vector<uint64_t> index;
        for (const auto& m : msgs) {
            if (m.port != keys::result_port)
                continue;
            index.push_back(u64(m.msg, keys::frame));
            const double v = pmt::to_double(pmt::dict_ref(m.msg, pmt::intern(keys::label), pmt::PMT_NIL));
            const pmt::pmt_t truth = pmt::dict_ref(m.msg, pmt::intern(keys::truth), pmt::PMT_NIL);
            const long t = pmt::to_long(pmt::dict_ref(truth, pmt::intern(keys::class_id), pmt::PMT_NIL));
            CPPUNIT_ASSERT_EQUAL(t == long(v), pmt::to_bool(pmt::dict_ref(m.msg, pmt::intern(keys::correct), pmt::PMT_F)));
        }
        CPPUNIT_ASSERT(index == std::vector<uint64_t>({ 0, 1, 2, 3, 104, 105, 106, 107, 108, 109 }));
        CPPUNIT_ASSERT_EQUAL(uint64_t(5), task.correct); // the even frames
    }

    void skipped_frames_keep_their_place()
    {
        const stream s(9, { 0, 4, 8 }, 0);
        fake_task task;
        const auto msgs = run(s, 2, 1, 3, task);
        // With K = 1, each handled frame (answered or skipped) is followed by a metrics
        // message: the sequence of frame counts and results shows the stream order.
        std::vector<std::string> order;
        for (const auto& m : msgs)
            order.push_back(m.port == keys::result_port ? "r" + std::to_string(u64(m.msg, keys::frame))
                                                         : "m" + std::to_string(u64(m.msg, keys::frames)) + "/" +
                                                               std::to_string(u64(m.msg, keys::frames_skipped)));
        const std::vector<std::string> want = { "m1/1", "r101", "m2/1", "r102", "m3/1", "r103", "m4/1",
                                                "m5/2", "r105", "m6/2", "r106", "m7/2", "r107", "m8/2",
                                                "m9/3" };
        CPPUNIT_ASSERT(order == want);
        // The task is told each decoded frame's index, the skipped ones left out.
        CPPUNIT_ASSERT(task.indices == std::vector<uint64_t>({ 101, 102, 103, 105, 106, 107 }));
    }

    void metrics_every_k_and_at_the_end()
    {
        fake_task task;
        auto count = [](const std::vector<message>& msgs) {
            std::vector<uint64_t> f;
            for (const auto& m : msgs)
                if (m.port == keys::metrics_port)
                    f.push_back(u64(m.msg, keys::frames));
            return f;
        };
        CPPUNIT_ASSERT(count(run(stream(11, {}, 0), 4, 5, 3, task)) == std::vector<uint64_t>({ 5, 10, 11 }));
        CPPUNIT_ASSERT(count(run(stream(10, {}, 0), 4, 5, 3, task)) == std::vector<uint64_t>({ 5, 10 }));
        CPPUNIT_ASSERT(count(run(stream(10, {}, 0), 4, 0, 3, task)) == std::vector<uint64_t>({ 10 }));
        CPPUNIT_ASSERT(count(run(stream(0, {}, 0), 4, 5, 1, task)) == std::vector<uint64_t>({ 0 }));
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_sink_core);
