// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: target_channel implementation (see target_channel.h). */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_TARGET_CHANNEL_IMPL_H
#define INCLUDED_SEMS_LIB_BLOCKS_TARGET_CHANNEL_IMPL_H

#include "blocks/common/channel_block_common.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include "blocks/common/fault_log.h"
#include <gnuradio/sems/blocks/target_channel.h>
#include <pmt/pmt.h>
#include <atomic>
#include <optional>

namespace gr {
namespace sems {

class target_channel_impl : public target_channel
{
public:
    //! The block's name, in its GNU Radio identity and in every message it raises.
    static constexpr const char* who = "target_channel";

    target_channel_impl(channel_model model, double snr_db, int n_receive, int n_transmit);

    void set_snr_db(double snr_db) override;
    double snr_db() const override;
    const frame_settings& settings() const override { return d_model.settings(); }
    std::string scene_json() const override { return d_model.scene_spec().to_json_string(); }
    uint64_t frames() const override { return d_frames; }
    uint64_t nonfinite_symbols() const override { return d_nonfinite; }
    // Frames whose computation threw inside work(): sent as NaN, so the extractor counts
    // them as skipped; the first fault of each kind is logged.
    uint64_t frames_faulted() const { return d_faulted; }

    int work(int noutput_items, gr_vector_const_void_star& input_items, gr_vector_void_star& output_items) override;

private:
    void start_frame(uint64_t frame, uint64_t out_offset);
    // Symbol i of the work call on every output: its channel, summed over the inputs, and noise.
    void apply_symbol(const gr_vector_const_void_star& input_items, gr_vector_void_star& output_items, int i);

    channel_model d_model;
    const int d_n, d_m;
    const int d_rx, d_tx; // outputs (receive elements), inputs (transmit elements)
    std::atomic<double> d_snr_db; // requested (setters and getters run on other threads)
    double d_frame_snr_db; // the current frame's

    frame_realization d_realization;        // the current frame's draw, buffers reused
    array_channel d_channels;               // the current frame's factors, one per stream
    std::vector<gr_complex> d_sum;          // several transmit elements: one's contribution
    int d_row = 0;                           // next row of the current frame
    uint64_t d_frame = 0;
    bool d_started = false;

    std::atomic<uint64_t> d_frames{ 0 };    // counters, read from other threads
    std::atomic<uint64_t> d_nonfinite{ 0 };
    std::atomic<uint64_t> d_faulted{ 0 };   // frames whose computation threw (sent as NaN)
    bool d_frame_faulted = false;
    detail::fault_log d_faults;

    const pmt::pmt_t d_frame_key;
    detail::truth_dict d_truth; // caches the previous frame's dict
    std::vector<gr::tag_t> d_tags;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_TARGET_CHANNEL_IMPL_H */
