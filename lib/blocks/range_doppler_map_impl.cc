// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: range_doppler_map implementation (see range_doppler_map.h). */
#include "blocks/common/block_mask.h"
#include "blocks/range_doppler_map_impl.h"
#include <gnuradio/io_signature.h>
#include <algorithm>

namespace gr {
namespace sems {

range_doppler_map::sptr range_doppler_map::make(const std::string& mask_file,
                                                const std::vector<int>& pilot_positions,
                                                int n_symbols,
                                                int n_subcarriers,
                                                const std::string& window)
{
    const char* const who = range_doppler_map_impl::who;
    auto mask = block_mask_one_frame(who, n_symbols, n_subcarriers, mask_file, pilot_positions, std::nullopt);
    return gnuradio::make_block_sptr<range_doppler_map_impl>(mask, window);
}

range_doppler_map_impl::range_doppler_map_impl(const pilot_mask& mask, const std::string& window)
    : gr::block(who,
                gr::io_signature::make(1, 1, sizeof(gr_complex) * mask.size()),
                gr::io_signature::make(1, 1, sizeof(float) * mask.n_symbols() * mask.n_subcarriers())),
      frame_map_block(mask.size(), mask, window)
{
}

} // namespace sems
} // namespace gr
