// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: frame_sync implementation (see frame_sync.h). */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_FRAME_SYNC_IMPL_H
#define INCLUDED_SEMS_LIB_BLOCKS_FRAME_SYNC_IMPL_H

#include "blocks/common/frame_spacing.h"
#include <gnuradio/sems/blocks/frame_sync.h>
#include <gnuradio/sems/core/frame/frame_search.h>
#include <pmt/pmt.h>
#include <atomic>
#include <string>
#include <vector>

namespace gr {
namespace sems {

class frame_sync_impl : public frame_sync
{
public:
    //! The block's name, in its GNU Radio identity and in every message it raises.
    static constexpr const char* who = "frame_sync";

    frame_sync_impl(frame_search search, int n_symbols, int n_subcarriers, int cp_len);

    bool locked() const override { return d_locked; }
    int64_t offset() const override { return d_offset; }
    double metric() const override { return d_metric; }
    uint64_t failures() const override { return d_failures; }
    int frame_len() const override { return d_search.frame_len(); }
    std::string stream_error() const override { return d_spacing.error(); }

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

private:
    const frame_search d_search;
    std::atomic<bool> d_locked{ false };
    std::atomic<int64_t> d_offset{ -1 };
    std::atomic<double> d_metric{ 0.0 };
    std::atomic<uint64_t> d_failures{ 0 };
    uint64_t d_next_frame = 0; // index of the next frame tag
    // Searching: the samples not yet dropped (any upstream buffer size works), starting at
    // stream offset d_buf_start. Locked: the found frame's samples still to be output.
    std::vector<gr_complex> d_buf;
    uint64_t d_buf_start = 0;
    size_t d_pending_pos = 0;
    // The tags of the buffered input (d_buf), other than frame tags, at their input offsets:
    // they go out at input offset − d_offset once locked (those before the frame are dropped).
    std::vector<gr::tag_t> d_buf_tags;
    const pmt::pmt_t d_frame_key, d_port;
    detail::frame_spacing_check d_spacing; // the incoming frame tags' cyclic prefix

    //! Checks the incoming frame tags' spacing; false (and the error logged) on a mismatch.
    bool check_spacing(const std::vector<gr::tag_t>& tags);

    //! Adds `tags` at output offsets (input offset − d_offset) that fall in [first, first + n).
    void carry_tags(const std::vector<gr::tag_t>& tags, uint64_t first, uint64_t n);
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_FRAME_SYNC_IMPL_H */
