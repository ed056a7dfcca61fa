// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems tests: a unitary CP-OFDM modulator/demodulator, the same maths as ofdm_tx/ofdm_rx
 * (qa_td_channel and fuzz/fuzz_td_channel drive td_channel with it). */
#ifndef INCLUDED_SEMS_QA_OFDM_MODEM_H
#define INCLUDED_SEMS_QA_OFDM_MODEM_H

#include <gnuradio/fft/fft.h>
#include <algorithm>
#include <cmath>

namespace gr {
namespace sems {
namespace qa {

struct ofdm_modem {
    int m, cp;
    gr::fft::fft_complex_rev rev;
    gr::fft::fft_complex_fwd fwd;
    ofdm_modem(int m_, int cp_) : m(m_), cp(cp_), rev(m_), fwd(m_) {}
    //! x: M subcarrier values -> out: M + CP samples, the prefix first.
    void tx(const gr_complex* x, gr_complex* out)
    {
        std::copy(x, x + m, rev.get_inbuf());
        rev.execute();
        const float sc = 1.0f / std::sqrt(float(m));
        for (int i = 0; i < m + cp; ++i)
            out[i] = rev.get_outbuf()[((i - cp) % m + m) % m] * sc;
    }
    //! in: M + CP samples -> y: the M subcarrier values of the prefix-free window.
    void rx(const gr_complex* in, gr_complex* y)
    {
        std::copy(in + cp, in + cp + m, fwd.get_inbuf());
        fwd.execute();
        const float sc = 1.0f / std::sqrt(float(m));
        for (int i = 0; i < m; ++i)
            y[i] = fwd.get_outbuf()[i] * sc;
    }
};

} // namespace qa
} // namespace sems
} // namespace gr

#endif // INCLUDED_SEMS_QA_OFDM_MODEM_H
