// SPDX-License-Identifier: GPL-3.0-or-later
/* libFuzzer harness: the pilot extractor's frame bookkeeping in a real flowgraph.
 * The input chooses the frame size (N <= 6, M <= 8), the mask, the number of
 * symbols and, per symbol, a frame tag (readable or not, any index), a NaN and an
 * extra tag. The extractor's counters must equal those of a reference model, the
 * output must hold exactly frames_out frames, each with one frame tag, and nothing
 * may crash or trip a sanitizer. */
#include <gnuradio/blocks/vector_sink.h>
#include <gnuradio/blocks/vector_source.h>
#include <gnuradio/sems/blocks/pilot_extractor.h>
#include <gnuradio/sems/core/common/tags.h>
#include <gnuradio/top_block.h>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <vector>

namespace {
struct bytes {
    const uint8_t* p;
    size_t n, i = 0;
    uint8_t next() { return i < n ? p[i++] : 0; }
};
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    bytes in{ data, size };
    const int n = 1 + in.next() % 6, m = 1 + in.next() % 8;
    std::vector<int> positions;
    for (int k = 0; k < n * m; ++k)
        if (in.next() & 1)
            positions.push_back(k);
    if (positions.empty())
        positions.push_back(0);
    const int items = in.next() % 64;

    std::vector<gr_complex> symbols(static_cast<size_t>(items) * m);
    std::vector<gr::tag_t> tags;
    uint64_t out = 0, dropped = 0, skipped = 0;
    int row = 0;
    bool nonfinite = false;
    const pmt::pmt_t frame_key = pmt::intern(gr::sems::keys::frame_tag);
    for (int t = 0; t < items; ++t) {
        const uint8_t e = in.next();
        for (int k = 0; k < m; ++k)
            symbols[static_cast<size_t>(t) * m + k] = gr_complex(float(t + k), float(k));
        if (e & 1) {
            gr::tag_t tag;
            tag.offset = t;
            tag.key = frame_key;
            tag.value = (e & 2) ? pmt::intern("not an index") : pmt::from_uint64(uint64_t(e >> 4) * 0x1000000001ULL);
            tags.push_back(tag);
            if (row > 0)
                ++dropped;
            row = 0;
        }
        if (row == 0)
            nonfinite = false;
        if (e & 4) {
            symbols[static_cast<size_t>(t) * m + (e >> 5) % m] =
                gr_complex((e & 8) ? std::numeric_limits<float>::infinity() : std::nanf(""), 0.0f);
            nonfinite = true;
        }
        if (e & 8) {
            gr::tag_t tag;
            tag.offset = t;
            tag.key = pmt::intern(gr::sems::keys::truth_tag);
            tag.value = pmt::from_long(t);
            tags.push_back(tag);
        }
        if (++row == n) {
            ++(nonfinite ? skipped : out);
            row = 0;
        }
    }
    if (row > 0)
        ++dropped; // the stream ends inside a frame

    auto ex = gr::sems::pilot_extractor::make("", positions, n, m);
    const int np = ex->n_pilots();
    auto src = gr::blocks::vector_source_c::make(symbols, false, m, tags);
    auto sink = gr::blocks::vector_sink_c::make(np);
    auto tb = gr::make_top_block("fuzz_extractor");
    tb->connect(src, 0, ex, 0);
    tb->connect(ex, 0, sink, 0);
    tb->run();

    if (ex->frames_out() != out || ex->frames_dropped_partial() != dropped || ex->frames_skipped_nonfinite() != skipped)
        std::abort();
    if (sink->data().size() != out * static_cast<size_t>(np))
        std::abort();
    uint64_t frame_tags = 0;
    for (const auto& t : sink->tags())
        frame_tags += pmt::eqv(t.key, frame_key) ? 1 : 0;
    if (frame_tags != out)
        std::abort();
    for (const auto& v : sink->data())
        if (!std::isfinite(v.real()) || !std::isfinite(v.imag()))
            std::abort();
    return 0;
}
