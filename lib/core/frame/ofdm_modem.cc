// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: one CP-OFDM symbol's unitary modulator and demodulator (see the header). */
#include <gnuradio/sems/core/frame/ofdm_modem.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {
int checked_m(int m)
{
    if (m <= 0)
        throw std::invalid_argument("ofdm_modem: n_subcarriers must be > 0, got " + std::to_string(m));
    return m;
}
} // namespace

ofdm_modem::ofdm_modem(int n_subcarriers, int cp_len)
    : d_m(checked_m(n_subcarriers)),
      d_cp(cp_len),
      d_scale(static_cast<float>(1.0 / std::sqrt(static_cast<double>(n_subcarriers)))),
      d_rev(n_subcarriers, 1),
      d_fwd(n_subcarriers, 1)
{
    if (cp_len < 0 || cp_len > n_subcarriers)
        throw std::invalid_argument("ofdm_modem: cp_len must be in [0, n_subcarriers = " +
                                    std::to_string(n_subcarriers) + "], got " + std::to_string(cp_len));
}

void ofdm_modem::modulate(const gr_complex* x, gr_complex* out)
{
    std::copy(x, x + d_m, d_rev.get_inbuf());
    d_rev.execute();
    const gr_complex* t = d_rev.get_outbuf();
    for (int k = 0; k < d_m; ++k)
        out[d_cp + k] = t[k] * d_scale;
    std::copy(out + d_m, out + d_m + d_cp, out); // the prefix repeats the symbol's last L samples
}

void ofdm_modem::demodulate(const gr_complex* in, gr_complex* y)
{
    std::copy(in + d_cp, in + d_cp + d_m, d_fwd.get_inbuf());
    d_fwd.execute();
    const gr_complex* f = d_fwd.get_outbuf();
    for (int k = 0; k < d_m; ++k)
        y[k] = f[k] * d_scale;
}

} // namespace sems
} // namespace gr
