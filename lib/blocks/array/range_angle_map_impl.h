// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: range_angle_map implementation (see range_angle_map.h). */
#ifndef INCLUDED_SEMS_RANGE_ANGLE_MAP_IMPL_H
#define INCLUDED_SEMS_RANGE_ANGLE_MAP_IMPL_H

#include "blocks/common/frame_map_block.h"
#include <gnuradio/sems/blocks/range_angle_map.h>
#include <gnuradio/sems/core/array/range_angle.h>

namespace gr {
namespace sems {

class range_angle_map_impl : public detail::frame_map_block<range_angle_map, range_angle>
{
public:
    //! The block's name, in its GNU Radio identity and in every message it raises.
    static constexpr const char* who = "range_angle_map";

    range_angle_map_impl(const pilot_mask& mask, const array_geometry& array, double wavelength_m, int n_angles,
                         const std::string& window);

    int n_elements() const override { return d_k; }
    int n_pilots() const override { return d_np; }
    int n_angles() const override { return d_map.n_angles(); }

private:
    const int d_k, d_np;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_RANGE_ANGLE_MAP_IMPL_H */
