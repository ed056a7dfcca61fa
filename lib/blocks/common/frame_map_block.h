// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what the map blocks share (internal): one frame's pilot observations in, its map
 * out (range_doppler_map, range_angle_map). A frame with a NaN/Inf observation is skipped and
 * counted; each map carries its frame's tags. `Map` is the core map (compute(in, out),
 * map_size()); `Block` the block's public interface (a gr::block). */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_FRAME_MAP_BLOCK_H
#define INCLUDED_SEMS_LIB_BLOCKS_FRAME_MAP_BLOCK_H

#include "blocks/common/stream_values.h"
#include <gnuradio/block.h>
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <utility>
#include <vector>

namespace gr {
namespace sems {
namespace detail {

template <class Block, class Map>
class frame_map_block : public Block
{
public:
    // in_len: observations per frame; then the core map's arguments. gr::block, a virtual
    // base, is constructed by the most-derived class (the block's name and signatures).
    template <class... Args>
    explicit frame_map_block(int in_len, Args&&... map_args)
        : d_map(std::forward<Args>(map_args)...), d_in_len(in_len)
    {
        this->set_tag_propagation_policy(gr::block::TPP_DONT); // tags follow their frame by hand (frames may be skipped)
    }

    uint64_t frames_out() const override { return d_frames_out; }
    uint64_t frames_skipped_nonfinite() const override { return d_skipped_nonfinite; }

    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override
    {
        const auto* in = static_cast<const gr_complex*>(input_items[0]);
        auto* out = static_cast<float*>(output_items[0]);
        const int n = std::min(noutput_items, ninput_items[0]);
        const uint64_t nread = this->nitems_read(0), nwritten = this->nitems_written(0);
        int produced = 0;
        for (int i = 0; i < n; ++i) {
            const gr_complex* obs = in + static_cast<size_t>(i) * d_in_len;
            if (!all_finite(obs, d_in_len)) {
                ++d_skipped_nonfinite;
                continue;
            }
            d_map.compute(obs, out + static_cast<size_t>(produced) * d_map.map_size());
            this->get_tags_in_range(d_tags, 0, nread + i, nread + i + 1);
            for (const auto& t : d_tags)
                this->add_item_tag(0, nwritten + produced, t.key, t.value, t.srcid);
            ++produced;
            ++d_frames_out;
        }
        this->consume(0, n);
        return produced;
    }

protected:
    Map d_map;
    const int d_in_len;

private:
    std::atomic<uint64_t> d_frames_out{ 0 }, d_skipped_nonfinite{ 0 };
    std::vector<gr::tag_t> d_tags;
};

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_FRAME_MAP_BLOCK_H */
