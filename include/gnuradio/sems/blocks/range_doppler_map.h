// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the range-Doppler map block: one gr_complex[N_p] frame of pilot observations
 * in (the pilot extractor's output), one float[N·M] map in dB out (core/channel/range_doppler.h:
 * row d = Doppler bin d - N/2, column q = delay index q). For the full grid, give a mask
 * with every cell a pilot (the extractor then passes the whole grid Y/X).
 *
 * A frame with a NaN/Inf observation is skipped and counted. Each map carries its
 * frame's tags (sems_frame, sems_truth).
 */
#ifndef INCLUDED_SEMS_RANGE_DOPPLER_MAP_H
#define INCLUDED_SEMS_RANGE_DOPPLER_MAP_H

#include <gnuradio/block.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Range-Doppler map of each frame's pilot observations (core/channel/range_doppler.h), in dB.
 * \details Frame check: a mask file carries only its grid, refused unless it is n_symbols x
 * n_subcarriers (pilot_mask::check_frame names the field and both values); the block has no guard,
 * bandwidth, carrier, symbol-interval or CP parameter, so it cannot compare those.
 * \ingroup sems_blocks
 */
class SEMS_API range_doppler_map : virtual public gr::block
{
public:
    typedef std::shared_ptr<range_doppler_map> sptr; //!< shared pointer to the block

    /*!
     * \brief gr_complex[N_p] in, float[N·M] (dB) out, one item per frame.
     * \param mask_file        pilot mask JSON; "" to use pilot_positions
     * \param pilot_positions  flat pilot positions n·M+m; empty to use mask_file
     * \param n_symbols        N
     * \param n_subcarriers    M
     * \param window           "hann" or "rect" (both axes)
     * \return the block.
     * \throws std::invalid_argument naming the parameter and the problem.
     */
    static sptr make(const std::string& mask_file = "",
                     const std::vector<int>& pilot_positions = {},
                     int n_symbols = frame_settings{}.n_symbols,
                     int n_subcarriers = frame_settings{}.n_subcarriers,
                     const std::string& window = "hann");

    /*! \brief N_p. \return the input vector length. */
    virtual int n_pilots() const = 0;
    /*! \brief Maps written. \return the count. */
    virtual uint64_t frames_out() const = 0;
    /*! \brief Frames skipped for a NaN/Inf observation. \return the count. */
    virtual uint64_t frames_skipped_nonfinite() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_RANGE_DOPPLER_MAP_H */
