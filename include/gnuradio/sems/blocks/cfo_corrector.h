// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The CFO corrector block: a bistatic receiver's carrier frequency offset, estimated
 *        from the cyclic prefix (core/frame/cp_sync.h) and removed.
 */
#ifndef INCLUDED_SEMS_BLOCKS_CFO_CORRECTOR_H
#define INCLUDED_SEMS_BLOCKS_CFO_CORRECTOR_H

#include <gnuradio/sync_block.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <cstdint>

namespace gr {
namespace sems {

/*!
 * \brief Estimates the carrier frequency offset from the cyclic prefix (van de Beek) and
 *        removes it, sample by sample.
 * \ingroup sems
 *
 * \details Samples in, samples out, 1:1, in whole windows of `symbols` symbols of M + cp
 * samples (any start: the symbol timing is estimated too, cp_sync()). The offset of each
 * window is averaged into the running estimate with forgetting λ (1/(1 − λ) windows) and
 * removed by a phase that advances 2π·ε/M per sample, continuous across windows, so a
 * sensing receiver sees no phase jump. Offsets are unambiguous in (−½, ½) subcarrier
 * spacings. A monostatic radio shares its oscillator and has no offset: this is for a
 * bistatic link. On an echo-only link the estimate is the offset plus the echoes'
 * power-weighted Doppler (indistinguishable within a symbol; at most 1/(2T)), of whose turn
 * per symbol the correction removes S/(B·T) (docs/reference/sdr_receiver.md). Tags pass on
 * their samples.
 */
class SEMS_API cfo_corrector : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<cfo_corrector> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes a CFO corrector.
     * \param n_subcarriers M, the FFT size (>= 1)
     * \param cp_len        the cyclic prefix (1 .. M)
     * \param symbols       symbols per window (>= 2; one is kept for the timing search)
     * \param forgetting    λ in [0, 1), weight of the previous windows' estimate
     * \param snr_db        SNR per sample of the timing metric (finite)
     * \return the block.
     * \throws std::invalid_argument naming the parameter.
     */
    static sptr make(int n_subcarriers = frame_settings{}.n_subcarriers,
                     int cp_len = frame_settings{}.cp_len,
                     int symbols = frame_settings{}.n_symbols,
                     double forgetting = 0.5,
                     double snr_db = 10.0);

    //! \brief The running estimate ε̂ in subcarrier spacings. \return ε̂.
    virtual double cfo() const = 0;
    //! \brief The last window's symbol timing, samples from its start. \return θ̂.
    virtual int timing() const = 0;
    //! \brief Windows processed. \return the count.
    virtual uint64_t windows() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BLOCKS_CFO_CORRECTOR_H */
