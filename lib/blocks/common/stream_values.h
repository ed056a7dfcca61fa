// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: reading what streams and tags carry, the same way in every block (internal). */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_STREAM_VALUES_H
#define INCLUDED_SEMS_LIB_BLOCKS_STREAM_VALUES_H

#include "core/common/checks.h"
#include <gnuradio/gr_complex.h>
#include <pmt/pmt.h>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>

namespace gr {
namespace sems {
namespace detail {

// The frame index a sems_frame tag carries: any non-negative integer PMT (uint64 as the
// mapper writes it, or a plain integer from a hand-made tag); nullopt when unreadable.
inline std::optional<uint64_t> frame_index_of(const pmt::pmt_t& v)
{
    if (pmt::is_uint64(v))
        return pmt::to_uint64(v);
    if (pmt::is_integer(v) && pmt::to_long(v) >= 0)
        return static_cast<uint64_t>(pmt::to_long(v));
    return std::nullopt;
}

// A bad frame is counted and skipped, never decoded: the finite check is the shared one.
using checks::all_finite;

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_STREAM_VALUES_H */
