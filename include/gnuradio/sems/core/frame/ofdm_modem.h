// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The unitary CP-OFDM modulator and demodulator of one symbol: the maths of ofdm_tx and
 *        ofdm_rx, for code that builds or reads a frame's samples itself (the radio's frame
 *        model front_end_frame, the false-lock measurement sems_sync_false_lock, the tests).
 *
 * modulate: the M subcarrier values X → the M + L samples of the symbol, the prefix first:
 * x[i] = IDFT(X)[(i − L) mod M] / sqrt(M). demodulate: the symbol's M + L samples → the M
 * values DFT(prefix-free window) / sqrt(M). Both are unitary, so a resource element keeps its
 * power and white noise of σ² per sample is σ² per resource element.
 */
#ifndef INCLUDED_SEMS_CORE_OFDM_MODEM_H
#define INCLUDED_SEMS_CORE_OFDM_MODEM_H

#include <gnuradio/fft/fft.h>
#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>

namespace gr {
namespace sems {

/*! \brief One CP-OFDM symbol's unitary modulator and demodulator (FFT plans of size M). */
class SEMS_API ofdm_modem
{
public:
    /*!
     * \brief A modem of M subcarriers and a prefix of L samples.
     * \param n_subcarriers M (> 0).
     * \param cp_len L (0 ≤ L ≤ M).
     * \throws std::invalid_argument naming the value otherwise.
     */
    ofdm_modem(int n_subcarriers, int cp_len);
    /*! \brief M. \return the subcarriers. */
    int n_subcarriers() const { return d_m; }
    /*! \brief L. \return the prefix length in samples. */
    int cp_len() const { return d_cp; }
    /*! \brief M + L. \return the samples of one symbol. */
    int symbol_len() const { return d_m + d_cp; }
    /*!
     * \brief The symbol's samples.
     * \param x M subcarrier values.
     * \param out M + L samples, the prefix first (may not overlap x).
     */
    void modulate(const gr_complex* x, gr_complex* out);
    /*!
     * \brief The subcarrier values of a symbol.
     * \param in M + L samples, the prefix first (the prefix is skipped).
     * \param y M values (may not overlap in).
     */
    void demodulate(const gr_complex* in, gr_complex* y);

private:
    int d_m, d_cp;
    float d_scale; // 1/sqrt(M), rounded once
    gr::fft::fft_complex_rev d_rev;
    gr::fft::fft_complex_fwd d_fwd;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_OFDM_MODEM_H */
