// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: range_doppler_map implementation (see range_doppler_map.h). */
#ifndef INCLUDED_SEMS_RANGE_DOPPLER_MAP_IMPL_H
#define INCLUDED_SEMS_RANGE_DOPPLER_MAP_IMPL_H

#include "blocks/common/frame_map_block.h"
#include <gnuradio/sems/blocks/range_doppler_map.h>
#include <gnuradio/sems/core/channel/range_doppler.h>

namespace gr {
namespace sems {

class range_doppler_map_impl : public detail::frame_map_block<range_doppler_map, range_doppler>
{
public:
    //! The block's name, in its GNU Radio identity and in every message it raises.
    static constexpr const char* who = "range_doppler_map";

    range_doppler_map_impl(const pilot_mask& mask, const std::string& window);

    int n_pilots() const override { return d_in_len; }
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_RANGE_DOPPLER_MAP_IMPL_H */
