// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: pilot_extractor implementation (see pilot_extractor.h). */
#include "blocks/common/block_mask.h"
#include "blocks/pilot_extractor_impl.h"
#include "blocks/common/stream_values.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/common/tags.h>
#include <gnuradio/sems/core/common/limits.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

pilot_extractor::sptr pilot_extractor::make(const std::string& mask_file,
                                            const std::vector<int>& pilot_positions,
                                            int n_symbols,
                                            int n_subcarriers,
                                            gr_complex pilot_symbol,
                                            int n_elements)
{
    const char* const who = pilot_extractor_impl::who;
    if (n_elements < 1 || n_elements > limits::max_array_elements)
        throw std::invalid_argument(std::string(who) + ": n_elements must be in [1, " +
                                    std::to_string(limits::max_array_elements) +
                                    "] (one input per receive element), got " + std::to_string(n_elements));
    auto mask = block_mask(who, n_symbols, n_subcarriers, mask_file, pilot_positions, pilot_symbol, true);
    return gnuradio::make_block_sptr<pilot_extractor_impl>(mask, n_elements);
}

pilot_extractor_impl::pilot_extractor_impl(const super_frame_mask& mask, int n_elements)
    : gr::block(who,
                gr::io_signature::make(n_elements, n_elements, sizeof(gr_complex) * mask.n_subcarriers()),
                gr::io_signature::make(1, 1, sizeof(gr_complex) * mask.pilots_per_frame() * n_elements)),
      d_mask(mask),
      d_n(mask.n_symbols()),
      d_m(mask.n_subcarriers()),
      d_np(mask.pilots_per_frame()),
      d_k(n_elements),
      d_obs(size_t(d_np) * n_elements),
      d_frame_key(pmt::intern(keys::frame_tag))
{
    for (const auto& set : d_mask.sets()) {
        pilot_set s;
        s.first_of_row.assign(d_n + 1, 0);
        for (int k = 0; k < d_np; ++k) // Y/x_k = H + noise/sqrt(p_k), x_k = sqrt(p_k)·s_p·exp(jφ_k)
            s.values.push_back(set.transmitted_pilot(k));
        for (const auto& p : set.positions()) { // mask order: sorted by (n, m)
            s.cols.push_back(p.m);
            ++s.first_of_row[p.n + 1];
        }
        for (int n = 0; n < d_n; ++n)
            s.first_of_row[n + 1] += s.first_of_row[n];
        d_sets.push_back(std::move(s));
    }
    d_set = &d_sets.front();
    set_relative_rate(1, static_cast<uint64_t>(d_n));
    set_tag_propagation_policy(TPP_DONT); // tags are carried by hand, frame by frame
    d_frame_tags.reserve(16);
    d_tags.reserve(64);
}

void pilot_extractor_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    // The frame state persists across calls, so any input is progress; asking for a
    // whole frame could exceed a small upstream buffer.
    for (auto& n : ninput_items_required)
        n = 1;
}

bool pilot_extractor_impl::stop()
{
    if (d_row > 0) { // the stream ended (or was stopped) inside a frame
        ++d_dropped_partial;
        d_row = 0;
    }
    return true;
}

void pilot_extractor_impl::begin_frame(bool tagged, uint64_t frame)
{
    d_row = 0;
    d_tagged = tagged;
    d_nonfinite = false;
    d_frame = frame;
    d_set = &d_sets[frame % d_sets.size()]; // the super-frame's set of this frame
    d_started = true;
    d_frame_tags.clear();
}

int pilot_extractor_impl::general_work(int noutput_items,
                                       gr_vector_int& ninput_items,
                                       gr_vector_const_void_star& input_items,
                                       gr_vector_void_star& output_items)
{
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const int avail = *std::min_element(ninput_items.begin(), ninput_items.end()); // the elements in lockstep
    const uint64_t nread = nitems_read(0), nwritten = nitems_written(0);

    get_tags_in_range(d_tags, 0, nread, nread + static_cast<uint64_t>(avail));
    size_t next_tag = 0;

    int consumed = 0, produced = 0;
    while (consumed < avail && produced < noutput_items) {
        const uint64_t offset = nread + static_cast<uint64_t>(consumed);

        // A frame tag on this symbol starts a frame; any other tag rides with the frame.
        bool tagged = false;
        uint64_t tagged_frame = 0;
        const size_t first_tag = next_tag;
        for (; next_tag < d_tags.size() && d_tags[next_tag].offset == offset; ++next_tag) {
            if (!pmt::eqv(d_tags[next_tag].key, d_frame_key))
                continue;
            const auto index = detail::frame_index_of(d_tags[next_tag].value);
            tagged = true;
            tagged_frame = index ? *index : (d_started ? d_frame + 1 : 0); // unreadable: keep counting
        }
        if (tagged) {
            if (d_row > 0)
                ++d_dropped_partial; // the previous frame ended before N symbols
            begin_frame(true, tagged_frame);
        } else if (d_row == 0) {
            begin_frame(false, d_started ? d_frame + 1 : 0);
        }
        for (size_t t = first_tag; t < next_tag; ++t)
            if (!pmt::eqv(d_tags[t].key, d_frame_key))
                d_frame_tags.push_back(d_tags[t]);

        const pilot_set& set = *d_set;
        for (int e = 0; e < d_k; ++e) {
            const gr_complex* y = static_cast<const gr_complex*>(input_items[e]) + static_cast<size_t>(consumed) * d_m;
            d_nonfinite = d_nonfinite || !detail::all_finite(y, d_m);
            gr_complex* obs = d_obs.data() + static_cast<size_t>(e) * d_np;
            for (int k = set.first_of_row[d_row]; k < set.first_of_row[d_row + 1]; ++k)
                obs[k] = y[set.cols[k]] / set.values[k];
        }
        ++consumed;

        if (++d_row < d_n)
            continue;
        // A whole frame.
        if (d_nonfinite) {
            ++d_skipped_nonfinite;
        } else {
            const uint64_t out_offset = nwritten + static_cast<uint64_t>(produced);
            std::copy(d_obs.begin(), d_obs.end(), out + static_cast<size_t>(produced) * d_obs.size());
            add_item_tag(0, out_offset, d_frame_key, pmt::from_uint64(d_frame), alias_pmt());
            for (const auto& t : d_frame_tags)
                add_item_tag(0, out_offset, t.key, t.value, t.srcid);
            ++produced;
            ++d_frames_out;
        }
        d_row = 0;
        d_frame_tags.clear();
    }
    consume_each(consumed);
    return produced;
}

} // namespace sems
} // namespace gr
