// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: range_doppler_map implementation (see range_doppler_map.h). */
#ifndef INCLUDED_SEMS_RANGE_DOPPLER_MAP_IMPL_H
#define INCLUDED_SEMS_RANGE_DOPPLER_MAP_IMPL_H

#include <gnuradio/sems/blocks/range_doppler_map.h>
#include <gnuradio/sems/core/channel/range_doppler.h>
#include <atomic>

namespace gr {
namespace sems {

class range_doppler_map_impl : public range_doppler_map
{
public:
    range_doppler_map_impl(const pilot_mask& mask, const std::string& window);

    int n_pilots() const override { return d_np; }
    uint64_t frames_out() const override { return d_frames_out; }
    uint64_t frames_skipped_nonfinite() const override { return d_skipped_nonfinite; }

    int general_work(int noutput_items,
                     gr_vector_int& ninput_items,
                     gr_vector_const_void_star& input_items,
                     gr_vector_void_star& output_items) override;

private:
    range_doppler d_map;
    const int d_np;
    std::atomic<uint64_t> d_frames_out{ 0 }, d_skipped_nonfinite{ 0 };
    std::vector<gr::tag_t> d_tags;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_RANGE_DOPPLER_MAP_IMPL_H */
