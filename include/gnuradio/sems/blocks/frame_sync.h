// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: frame alignment of a CP-OFDM sample stream whose start is unknown (a file, an
 * SDR): finds the frame start from the known pilots (core frame_search: correlation with
 * the pilots' time-domain template over `search_frames` frames), drops the samples before
 * it, and from there passes the stream on with a keys::frame_tag (frame index from 0) on the
 * first sample of every frame, so ofdm_rx and the extractor get whole frames.
 *
 * Until a frame is found it outputs nothing: each search that finds no frame (F·L·ρ below
 * the threshold; noise alone) is counted in failures() and the window slides by one frame.
 * The offset found (samples from the stream start) is offset() and goes out as a dict
 * {offset, metric, failures} (keys::sync_offset, sync_metric, sync_failures) on the message
 * port "sync" (keys::sync_port). Once locked it stays locked (an
 * offset calibrated once, as on a loopback); frame_search.h states what the search assumes.
 *
 * On a monostatic radio the transmitter's leakage (delay 0, static, far above the echoes)
 * is what it locks to: the frame start itself, the right timing for ranging (cancel the
 * leakage after this block, sems::leakage_canceller). Without leakage it times from the
 * pilots of the strongest echo (`noncoherent` combining, as the echo's phase turns from
 * frame to frame): the offset then absorbs that echo's delay, and every range is relative
 * to it unless the offset is calibrated once on the direct path
 * (examples/sems_offset_calibration.grc). False locks per frame of noise:
 * frame_search::false_lock_probability() (3.6e-8 coherent at the defaults; measured by
 * apps/evaluation/sems_sync_false_lock.cc, docs/reference/sdr_receiver.md).
 *
 * Every other input tag (a replayed keys::truth_tag, ...) goes out on the same sample, at
 * output offset = input offset − offset(); tags on the dropped samples are dropped with them,
 * and incoming keys::frame_tag tags are dropped (the frames are numbered here). Incoming
 * frame tags spaced other than N·(M + cp_len) samples per frame (a transmitter with another
 * cyclic prefix) stop the stream (WORK_DONE) with an error, kept in stream_error(), that names
 * both prefix lengths when the spacing fits one.
 */
#ifndef INCLUDED_SEMS_BLOCKS_FRAME_SYNC_H
#define INCLUDED_SEMS_BLOCKS_FRAME_SYNC_H

#include <gnuradio/block.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Finds the frame start in a sample stream from the known pilots and tags frames.
 * \details Frame check: a mask file carries only its grid, refused unless it is n_symbols x
 * n_subcarriers (pilot_mask::check_frame names the field and both values); a mask has no CP to
 * compare with cp_len, and the block has no guard, bandwidth, carrier or symbol-interval
 * parameter, so it cannot compare those.
 * \ingroup sems
 */
class SEMS_API frame_sync : virtual public gr::block
{
public:
    typedef std::shared_ptr<frame_sync> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes a frame synchroniser.
     * \param mask_file      pilot mask file (or "" with pilot_positions)
     * \param pilot_positions flat pilot indices n·M + m (or empty with mask_file)
     * \param n_symbols      N
     * \param n_subcarriers  M
     * \param pilot_symbol   s_p
     * \param pilot_power    E_p, as in the pilot mapper
     * \param cp_len         cyclic prefix (samples)
     * \param search_frames  F, frames correlated per search (>= 1)
     * \param threshold      detection threshold on the metric (frame_search.h)
     * \param noncoherent    combine the F frames in power (an echo whose phase changes
     *                       from frame to frame); then raise the threshold, see
     *                       frame_search::threshold_for()
     * \return the block.
     * \throws std::invalid_argument naming the parameter.
     */
    static sptr make(const std::string& mask_file = "",
                     const std::vector<int>& pilot_positions = {},
                     int n_symbols = frame_settings{}.n_symbols,
                     int n_subcarriers = frame_settings{}.n_subcarriers,
                     gr_complex pilot_symbol = gr_complex(1.0f, 0.0f),
                     double pilot_power = 1.0,
                     int cp_len = frame_settings{}.cp_len,
                     int search_frames = 4,
                     double threshold = 25.0,
                     bool noncoherent = false);

    virtual bool locked() const = 0;          //!< \return whether the frame start was found
    virtual int64_t offset() const = 0;      //!< \return samples dropped before the first frame; -1 until found
    virtual double metric() const = 0;        //!< \return F·L·ρ of the last search
    virtual uint64_t failures() const = 0;    //!< \return searches that found no frame
    virtual int frame_len() const = 0;        //!< \return L = N·(M + cp_len)
    /*!
     * \brief Why the block stopped the stream, empty while it runs: incoming frame tags
     *        spaced for another cyclic prefix (the message names both prefix lengths when the
     *        spacing fits one).
     * \return the error message, or "".
     */
    virtual std::string stream_error() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BLOCKS_FRAME_SYNC_H */
