// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: where the mappers put the tags of their data symbols (internal to the library): a
 * tag on a data symbol moves to the OFDM symbol that carries it; an upstream frame tag is not
 * carried, since a mapper writes its own. pilot_mapper and mimo_pilot_mapper share it. */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_DATA_TAGS_H
#define INCLUDED_SEMS_LIB_BLOCKS_DATA_TAGS_H

#include <gnuradio/tags.h>
#include <pmt/pmt.h>
#include <cstdint>
#include <vector>

namespace gr {
namespace sems {

// Calls place(tag) for each tag of `tags` from `next` on whose input offset is below used_end
// (the data symbols just placed), except frame tags; advances `next` past them.
template <typename Place>
inline void move_data_tags(const std::vector<gr::tag_t>& tags,
                           size_t& next,
                           uint64_t used_end,
                           const pmt::pmt_t& frame_key,
                           Place place)
{
    for (; next < tags.size() && tags[next].offset < used_end; ++next)
        if (!pmt::eqv(tags[next].key, frame_key))
            place(tags[next]);
}

} // namespace sems
} // namespace gr

#endif
