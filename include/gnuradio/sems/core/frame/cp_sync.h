// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: symbol timing and carrier frequency offset from the cyclic prefix (van de Beek,
 * Sandell and Börjesson, "ML estimation of time and frequency offset in OFDM systems", IEEE
 * Trans. Signal Process. 45(7), 1997): for a bistatic link, whose receiver's oscillator is
 * not the transmitter's.
 *
 * A CP-OFDM symbol's prefix repeats its last cp samples M samples later. With a frequency
 * offset of ε subcarrier spacings, r[k] = s[k]·e^{j2πεk/M} + noise, so over the prefix of a
 * symbol starting at θ
 *
 *     γ(θ) = Σ_{i<cp} r[θ + i]·conj(r[θ + i + M]) ≈ e^{−j2πε}·Σ|s|²,
 *     Φ(θ) = ½·Σ_{i<cp} |r[θ + i]|² + |r[θ + i + M]|²,
 *
 * summed over the symbols of the window. The ML estimates are θ̂ = argmax_θ |γ(θ)| − ρ·Φ(θ),
 * ρ = SNR/(SNR + 1), and ε̂ = −∠γ(θ̂)/(2π), unambiguous for |ε| < ½. With K = symbols·cp
 * sample pairs at SNR (per sample) the estimate's variance is, at high K,
 *
 *     var(ε̂) ≈ (1/SNR + 1/(2·SNR²)) / (4π²·K)                         (cp_cfo_variance()).
 *
 * The timing is of the symbol (modulo M + cp), not of the frame: frame_search finds the
 * frame. cp = 0 has no prefix to correlate and is refused.
 */
#ifndef INCLUDED_SEMS_CORE_CP_SYNC_H
#define INCLUDED_SEMS_CORE_CP_SYNC_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <cstddef>

namespace gr {
namespace sems {

//! \brief The cyclic-prefix estimates of one window.
struct SEMS_API cp_sync_estimate {
    int timing = 0;    //!< θ̂, the first symbol start in [0, M + cp)
    double cfo = 0.0;  //!< ε̂, the frequency offset in subcarrier spacings, in [−½, ½)
    double metric = 0.0; //!< |γ(θ̂)| − ρ·Φ(θ̂)
};

/*!
 * \brief Van de Beek's ML timing and frequency offset from the cyclic prefix.
 * \param x         (symbols + 1)·(M + cp) samples
 * \param symbols   symbols summed (>= 1)
 * \param m         M, the FFT size (>= 1)
 * \param cp        the prefix in samples (1 .. M)
 * \param snr       SNR per sample, linear (> 0; +inf for ρ = 1)
 * \return θ̂, ε̂ and the metric.
 * \throws std::invalid_argument naming the parameter.
 */
SEMS_API cp_sync_estimate cp_sync(const gr_complex* x, int symbols, int m, int cp, double snr);

/*!
 * \brief ε̂ alone, the timing known: x starts on a symbol's prefix.
 * \param x        symbols·(M + cp) samples
 * \param symbols  symbols summed (>= 1)
 * \param m        M (>= 1)
 * \param cp       the prefix (1 .. M)
 * \return ε̂ in subcarrier spacings, in [−½, ½).
 * \throws std::invalid_argument naming the parameter.
 */
SEMS_API double cp_cfo(const gr_complex* x, int symbols, int m, int cp);

/*!
 * \brief Removes a frequency offset: x[k] ·= e^{−j2πε(k0 + k)/M}.
 * \param x    samples, corrected in place
 * \param n    their number
 * \param cfo  ε in subcarrier spacings
 * \param m    M (>= 1)
 * \param k0   the stream index of x[0] (keeps the phase continuous across calls)
 * \throws std::invalid_argument naming the parameter.
 */
SEMS_API void cp_cfo_correct(gr_complex* x, size_t n, double cfo, int m, unsigned long long k0 = 0);

/*!
 * \brief The estimate's variance at high K (the file comment).
 * \param snr     SNR per sample, linear (> 0)
 * \param pairs   K = symbols·cp sample pairs (>= 1)
 * \return var(ε̂) in subcarrier spacings².
 */
SEMS_API double cp_cfo_variance(double snr, long pairs);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_CP_SYNC_H */
