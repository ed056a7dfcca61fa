// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: pilot_mapper implementation (see pilot_mapper.h). */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_PILOT_MAPPER_IMPL_H
#define INCLUDED_SEMS_LIB_BLOCKS_PILOT_MAPPER_IMPL_H

#include <gnuradio/sems/blocks/pilot_mapper.h>
#include <pmt/pmt.h>
#include <atomic>

namespace gr {
namespace sems {

class pilot_mapper_impl : public pilot_mapper
{
public:
    //! The block's name, in its GNU Radio identity and in every message it raises.
    static constexpr const char* who = "pilot_mapper";

    pilot_mapper_impl(const super_frame_mask& mask,
                      double pilot_power,
                      double data_power,
                      const std::vector<int>& guard_subcarriers);

    void set_pilot_power(double energy) override;
    double pilot_power() const override;
    void set_data_power(double energy) override;
    double data_power() const override;

    const pilot_mask& mask() const override { return d_mask.set(0); }
    const super_frame_mask& super_frame() const override { return d_mask; }
    int n_pilots() const override { return d_mask.pilots_per_frame(); }
    int data_per_frame() const override { return d_data_per_frame; }
    uint64_t frames() const override { return d_frames; }

    bool check_topology(int ninputs, int noutputs) override;
    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

private:
    // The pilots' values of a frame at pilot energy `energy` (E_p).
    void latch_pilot_values(double energy);

    // One frame's pilot set, laid out for the row loop.
    struct pilot_set {
        // Per row n: which subcarriers carry pilots and which carry data (ascending).
        std::vector<std::vector<int>> pilot_cols, data_cols;
        std::vector<long> data_before_row;  // data symbols in rows [0, n), n = 0..N
        std::vector<int> pilots_before_row; // pilots in rows [0, n), n = 0..N
    };
    // The set of frame f (f mod F).
    const pilot_set& set_of(uint64_t frame) const { return d_sets[frame % d_sets.size()]; }

    const super_frame_mask d_mask;
    const int d_n, d_m;
    std::vector<pilot_set> d_sets;       // per frame of the super-frame
    std::vector<int> d_guard_cols;       // zero in every symbol
    int d_data_per_frame;                // the same for every set: N·(M − G) − N_p

    // Requested energies (setters and getters run on other threads than work) and the
    // amplitudes of the current frame.
    std::atomic<double> d_pilot_power, d_data_power;
    std::vector<gr_complex> d_pilot_values; // sqrt(E_p·p_k)·s_p per pilot of the frame's set, mask order
    float d_data_amp;         // sqrt(E_d)

    int d_row = 0;          // next row of the current frame
    uint64_t d_frame = 0;   // index of the frame that row belongs to
    std::atomic<uint64_t> d_frames{ 0 }; // frames started (read from other threads)
    const pmt::pmt_t d_frame_key;
    std::vector<gr::tag_t> d_tags;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_PILOT_MAPPER_IMPL_H */
