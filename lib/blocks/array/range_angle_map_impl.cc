// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: range_angle_map implementation (see range_angle_map.h). */
#include "blocks/common/block_mask.h"
#include "blocks/array/range_angle_map_impl.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/array/array_setting.h>
#include <algorithm>
#include <stdexcept>

namespace gr {
namespace sems {

range_angle_map::sptr range_angle_map::make(const std::string& array,
                                            const std::string& mask_file,
                                            const std::vector<int>& pilot_positions,
                                            int n_symbols,
                                            int n_subcarriers,
                                            double carrier_hz,
                                            int n_angles,
                                            const std::string& window)
{
    const char* const who = range_angle_map_impl::who;
    const array_geometry a = array_from_setting(array, who);
    frame_settings fs;
    fs.carrier_hz = carrier_hz;
    if (!(std::isfinite(carrier_hz) && carrier_hz > 0.0))
        throw std::invalid_argument(std::string(who) + ": carrier_hz must be > 0, got " + std::to_string(carrier_hz));
    auto mask = block_mask_one_frame(who, n_symbols, n_subcarriers, mask_file, pilot_positions, std::nullopt);
    try {
        return gnuradio::make_block_sptr<range_angle_map_impl>(mask, a, fs.wavelength_m(), n_angles, window);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(who) + ": " + e.what());
    }
}

range_angle_map_impl::range_angle_map_impl(const pilot_mask& mask, const array_geometry& array, double wavelength_m,
                                           int n_angles, const std::string& window)
    : gr::block(who,
                gr::io_signature::make(1, 1, sizeof(gr_complex) * mask.size() * array.n_receive()),
                gr::io_signature::make(1, 1, sizeof(float) * size_t(n_angles > 0 ? n_angles : 1) * mask.n_subcarriers())),
      frame_map_block(mask.size() * array.n_receive(), mask, array, wavelength_m, n_angles, window),
      d_k(array.n_receive()),
      d_np(mask.size())
{
}

} // namespace sems
} // namespace gr
