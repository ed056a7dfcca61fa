// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: range_doppler_map implementation (see range_doppler_map.h). */
#include "blocks/common/block_mask.h"
#include "blocks/range_doppler_map_impl.h"
#include "blocks/common/stream_values.h"
#include <gnuradio/io_signature.h>
#include <algorithm>

namespace gr {
namespace sems {

static const char* const who = "range_doppler_map";

range_doppler_map::sptr range_doppler_map::make(const std::string& mask_file,
                                                const std::vector<int>& pilot_positions,
                                                int n_symbols,
                                                int n_subcarriers,
                                                const std::string& window)
{
    auto mask = block_mask_one_frame(who, n_symbols, n_subcarriers, mask_file, pilot_positions, gr_complex(1.0f, 0.0f));
    return gnuradio::make_block_sptr<range_doppler_map_impl>(mask, window);
}

range_doppler_map_impl::range_doppler_map_impl(const pilot_mask& mask, const std::string& window)
    : gr::block(who,
                gr::io_signature::make(1, 1, sizeof(gr_complex) * mask.size()),
                gr::io_signature::make(1, 1, sizeof(float) * mask.n_symbols() * mask.n_subcarriers())),
      d_map(mask, window),
      d_np(mask.size())
{
    set_tag_propagation_policy(TPP_DONT); // tags follow their frame by hand (frames may be skipped)
}

int range_doppler_map_impl::general_work(int noutput_items,
                                         gr_vector_int& ninput_items,
                                         gr_vector_const_void_star& input_items,
                                         gr_vector_void_star& output_items)
{
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<float*>(output_items[0]);
    const int n = std::min(noutput_items, ninput_items[0]);
    const uint64_t nread = nitems_read(0), nwritten = nitems_written(0);
    int produced = 0;
    for (int i = 0; i < n; ++i) {
        const gr_complex* obs = in + static_cast<size_t>(i) * d_np;
        if (!detail::all_finite(obs, d_np)) {
            ++d_skipped_nonfinite;
            continue;
        }
        d_map.compute(obs, out + static_cast<size_t>(produced) * d_map.map_size());
        get_tags_in_range(d_tags, 0, nread + i, nread + i + 1);
        for (const auto& t : d_tags)
            add_item_tag(0, nwritten + produced, t.key, t.value, t.srcid);
        ++produced;
        ++d_frames_out;
    }
    consume(0, n);
    return produced;
}

} // namespace sems
} // namespace gr
