// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: where does a frame start in a sample stream? (the time-domain receiver's
 * alignment step; docs/design.md §3, time domain)
 *
 * The known part of a transmitted frame is its pilots: the template t is the frame's
 * CP-OFDM samples with the data set to zero (sqrt(E_p)·s_p at the mask positions, unitary
 * inverse FFT, prefix), N·(M + CP) samples long. Over F consecutive frames of a received
 * window x (F + 1 frames long, the pilots repeat every frame), for every lag θ in one frame,
 *
 *     c(θ) = Σ_f Σ_k x[θ + f·L + k] · conj(t[k]),   ρ(θ) = |c(θ)|² / (F·Σ|t|² · Σ_f Σ_k |x[θ + f·L + k]|²)
 *
 * (0 ≤ ρ ≤ 1 by Cauchy–Schwarz), the best lag is the frame start. The unknown data and the
 * noise leave ρ ≈ Exp(1/(F·L)) at every lag; the pilots add ≈ Σ|t|²/L·SNR/(1+SNR) at the
 * true lag. The frame is found when F·L·ρ exceeds `threshold`. The lag's correlations for
 * all lags come from one forward and one inverse FFT of the window (cost O(W log W), W = (F + 1)·L).
 *
 * Non-coherent combining (`noncoherent`): the F frames are combined in power,
 *
 *     z_f(θ) = L·|c_f(θ)|² / (Σ|t|² · Σ_k |x[θ + f·L + k]|²),   metric(θ) = Σ_f z_f(θ),
 *
 * so a path whose phase changes from frame to frame (an echo with Doppler, a drifting
 * oscillator) still adds up; it needs the path's delay to stay within a sample over F frames.
 *
 * The false-lock probability per search (noise and data alone, no frame): at one lag the
 * metric is Exp(1) coherently and Gamma(F, 1) non-coherently, so with the L lags taken as
 * independent (a union bound, tight at small values)
 *
 *     P_false(T) ≈ L · e^{−T}                            (coherent)
 *     P_false(T) ≈ L · e^{−T} · Σ_{k<F} T^k / k!          (non-coherent),
 *
 * false_lock_probability(). The block searches once per frame until it locks, so this is
 * also the false locks per frame of noise. The default T = 25 gives 3.6e-8 coherently at
 * L = 2560; non-coherently with F = 4 it gives 1.0e-4, so use threshold_for(1e-6, ...) = 30.2
 * there. apps/evaluation/sems_sync_false_lock.cc measures both on noise (docs/reference/sdr_receiver.md).
 * The best lag fixes the frame phase; the first frame is then the first of the F whose own
 * metric L·ρ_f (z_f) passes threshold/F (the stream may begin inside the window, after
 * silence or noise).
 *
 * Coherently it assumes one path: the received frame is g·(the transmitted frame) + noise with
 * one complex gain g over the F frames — a loopback, a cable, a file, the transmitter's
 * leakage into a monostatic radio's receiver (delay 0: the right timing for the echoes
 * behind it). Non-coherently, g may change from frame to frame; within a frame the pilots
 * must still add up (Doppler small against 1/(pilot symbols' span)): an echo alone is then
 * timed at its own delay, so the offset found is the frame start plus the echo's delay, and
 * ranges are relative to it unless the offset is calibrated on the direct path
 * (examples/sems_offset_calibration.grc). A mask whose pilots share one subcarrier gives a
 * periodic template that cannot resolve single samples: such masks are refused (the
 * template's autocorrelation sidelobe must stay below max_sidelobe of its peak; the
 * shipped classifier mask, 32 pilots on subcarrier 17, is one; the delay masks pass).
 */
#ifndef INCLUDED_SEMS_CORE_FRAME_SEARCH_H
#define INCLUDED_SEMS_CORE_FRAME_SEARCH_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <memory>
#include <vector>

namespace gr {
namespace sems {

//! \brief The outcome of one search.
struct SEMS_API frame_search_result {
    bool found = false;   //!< whether the metric reached the threshold
    int lag = 0;          //!< first frame start, samples from the window start (0 <= lag < F·L)
    double metric = 0.0;  //!< F·L·ρ (or Σ_f z_f, non-coherent) at the best lag (compare with the threshold)
};

/*!
 * \brief Frame-start search by correlation with the pilots' time-domain template.
 */
class SEMS_API frame_search
{
public:
    /*!
     * \param mask the pilot mask (its N, M, pilot symbol)
     * \param cp_len cyclic prefix in samples (0 <= cp_len <= M)
     * \param pilot_power E_p, as given to the pilot mapper (> 0)
     * \param frames F, frames correlated per search (>= 1)
     * \param threshold detection threshold on the metric (> 0)
     * \param noncoherent combine the F frames in power (true) or in amplitude (false)
     * \throws std::invalid_argument naming the parameter.
     */
    frame_search(const pilot_mask& mask,
                 int cp_len,
                 double pilot_power,
                 int frames,
                 double threshold = 25.0,
                 bool noncoherent = false);

    /*!
     * \brief False-lock probability of one search on noise alone (the union bound above).
     * \param threshold T (> 0)
     * \param frames F (>= 1)
     * \param frame_len L, lags searched (>= 1)
     * \param noncoherent the combining
     * \return P_false(T), at most 1.
     * \throws std::invalid_argument naming the parameter.
     */
    static double false_lock_probability(double threshold, int frames, int frame_len, bool noncoherent);
    /*!
     * \brief The threshold whose false_lock_probability() is p (bisection).
     * \param p false locks per search, in (0, 1)
     * \param frames F (>= 1)
     * \param frame_len L (>= 1)
     * \param noncoherent the combining
     * \return T.
     * \throws std::invalid_argument naming the parameter.
     */
    static double threshold_for(double p, int frames, int frame_len, bool noncoherent);

    //! \brief Whether the frames are combined in power. \return the combining.
    bool noncoherent() const { return d_noncoherent; }
    //! \brief The detection threshold. \return T.
    double threshold() const { return d_threshold; }

    //! \brief L = N·(M + cp_len), samples per frame. \return L.
    int frame_len() const { return d_len; }
    //! \brief Samples a search needs: (F + 1)·L. \return the window length.
    int window_len() const { return (d_frames + 1) * d_len; }
    //! \brief The pilots' time-domain template of one frame. \return L samples.
    const std::vector<gr_complex>& frame_template() const { return d_template; }
    //! \brief Largest autocorrelation of the template at a non-zero lag, relative to its peak. \return the ratio.
    double sidelobe() const { return d_sidelobe; }
    //! Templates whose sidelobe() exceeds this are refused (they cannot resolve a sample).
    static constexpr double max_sidelobe = 0.8;

    /*!
     * \brief Searches one window. One search at a time per object (copies share the FFT
     *        buffers). \param x window_len() samples \return the best lag and its metric.
     */
    frame_search_result search(const gr_complex* x) const;

private:
    struct correlator; // FFT plans and the template's spectrum
    int d_len, d_frames;
    double d_threshold, d_template_energy, d_sidelobe = 1.0;
    bool d_noncoherent = false;
    std::vector<gr_complex> d_template;
    std::shared_ptr<correlator> d_corr;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_FRAME_SEARCH_H */
