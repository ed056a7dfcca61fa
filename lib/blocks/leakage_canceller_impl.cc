// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: leakage_canceller implementation (see leakage_canceller.h). */
#include "blocks/leakage_canceller_impl.h"
#include <gnuradio/io_signature.h>
#include <algorithm>

namespace gr {
namespace sems {

leakage_canceller::sptr
leakage_canceller::make(int taps, int window, double forgetting, bool widely_linear, bool dc, double clip_level)
{
    leakage_canceller_settings s;
    s.taps = taps;
    s.window = window;
    s.forgetting = forgetting;
    s.widely_linear = widely_linear;
    s.dc = dc;
    s.clip_level = clip_level;
    return gnuradio::make_block_sptr<leakage_canceller_impl>(s); // validated by the core
}

leakage_canceller_impl::leakage_canceller_impl(const leakage_canceller_settings& settings)
    : gr::block("leakage_canceller",
                gr::io_signature::make(2, 2, sizeof(gr_complex)),
                gr::io_signature::make(1, 1, sizeof(gr_complex))),
      d_core(settings),
      d_max_lead(max_lead(settings.window))
{
    set_output_multiple(settings.window); // whole windows: each is fitted and cancelled at once
    // Room for four windows: the scheduler offers at most half the output buffer, so with the
    // output empty (nothing received yet) it offers two windows, which is when forecast() lets
    // the transmitted samples in.
    set_min_output_buffer(4 * settings.window);
    set_tag_propagation_policy(TPP_DONT); // rx's tags are copied in general_work(); tx's are dropped
}

std::vector<gr_complex> leakage_canceller_impl::taps() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_core.taps();
}

std::vector<gr_complex> leakage_canceller_impl::image_taps() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_core.image_taps();
}

gr_complex leakage_canceller_impl::dc() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_core.dc();
}

uint64_t leakage_canceller_impl::windows() const
{
    std::lock_guard<std::mutex> lock(d_mutex);
    return d_core.windows();
}

void leakage_canceller_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    // The scheduler asks for the largest output first and halves it down to one window when
    // the inputs fall short. Above one window: any transmitted sample is enough, so they are
    // taken while nothing is received (a frame_sync upstream still searching) and the
    // transmitter never waits for the receiver. At one window: what that window needs, so
    // the stream ends when an input has ended without a whole window of pairs left.
    const int w = d_core.window();
    const auto held = static_cast<int>(std::min<uint64_t>(d_held_count, uint64_t(w)));
    if (noutput_items > w) {
        ninput_items_required[0] = 0;
        ninput_items_required[1] = 1;
    } else {
        ninput_items_required[0] = noutput_items;
        ninput_items_required[1] = std::max(0, noutput_items - held);
    }
}

int leakage_canceller_impl::general_work(int noutput_items,
                                         gr_vector_int& ninput_items,
                                         gr_vector_const_void_star& input_items,
                                         gr_vector_void_star& output_items)
{
    const auto* rx = static_cast<const gr_complex*>(input_items[0]);
    const auto* tx = static_cast<const gr_complex*>(input_items[1]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const int w = d_core.window();

    // Take every transmitted sample that has arrived; they wait here for their received ones.
    if (d_held_pos > 0 && d_held_pos >= d_held.size() / 2) { // compact
        d_held.erase(d_held.begin(), d_held.begin() + static_cast<std::ptrdiff_t>(d_held_pos));
        d_held_pos = 0;
    }
    d_held.insert(d_held.end(), tx, tx + ninput_items[1]);
    consume(1, ninput_items[1]);

    const size_t held = d_held.size() - d_held_pos;
    const int n = static_cast<int>(
        std::min<size_t>(std::min(noutput_items, ninput_items[0]), held) / static_cast<size_t>(w) *
        static_cast<size_t>(w));
    {
        std::lock_guard<std::mutex> lock(d_mutex);
        for (int s = 0; s < n; s += w)
            d_core.process(rx + s, d_held.data() + d_held_pos + s, out + s);
    }
    d_held_pos += static_cast<size_t>(n);
    d_held_count = d_held.size() - d_held_pos;

    std::vector<gr::tag_t> tags; // rx's tags, on the same samples (rx item k is output item k)
    get_tags_in_range(tags, 0, nitems_read(0), nitems_read(0) + uint64_t(n));
    for (const auto& t : tags)
        add_item_tag(0, t.offset, t.key, t.value, t.srcid);
    consume(0, n);

    if (n == 0 && d_held_count > d_max_lead) {
        d_error = "leakage_canceller: the transmitted samples (input 1) run " + std::to_string(d_held_count) +
                  " samples ahead of the received ones (input 0), more than the " + std::to_string(d_max_lead) +
                  " it holds: the received stream has stalled or never started (a frame_sync upstream that "
                  "finds no frame outputs nothing)";
        d_failed = true;
        d_logger->error("{}", d_error);
        return WORK_DONE;
    }
    return n;
}

} // namespace sems
} // namespace gr
