// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: frame_sync implementation (see frame_sync.h). */
#include "blocks/frame_sync_impl.h"
#include "blocks/common/block_mask.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/common/tags.h>
#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace gr {
namespace sems {

frame_sync::sptr frame_sync::make(const std::string& mask_file,
                                  const std::vector<int>& pilot_positions,
                                  int n_symbols,
                                  int n_subcarriers,
                                  gr_complex pilot_symbol,
                                  double pilot_power,
                                  int cp_len,
                                  int search_frames,
                                  double threshold,
                                  bool noncoherent)
{
    const char* const who = frame_sync_impl::who;
    auto mask = block_mask_one_frame(who, n_symbols, n_subcarriers, mask_file, pilot_positions, pilot_symbol);
    try {
        return gnuradio::make_block_sptr<frame_sync_impl>(
            frame_search(mask, cp_len, pilot_power, search_frames, threshold, noncoherent), mask.n_symbols(),
            mask.n_subcarriers(), cp_len);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(who) + ": " + e.what());
    }
}

frame_sync_impl::frame_sync_impl(frame_search search, int n_symbols, int n_subcarriers, int cp_len)
    : gr::block(who,
                gr::io_signature::make(1, 1, sizeof(gr_complex)),
                gr::io_signature::make(1, 1, sizeof(gr_complex))),
      d_search(std::move(search)),
      d_frame_key(pmt::intern(keys::frame_tag)),
      d_port(pmt::intern(keys::sync_port)),
      d_spacing(who, n_symbols, n_subcarriers, cp_len)
{
    message_port_register_out(d_port);
    // Tags are placed by hand: input and output offsets differ by the offset found. Incoming
    // frame tags are dropped (this block numbers the frames it finds); every other tag (a
    // replayed sems_truth, ...) goes out on the same sample, at input offset − offset().
    set_tag_propagation_policy(TPP_DONT);
}

bool frame_sync_impl::check_spacing(const std::vector<gr::tag_t>& tags)
{
    for (const auto& t : tags) // another cyclic prefix upstream: refuse the stream
        if (pmt::eqv(t.key, d_frame_key) && !d_spacing.check(t, d_logger))
            return false;
    return true;
}

void frame_sync_impl::carry_tags(const std::vector<gr::tag_t>& tags, uint64_t first, uint64_t n)
{
    for (const auto& t : tags) {
        if (t.offset < static_cast<uint64_t>(d_offset))
            continue; // before the first frame: dropped with its samples
        const uint64_t out = t.offset - static_cast<uint64_t>(d_offset);
        if (out >= first && out < first + n)
            add_item_tag(0, out, t.key, t.value, t.srcid);
    }
}

void frame_sync_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    // Searching: whatever is there (it is buffered here). Locked: 1:1, after what is pending.
    if (!d_locked)
        ninput_items_required[0] = 1;
    else
        ninput_items_required[0] = d_pending_pos < d_buf.size() ? 0 : noutput_items;
}

int frame_sync_impl::general_work(int noutput_items,
                                  gr_vector_int& ninput_items,
                                  gr_vector_const_void_star& input_items,
                                  gr_vector_void_star& output_items)
{
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const size_t window = static_cast<size_t>(d_search.window_len());
    const size_t frame = static_cast<size_t>(d_search.frame_len());
    if (!d_locked) {
        const uint64_t read = nitems_read(0);
        std::vector<gr::tag_t> tags;
        get_tags_in_range(tags, 0, read, read + static_cast<uint64_t>(ninput_items[0]));
        if (!check_spacing(tags))
            return WORK_DONE;
        for (auto& t : tags)
            if (!pmt::eqv(t.key, d_frame_key))
                d_buf_tags.push_back(std::move(t));
        d_buf.insert(d_buf.end(), in, in + ninput_items[0]);
        consume_each(ninput_items[0]);
        while (!d_locked && d_buf.size() >= window) {
            const auto r = d_search.search(d_buf.data());
            d_metric = r.metric;
            if (!r.found) { // slide by one frame
                ++d_failures;
                d_buf.erase(d_buf.begin(), d_buf.begin() + static_cast<std::ptrdiff_t>(frame));
                d_buf_start += frame;
                d_buf_tags.erase(std::remove_if(d_buf_tags.begin(),
                                                d_buf_tags.end(),
                                                [this](const gr::tag_t& t) { return t.offset < d_buf_start; }),
                                 d_buf_tags.end());
                continue;
            }
            d_offset = static_cast<int64_t>(d_buf_start) + r.lag;
            d_locked = true;
            d_pending_pos = static_cast<size_t>(r.lag);
            pmt::pmt_t dict = pmt::make_dict();
            dict = pmt::dict_add(dict, pmt::intern(keys::sync_offset), pmt::from_long(d_offset));
            dict = pmt::dict_add(dict, pmt::intern(keys::sync_metric), pmt::from_double(r.metric));
            dict = pmt::dict_add(dict, pmt::intern(keys::sync_failures), pmt::from_uint64(d_failures));
            message_port_pub(d_port, dict);
        }
        if (!d_locked)
            return 0;
    }
    int n = 0;
    const uint64_t first = nitems_written(0), L = frame;
    if (d_pending_pos < d_buf.size()) { // the found frames, from the window
        n = static_cast<int>(std::min<size_t>(noutput_items, d_buf.size() - d_pending_pos));
        std::memcpy(out, d_buf.data() + d_pending_pos, sizeof(gr_complex) * n);
        carry_tags(d_buf_tags, first, static_cast<uint64_t>(n));
        d_pending_pos += n;
        if (d_pending_pos == d_buf.size()) {
            d_buf.clear();
            d_buf.shrink_to_fit();
            d_buf_tags.clear();
            d_pending_pos = 0;
        }
    } else {
        n = std::min(noutput_items, ninput_items[0]);
        std::memcpy(out, in, sizeof(gr_complex) * n);
        std::vector<gr::tag_t> tags;
        get_tags_in_range(tags, 0, nitems_read(0), nitems_read(0) + static_cast<uint64_t>(n));
        if (!check_spacing(tags))
            return WORK_DONE;
        tags.erase(std::remove_if(tags.begin(),
                                  tags.end(),
                                  [this](const gr::tag_t& t) { return pmt::eqv(t.key, d_frame_key); }),
                   tags.end());
        carry_tags(tags, first, static_cast<uint64_t>(n));
        consume_each(n);
    }
    for (uint64_t t = (first + L - 1) / L * L; t < first + static_cast<uint64_t>(n); t += L)
        add_item_tag(0, t, d_frame_key, pmt::from_uint64(d_next_frame++));
    return n;
}

} // namespace sems
} // namespace gr
