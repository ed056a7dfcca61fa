// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a time-domain block's check that the stream's frames have its cyclic prefix (internal).
 *
 * ofdm_tx moves each frame's sems_frame tag to the frame's first sample, so the tags of
 * frames f and f + 1 lie N·(M + CP_tx) samples apart. A block built with another cp_len would
 * cut every symbol at the wrong place and answer garbage without a word: it reads the
 * transmitter's prefix from the tags' spacing and refuses the stream, naming both values.
 */
#ifndef INCLUDED_SEMS_LIB_BLOCKS_FRAME_SPACING_H
#define INCLUDED_SEMS_LIB_BLOCKS_FRAME_SPACING_H

#include "blocks/common/stream_values.h"
#include <gnuradio/logger.h>
#include <gnuradio/tags.h>
#include <atomic>
#include <cstdint>
#include <string>

namespace gr {
namespace sems {
namespace detail {

class frame_spacing_check
{
public:
    frame_spacing_check(const char* who, int n_symbols, int n_subcarriers, int cp_len)
        : d_who(who), d_n(n_symbols), d_m(n_subcarriers), d_cp(cp_len)
    {
    }

    // A sems_frame tag of the input; false after a mismatch (the error logged and kept).
    bool check(const gr::tag_t& tag, const gr::logger_ptr& logger)
    {
        auto error = observe(tag.offset, tag.value);
        if (error.empty())
            return true;
        d_error = std::move(error);
        d_failed = true;
        logger->error("{}", d_error);
        return false;
    }

    // The mismatch that stopped the stream, "" while it runs (any thread).
    std::string error() const { return d_failed ? d_error : std::string(); }

    // A sems_frame tag at stream offset `offset`; returns the error ("" when consistent).
    // Tags come in stream order. Only consecutive frames (index f after f − 1) are compared:
    // an unreadable value, a jump or a restarted count starts a new reference.
    std::string observe(uint64_t offset, const pmt::pmt_t& value)
    {
        const auto index = frame_index_of(value);
        if (!index)
            return {};
        const bool next = d_have && *index == d_index + 1 && offset > d_offset;
        const uint64_t samples = offset - d_offset, previous = d_index;
        d_have = true;
        d_index = *index;
        d_offset = offset;
        const uint64_t expected = static_cast<uint64_t>(d_n) * static_cast<uint64_t>(d_m + d_cp);
        if (!next || samples == expected)
            return {};
        std::string msg = std::string(d_who) + ": the input's sems_frame tags put frame " + std::to_string(*index) +
                          " " + std::to_string(samples) + " samples after frame " + std::to_string(previous) +
                          ", this block expects N·(M + cp_len) = " + std::to_string(d_n) + "·(" +
                          std::to_string(d_m) + " + " + std::to_string(d_cp) + ") = " + std::to_string(expected) +
                          ": ";
        const uint64_t n = static_cast<uint64_t>(d_n);
        if (samples % n == 0 && samples / n >= static_cast<uint64_t>(d_m))
            msg += "the transmitter's cyclic prefix is " + std::to_string(samples / n - d_m) +
                   " samples, this block's cp_len is " + std::to_string(d_cp) + ". ";
        else
            msg += "the frames are not N·(M + CP) samples apart for any cyclic prefix CP. ";
        return msg + "Give SemS OFDM TX, target_channel_td, frame_sync and SemS OFDM RX the same cp_len.";
    }

private:
    const char* d_who;
    int d_n, d_m, d_cp;
    bool d_have = false;
    uint64_t d_index = 0, d_offset = 0;
    std::string d_error;               // written once, before d_failed is set
    std::atomic<bool> d_failed{ false };
};

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_BLOCKS_FRAME_SPACING_H */
