// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a free-running oscillator's phase noise as a sample stream.
 *
 * gr_complex out: exp(jφ[n]), φ the Wiener phase of core/radio/phase_noise.h (double precision,
 * seeded), φ[0] = 0. Multiplying the transmitted samples by this stream is the up-conversion
 * by a noisy oscillator; multiplying the received samples by its conjugate
 * (blocks.multiply_conjugate_cc) with the SAME stream is the down-conversion by the same
 * oscillator (monostatic), so a path at delay τ keeps φ(t − τ) − φ(t) and the zero-delay
 * leakage almost nothing. Two sources with different seeds are two oscillators (bistatic).
 */
#ifndef INCLUDED_SEMS_BLOCKS_PHASE_NOISE_SOURCE_H
#define INCLUDED_SEMS_BLOCKS_PHASE_NOISE_SOURCE_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sync_block.h>
#include <cstdint>

namespace gr {
namespace sems {

/*!
 * \brief Source of exp(jφ[n]) for an oscillator of phase noise L(f) dBc/Hz at an offset.
 *
 * \ingroup sems
 */
class SEMS_API phase_noise_source : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<phase_noise_source> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes an oscillator's phase-noise source.
     * \param sample_rate_hz f_s, the stream's sample rate in Hz
     * \param dbc_hz L(f) in dBc/Hz (below 0, on the 1/f² skirt: front_end_settings::validate)
     * \param offset_hz the offset f in Hz at which L is quoted
     * \param seed seed of the phase increments
     * \return the block.
     * \throws std::invalid_argument naming the parameter and its value.
     */
    static sptr make(double sample_rate_hz = frame_settings().bandwidth_hz, double dbc_hz = -90.0, double offset_hz = 100e3, uint64_t seed = 0);

    //! \brief The phase diffusion. \return D = 4π² f² 10^(L/10) in rad²/s.
    virtual double diffusion() const = 0;
    //! \brief Samples emitted so far. \return the count.
    virtual uint64_t samples() const = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BLOCKS_PHASE_NOISE_SOURCE_H */
