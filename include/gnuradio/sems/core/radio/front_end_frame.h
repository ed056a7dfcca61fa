// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief One frame through the radio front end, at resource-element level: what the
 *        receiver's FFT sees of a frame whose noiseless channel H is known. The trainer draws
 *        its observations through it when it trains for a radio (sems_train --radio).
 *
 * It is the streaming chain of docs/guides/radio_front_end.md (GNU Radio's blocks around
 * target_channel_td, then leakage_canceller and ofdm_rx) applied to one frame from its
 * frequency-domain channel:
 *  1. X: a unit-modulus QPSK symbol on every used resource element, 0 on guard subcarriers
 *     (what pilot_mapper sends: pilots and data alike; the estimate divides by X).
 *  2. The transmitted samples x: per symbol the unitary inverse FFT of X_n with its cyclic
 *     prefix (ofdm_tx), up-converted by the TX oscillator e^{jφ_tx(t)}.
 *  3. The echo: per symbol the unitary inverse FFT of H_n·X_n with its prefix, turned by the
 *     oscillators' e^{j(φ_tx(t − τ) − φ_rx(t))} at the echo's delay τ (linear between
 *     samples). The FFT of H_n·X_n is what the time-domain channel gives a CP-OFDM stream
 *     when the delay lies within the prefix and the target does not move within a symbol
 *     (td_channel.h bounds that difference). One delay turns every path of the frame: the
 *     target of interest's (exact for one path; for clutter the increment φ(t − τ) − φ(t)
 *     differs only by the delays' difference).
 *  4. The leakage: Σ_k h_k·x(t − k)·e^{jφ_tx(t − k)} (front_end_settings::leakage_response),
 *     added to the echo; both down-converted by e^{−jφ_rx(t)}.
 *  5. Noise CN(0, σ²) per sample, i.e. σ² per resource element after the unitary FFT.
 *  6. CFO e^{j(2π·cfo·t + θ0)} with a random θ0; IQ imbalance μ·r + ν·conj(r); the DC
 *     offset at 45°; the converter: each rail clipped at ±front_end_settings::full_scale and
 *     rounded to steps of 2^(1 − ENOB) of it.
 *  7. With one shared oscillator (monostatic: the receiver has the transmitted samples) and
 *     leakage or a DC offset, leakage_fit (the defaults, one frame per window, at least the
 *     radio's leakage taps, the converter's full scale as clip_level) cancels them. In a stream
 *     its fit carries the previous windows; here one window of the leakage alone (with noise,
 *     the oscillators running on) precedes the frame and stands for them
 *     (leakage_fit::hold_as_steady_state).
 *  8. Per symbol, the unitary FFT of the prefix-free window, divided by X: the estimate
 *     Ĥ[n, m] (on a guard subcarrier, the FFT itself).
 *
 * With the ideal radio the estimate is H + CN(0, σ²) per resource element, the trainer's
 * model without a radio (up to the float rounding of the transforms). Not modelled: a sample
 * clock offset (refused), the frame's start (known, as after frame_sync), a CFO corrector
 * (give the CFO it leaves). Cost: two frames of samples per frame, dominated by the
 * canceller's ~2L + 2K complex multiply-adds per sample when it runs (L taps, K = 2L + 1
 * regressors: 9 by default; plus K²/2 per clipped sample: leakage_canceller.h).
 */
#ifndef INCLUDED_SEMS_CORE_FRONT_END_FRAME_H
#define INCLUDED_SEMS_CORE_FRONT_END_FRAME_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/radio/front_end.h>
#include <cstdint>
#include <memory>

namespace gr {
namespace sems {

/*!
 * \brief Draws a frame's channel estimate through a radio front end (see the file comment).
 *        One object per thread: it holds FFT plans and buffers.
 */
class SEMS_API front_end_frame
{
public:
    /*!
     * \param frame the frame (N, M, bandwidth as the sample rate, CP, guards)
     * \param radio the front end
     * \throws std::invalid_argument naming the parameter: an invalid radio, a sample clock
     *         offset (not modelled), an invalid frame.
     */
    front_end_frame(const frame_settings& frame, const front_end_settings& radio);
    ~front_end_frame(); ///< Destructor.

    /*!
     * \brief The estimate of one frame.
     * \param h the noiseless channel, N·M values, row-major (symbol, subcarrier)
     * \param delay_index the echo's delay τ·B in samples (finite, >= 0; turns the oscillators)
     * \param noise_variance σ² per sample (finite, >= 0)
     * \param seed seeds the frame's symbols, noise, oscillators and CFO phase
     * \param out N·M values: Ĥ[n, m] (may not alias h)
     * \throws std::invalid_argument for a negative or non-finite delay or noise.
     */
    void observe(const gr_complex* h, double delay_index, double noise_variance, uint64_t seed, gr_complex* out);

    /*! \brief The mean power of the transmitted samples: used subcarriers over M. \return it. */
    double tx_power() const;
    /*! \brief Whether the canceller runs (shared oscillator with leakage or DC). \return it. */
    bool cancels() const;
    /*! \brief The frame. \return its settings. */
    const frame_settings& frame() const;

private:
    struct impl;
    std::unique_ptr<impl> d;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_FRONT_END_FRAME_H */
