// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: target_channel_td implementation (see target_channel_td.h). */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_TARGET_CHANNEL_TD_IMPL_H
#define INCLUDED_SEMS_LIB_BLOCKS_TARGET_CHANNEL_TD_IMPL_H

#include "blocks/common/channel_block_common.h"
#include "blocks/common/frame_spacing.h"
#include <gnuradio/sems/blocks/target_channel_td.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/channel/td_channel.h>
#include <atomic>
#include <string>

namespace gr {
namespace sems {

class target_channel_td_impl : public target_channel_td
{
public:
    //! The block's name, in its GNU Radio identity and in every message it raises.
    static constexpr const char* who = "target_channel_td";

    target_channel_td_impl(channel_model model, double snr_db, int n_receive, int n_transmit);

    void set_snr_db(double snr_db) override;
    double snr_db() const override;
    const frame_settings& settings() const override { return d_model.settings(); }
    std::string scene_json() const override { return d_model.scene_spec().to_json_string(); }
    uint64_t frames() const override { return d_frames; }
    uint64_t nonfinite_symbols() const override { return d_nonfinite; }
    uint64_t misaligned_tags() const override { return d_misaligned; }
    std::string stream_error() const override { return d_spacing.error(); }

    int work(int noutput_items, gr_vector_const_void_star& input_items, gr_vector_void_star& output_items) override;

private:
    void start_frame(uint64_t frame, uint64_t out_offset);

    channel_model d_model;
    std::vector<td_channel> d_td; // one per stream (channel_model::elements())
    const int d_rx, d_tx;         // outputs (receive elements), inputs (transmit elements)
    const int d_n, d_s;
    std::vector<gr_complex> d_sum; // several transmit elements: one's contribution
    std::atomic<double> d_snr_db; // requested (setters and getters run on other threads)
    double d_frame_snr_db;        // the current frame's

    int d_row = 0; // next symbol of the current frame
    uint64_t d_frame = 0;
    bool d_started = false;

    std::atomic<uint64_t> d_frames{ 0 };
    std::atomic<uint64_t> d_nonfinite{ 0 };
    std::atomic<uint64_t> d_misaligned{ 0 };

    const pmt::pmt_t d_frame_key;
    detail::truth_dict d_truth; // caches the previous frame's dict
    std::vector<gr::tag_t> d_tags;
    detail::frame_spacing_check d_spacing; // the stream's cyclic prefix, from its frame tags
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_TARGET_CHANNEL_TD_IMPL_H */
