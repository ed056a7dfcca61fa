// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The leakage canceller block: a monostatic radio's received samples minus the
 *        fitted leakage of its own transmission, its IQ image and DC (core/radio/leakage_canceller.h).
 */
#ifndef INCLUDED_SEMS_BLOCKS_LEAKAGE_CANCELLER_H
#define INCLUDED_SEMS_BLOCKS_LEAKAGE_CANCELLER_H

#include <gnuradio/block.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/radio/leakage_canceller.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Cancels the transmitter's leakage, its IQ image and the DC offset from the
 *        received samples, given the transmitted samples.
 * \ingroup sems
 *
 * \details Input 0: the received samples; input 1: the transmitted samples, sample-aligned
 * with input 0 (the radio's fixed TX-to-RX latency removed upstream). Output: input 0 minus
 * the widely-linear least-squares fit of input 1 (core leakage_canceller: L taps on tx and
 * conj(tx), a DC, fitted per window of W samples with forgetting λ across windows, the
 * window's own fit subtracted from it). The output comes in whole windows (latency W
 * samples); the tags of input 0 go out on the same samples, those of input 1 are dropped.
 * It removes whatever is static and within the first L samples of delay over the averaging
 * window: an echo there is removed with the leakage; an echo L samples or more behind passes.
 *
 * Received sample k is paired with transmitted sample k, whenever each arrives: the
 * transmitted samples that come before their received ones are held in the block (it always
 * takes them), so a frame_sync upstream of input 0, which outputs nothing until it has found
 * the first frame, never stalls the transmitter feeding input 1 (in one flowgraph:
 * ofdm_tx → radio → frame_sync → input 0, ofdm_tx → input 1). At most max_lead() samples are
 * held; beyond that the received stream has stalled or never started (frame_sync finds no
 * frame) and the block stops with an error naming both counts (stream_error()). The stream
 * ends when either input has ended and no whole window of pairs is left.
 */
class SEMS_API leakage_canceller : virtual public gr::block
{
public:
    typedef std::shared_ptr<leakage_canceller> sptr; ///< shared pointer to the block

    /*!
     * \brief The most transmitted samples held ahead of the received ones: 64 windows, and
     *        at least 2^20 samples.
     * \param window W, samples per fit
     * \return the limit in samples.
     */
    static uint64_t max_lead(int window)
    {
        const uint64_t windows = 64 * static_cast<uint64_t>(window > 0 ? window : 0);
        return windows > (uint64_t(1) << 20) ? windows : (uint64_t(1) << 20);
    }

    /*!
     * \brief Makes a leakage canceller.
     * \param taps          L, the leakage's delay spread in samples (1 .. 64)
     * \param window        W, samples per fit (>= 2·K regressors; one frame N·(M + CP) is best)
     * \param forgetting    λ in [0, 1), weight of the previous windows' fit
     * \param widely_linear fit the IQ image (conj(tx) taps) too
     * \param dc            fit a DC offset too
     * \param clip_level    the converter's full scale per rail in the stream's units (the
     *                      largest |I| or |Q| it outputs); clipped samples are left out of
     *                      the fit and their residual bounded (core leakage_canceller.h).
     *                      0: no clipping handled
     * \return the block.
     * \throws std::invalid_argument naming the parameter.
     */
    static sptr make(int taps = leakage_canceller_settings{}.taps,
                     int window = leakage_canceller_settings{}.window,
                     double forgetting = leakage_canceller_settings{}.forgetting,
                     bool widely_linear = leakage_canceller_settings{}.widely_linear,
                     bool dc = leakage_canceller_settings{}.dc,
                     double clip_level = leakage_canceller_settings{}.clip_level);

    //! \brief h_0 .. h_{L−1} of the last fit. \return L taps.
    virtual std::vector<gr_complex> taps() const = 0;
    //! \brief g_0 .. g_{L−1}, the IQ image's taps of the last fit. \return L taps.
    virtual std::vector<gr_complex> image_taps() const = 0;
    //! \brief The DC of the last fit. \return c.
    virtual gr_complex dc() const = 0;
    //! \brief Windows processed. \return the count.
    virtual uint64_t windows() const = 0;
    //! \brief Transmitted samples held, waiting for their received ones. \return the count.
    virtual uint64_t held() const = 0;
    /*!
     * \brief Why the block stopped the stream.
     * \return "" while it runs; the message after the transmitted samples ran more than
     *         max_lead() ahead of the received ones.
     */
    virtual std::string stream_error() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BLOCKS_LEAKAGE_CANCELLER_H */
