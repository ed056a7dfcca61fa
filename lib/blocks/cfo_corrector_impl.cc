// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: cfo_corrector implementation (see cfo_corrector.h). */
#include "blocks/cfo_corrector_impl.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/frame/cp_sync.h>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

cfo_corrector::sptr cfo_corrector::make(int n_subcarriers, int cp_len, int symbols, double forgetting, double snr_db)
{
    if (n_subcarriers < 1)
        throw std::invalid_argument("cfo_corrector: n_subcarriers must be >= 1, got " + std::to_string(n_subcarriers));
    if (cp_len < 1 || cp_len > n_subcarriers)
        throw std::invalid_argument("cfo_corrector: cp_len must be in [1, n_subcarriers] (the prefix is what it "
                                    "correlates), got " + std::to_string(cp_len));
    if (symbols < 2)
        throw std::invalid_argument("cfo_corrector: symbols must be >= 2, got " + std::to_string(symbols));
    if (!(forgetting >= 0.0 && forgetting < 1.0))
        throw std::invalid_argument("cfo_corrector: forgetting must be in [0, 1), got " + std::to_string(forgetting));
    if (!std::isfinite(snr_db))
        throw std::invalid_argument("cfo_corrector: snr_db must be finite, got " + std::to_string(snr_db));
    return gnuradio::make_block_sptr<cfo_corrector_impl>(
        n_subcarriers, cp_len, symbols, forgetting, std::pow(10.0, snr_db / 10.0));
}

cfo_corrector_impl::cfo_corrector_impl(int m, int cp, int symbols, double forgetting, double snr)
    : gr::sync_block("cfo_corrector",
                     gr::io_signature::make(1, 1, sizeof(gr_complex)),
                     gr::io_signature::make(1, 1, sizeof(gr_complex))),
      d_m(m), d_cp(cp), d_symbols(symbols), d_forgetting(forgetting), d_snr(snr)
{
    set_output_multiple(symbols * (m + cp));
}

int cfo_corrector_impl::work(int noutput_items, gr_vector_const_void_star& input_items, gr_vector_void_star& output_items)
{
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const int w = d_symbols * (d_m + d_cp);
    const int n = noutput_items / w * w;
    for (int s = 0; s < n; s += w) {
        // Timing and offset over symbols − 1 symbols (the search needs one symbol more).
        const auto e = cp_sync(in + s, d_symbols - 1, d_m, d_cp, d_snr);
        d_avg = d_forgetting * d_avg + std::polar(1.0, -2.0 * M_PI * e.cfo);
        const double cfo = -std::arg(d_avg) / (2.0 * M_PI);
        d_cfo = cfo;
        d_timing = e.timing;
        const double step = cfo / d_m; // turns per sample
        for (int k = 0; k < w; ++k) {
            out[s + k] = in[s + k] * gr_complex(std::polar(1.0, -2.0 * M_PI * d_phase));
            d_phase = std::fmod(d_phase + step, 1.0);
        }
        ++d_windows;
    }
    return n;
}

} // namespace sems
} // namespace gr
