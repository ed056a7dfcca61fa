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
 * true lag. The frame is found when F·L·ρ exceeds `threshold` (default 25: a false alarm
 * on noise alone has probability ≈ L·e^{−25}, 4e-8 per search at the defaults). The best
 * lag fixes the frame phase; the first frame is then the first of the F whose own metric
 * L·ρ_f passes threshold/F (the stream may begin inside the window, after silence or noise).
 *
 * It assumes a coherent path: the received frame is g·(the transmitted frame) + noise with
 * one complex gain g over the F frames — a loopback, a cable, a file, the direct path an
 * SDR user calibrates the offset on once. Echoes with Doppler (phase turning from symbol
 * to symbol) do not add up coherently, and a mask whose pilots share one subcarrier gives a
 * periodic template that cannot resolve single samples: such masks are refused (the
 * template's autocorrelation sidelobe must stay below max_sidelobe of its peak; the
 * shipped classifier mask, 32 pilots on subcarrier 32, is one; the delay masks pass).
 */
#ifndef INCLUDED_SEMS_CORE_FRAME_SEARCH_H
#define INCLUDED_SEMS_CORE_FRAME_SEARCH_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/pilot_mask.h>
#include <vector>

namespace gr {
namespace sems {

//! \brief The outcome of one search.
struct SEMS_API frame_search_result {
    bool found = false;   //!< whether the metric reached the threshold
    int lag = 0;          //!< first frame start, samples from the window start (0 <= lag < F·L)
    double metric = 0.0;  //!< F·L·ρ at the best lag (compare with the threshold)
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
     * \param threshold detection threshold on F·L·ρ (> 0)
     * \throws std::invalid_argument naming the parameter.
     */
    frame_search(const pilot_mask& mask, int cp_len, double pilot_power, int frames, double threshold = 25.0);

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

    //! \brief Searches one window. \param x window_len() samples \return the best lag and its metric.
    frame_search_result search(const gr_complex* x) const;

private:
    int d_len, d_frames;
    double d_threshold, d_template_energy, d_sidelobe = 1.0;
    std::vector<gr_complex> d_template;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_FRAME_SEARCH_H */
