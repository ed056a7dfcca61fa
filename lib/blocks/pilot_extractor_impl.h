// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: pilot_extractor implementation (see pilot_extractor.h). */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_PILOT_EXTRACTOR_IMPL_H
#define INCLUDED_SEMS_LIB_BLOCKS_PILOT_EXTRACTOR_IMPL_H

#include <gnuradio/sems/blocks/pilot_extractor.h>
#include <pmt/pmt.h>
#include <atomic>

namespace gr {
namespace sems {

class pilot_extractor_impl : public pilot_extractor
{
public:
    //! The block's name, in its GNU Radio identity and in every message it raises.
    static constexpr const char* who = "pilot_extractor";

    pilot_extractor_impl(const super_frame_mask& mask, int n_elements);

    const pilot_mask& mask() const override { return d_mask.set(0); }
    const super_frame_mask& super_frame() const override { return d_mask; }
    int n_pilots() const override { return d_np; }
    int n_elements() const override { return d_k; }
    uint64_t frames_out() const override { return d_frames_out; }
    uint64_t frames_dropped_partial() const override { return d_dropped_partial; }
    uint64_t frames_skipped_nonfinite() const override { return d_skipped_nonfinite; }

    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    bool stop() override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

private:
    void begin_frame(bool tagged, uint64_t frame);

    // One frame's pilot set, laid out for the row loop.
    struct pilot_set {
        std::vector<gr_complex> values; // the transmitted pilot sqrt(p_k)·s_p, mask order
        std::vector<int> cols;          // subcarrier of each pilot, mask order
        std::vector<int> first_of_row;  // pilots of row n: [first_of_row[n], first_of_row[n+1])
    };

    const super_frame_mask d_mask;
    const int d_n, d_m, d_np, d_k; // N, M, N_p, the elements
    std::vector<pilot_set> d_sets; // per frame of the super-frame
    const pilot_set* d_set;        // the current frame's

    // The frame being collected.
    std::vector<gr_complex> d_obs; // K x N_p, element-major
    std::vector<gr::tag_t> d_frame_tags;
    int d_row = 0;           // symbols collected
    bool d_tagged = false;   // started at a frame tag
    bool d_nonfinite = false;
    uint64_t d_frame = 0;
    bool d_started = false;

    // Counters, read from other threads.
    std::atomic<uint64_t> d_frames_out{ 0 }, d_dropped_partial{ 0 }, d_skipped_nonfinite{ 0 };
    const pmt::pmt_t d_frame_key;
    std::vector<gr::tag_t> d_tags;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_PILOT_EXTRACTOR_IMPL_H */
