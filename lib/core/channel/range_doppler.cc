// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: range-Doppler map of a frame (see range_doppler.h). */
#include <gnuradio/fft/fft.h>
#include <gnuradio/sems/core/channel/range_doppler.h>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace gr {
namespace sems {

struct range_doppler::plans {
    gr::fft::fft_complex_rev delay;   // over m: exp(+j2π m q/M)
    gr::fft::fft_complex_fwd doppler; // over n: exp(-j2π n d/N)
    plans(int m, int n) : delay(m, 1), doppler(n, 1) {}
};

static std::vector<float> make_window(const std::string& name, int len)
{
    std::vector<float> w(len, 1.0f);
    if (name == "rect")
        return w;
    if (name != "hann")
        throw std::invalid_argument("range_doppler: window must be \"hann\" or \"rect\", got \"" + name + "\"");
    // Periodic Hann: exact zeros of its spectrum fall on the DFT bins, so an on-bin target
    // stays on its cell.
    for (int k = 0; k < len; ++k)
        w[k] = 0.5f - 0.5f * static_cast<float>(std::cos(2.0 * M_PI * k / len));
    if (len == 1)
        w[0] = 1.0f;
    return w;
}

range_doppler::range_doppler(const pilot_mask& mask, const std::string& window)
    : d_mask(mask),
      d_n(mask.n_symbols()),
      d_m(mask.n_subcarriers()),
      d_wn(make_window(window, d_n)),
      d_wm(make_window(window, d_m)),
      d_flat(mask.flat_indices()),
      d_grid(static_cast<size_t>(d_n) * d_m),
      d_plans(std::make_unique<plans>(d_m, d_n))
{
    const double sn = std::accumulate(d_wn.begin(), d_wn.end(), 0.0);
    const double sm = std::accumulate(d_wm.begin(), d_wm.end(), 0.0);
    d_norm = static_cast<float>(1.0 / (sn * sn * sm * sm));
}

range_doppler::~range_doppler() = default;

int range_doppler::doppler_row(int bin, int n_symbols)
{
    return ((bin + n_symbols / 2) % n_symbols + n_symbols) % n_symbols;
}

void range_doppler::compute(const gr_complex* observations, float* out_db)
{
    std::fill(d_grid.begin(), d_grid.end(), gr_complex(0.0f, 0.0f));
    for (size_t k = 0; k < d_flat.size(); ++k) {
        const int n = d_flat[k] / d_m, m = d_flat[k] % d_m;
        d_grid[d_flat[k]] = observations[k] * (d_wn[n] * d_wm[m]);
    }
    // Delay transform, row by row.
    auto& dl = d_plans->delay;
    for (int n = 0; n < d_n; ++n) {
        gr_complex* row = d_grid.data() + static_cast<size_t>(n) * d_m;
        std::copy(row, row + d_m, dl.get_inbuf());
        dl.execute();
        std::copy(dl.get_outbuf(), dl.get_outbuf() + d_m, row);
    }
    // Doppler transform, column by column, into the shifted rows.
    auto& dp = d_plans->doppler;
    for (int q = 0; q < d_m; ++q) {
        for (int n = 0; n < d_n; ++n)
            dp.get_inbuf()[n] = d_grid[static_cast<size_t>(n) * d_m + q];
        dp.execute();
        for (int b = 0; b < d_n; ++b) {
            const float p = std::norm(dp.get_outbuf()[b]) * d_norm;
            out_db[static_cast<size_t>(doppler_row(b, d_n)) * d_m + q] =
                p > 0.0f ? std::max(floor_db, 10.0f * std::log10(p)) : floor_db;
        }
    }
}

} // namespace sems
} // namespace gr
