// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: mimo_pilot_mapper implementation (see mimo_pilot_mapper.h). */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_MIMO_PILOT_MAPPER_IMPL_H
#define INCLUDED_SEMS_LIB_BLOCKS_MIMO_PILOT_MAPPER_IMPL_H

#include <gnuradio/sems/blocks/mimo_pilot_mapper.h>
#include <pmt/pmt.h>
#include <atomic>

namespace gr {
namespace sems {

class mimo_pilot_mapper_impl : public mimo_pilot_mapper
{
public:
    //! The block's name, in its GNU Radio identity and in every message it raises.
    static constexpr const char* who = "mimo_pilot_mapper";

    mimo_pilot_mapper_impl(const mimo_mask& mask,
                           double pilot_power,
                           double data_power,
                           const std::vector<int>& guard_subcarriers);

    void set_pilot_power(double energy) override;
    double pilot_power() const override;
    void set_data_power(double energy) override;
    double data_power() const override;
    const mimo_mask& mask() const override { return d_mask; }
    int data_per_frame() const override { return d_data_per_frame; }
    uint64_t frames() const override { return d_frames; }

    bool check_topology(int ninputs, int noutputs) override;
    void forecast(int noutput_items, gr_vector_int& ninput_items_required) override;
    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

private:
    void latch(double pilot_energy, double data_energy);

    const mimo_mask d_mask;
    const int d_n, d_m, d_nt;
    // Per row n: the subcarriers that carry pilots (and the pilots' indices) and data, ascending.
    std::vector<std::vector<int>> d_pilot_cols, d_pilot_index, d_data_cols;
    std::vector<long> d_data_before_row; // data symbols in rows [0, n), n = 0..N
    std::vector<int> d_guard_cols;
    int d_data_per_frame;

    std::atomic<double> d_pilot_power, d_data_power;
    std::vector<gr_complex> d_values; // per element j and pilot k: a_kj·sqrt(E_p)·(the mask's pilot k), j-major
    float d_data_amp;                 // sqrt(E_d / N_t)

    int d_row = 0;
    uint64_t d_frame = 0;
    std::atomic<uint64_t> d_frames{ 0 };
    const pmt::pmt_t d_frame_key;
    std::vector<gr::tag_t> d_tags;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_MIMO_PILOT_MAPPER_IMPL_H */
