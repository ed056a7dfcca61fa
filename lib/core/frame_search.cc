// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: frame-start search (see frame_search.h). */
#include "core/checks.h"
#include <gnuradio/fft/fft.h>
#include <gnuradio/sems/core/frame_search.h>
#include <volk/volk.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

frame_search::frame_search(const pilot_mask& mask, int cp_len, double pilot_power, int frames, double threshold)
    : d_len(0), d_frames(frames), d_threshold(threshold), d_template_energy(0.0)
{
    const int n = mask.n_symbols(), m = mask.n_subcarriers();
    if (cp_len < 0 || cp_len > m)
        throw std::invalid_argument("frame_search: cp_len must be in [0, M = " + std::to_string(m) + "], got " +
                                    std::to_string(cp_len));
    if (!checks::positive(pilot_power))
        throw std::invalid_argument("frame_search: pilot_power must be a finite number > 0, got " +
                                    std::to_string(pilot_power));
    if (frames < 1)
        throw std::invalid_argument("frame_search: frames must be >= 1, got " + std::to_string(frames));
    if (!checks::positive(threshold))
        throw std::invalid_argument("frame_search: threshold must be a finite number > 0, got " +
                                    std::to_string(threshold));
    const int s = m + cp_len;
    d_len = n * s;
    d_template.assign(size_t(d_len), gr_complex(0.0f, 0.0f));
    gr::fft::fft_complex_rev ifft(m);
    const float scale = static_cast<float>(std::sqrt(pilot_power) / std::sqrt(double(m)));
    const auto rows = mask.carrier_lists();
    const auto values = mask.pilot_symbol_lists(); // sqrt(p_k)·s_p, as the mapper sends them
    for (int k = 0; k < n; ++k) {
        if (rows[k].empty())
            continue;
        std::fill(ifft.get_inbuf(), ifft.get_inbuf() + m, gr_complex(0.0f, 0.0f));
        for (size_t j = 0; j < rows[k].size(); ++j)
            ifft.get_inbuf()[rows[k][j]] = values[k][j] * scale;
        ifft.execute();
        for (int i = 0; i < s; ++i)
            d_template[size_t(k) * s + i] = ifft.get_outbuf()[((i - cp_len) % m + m) % m];
    }
    for (const auto& v : d_template)
        d_template_energy += std::norm(v);

    // The template must resolve single samples: its autocorrelation (|FFT|² over 2L, so
    // aperiodic) may not come close to its peak at any other lag. Pilots all on one
    // subcarrier give a tone, periodic in samples: refused, with the reason.
    const int nfft = 2 * d_len;
    gr::fft::fft_complex_fwd fwd(nfft);
    gr::fft::fft_complex_rev rev(nfft);
    std::fill(fwd.get_inbuf(), fwd.get_inbuf() + nfft, gr_complex(0.0f, 0.0f));
    std::copy(d_template.begin(), d_template.end(), fwd.get_inbuf());
    fwd.execute();
    for (int i = 0; i < nfft; ++i)
        rev.get_inbuf()[i] = std::norm(fwd.get_outbuf()[i]);
    rev.execute();
    const double peak = std::abs(rev.get_outbuf()[0]);
    double side = 0.0;
    for (int i = 1; i < nfft; ++i)
        side = std::max(side, double(std::abs(rev.get_outbuf()[i])));
    d_sidelobe = peak > 0.0 ? side / peak : 1.0;
    if (d_sidelobe > max_sidelobe)
        throw std::invalid_argument(
            "frame_search: the pilots cannot locate a frame to the sample: the template's "
            "autocorrelation reaches " +
            std::to_string(d_sidelobe) + " of its peak at another lag (max " + std::to_string(max_sidelobe) +
            "); pilots on few subcarriers (e.g. one) form a periodic tone. Use a mask whose pilots "
            "spread over many subcarriers, or a preamble");
}

frame_search_result frame_search::search(const gr_complex* x) const
{
    const size_t w = size_t(window_len());
    std::vector<double> energy(w + 1, 0.0); // prefix sums of |x|²
    for (size_t i = 0; i < w; ++i)
        energy[i + 1] = energy[i] + std::norm(x[i]);
    frame_search_result best;
    double best_rho = -1.0;
    for (int lag = 0; lag < d_len; ++lag) {
        gr_complex c(0.0f, 0.0f);
        double ex = 0.0;
        for (int f = 0; f < d_frames; ++f) {
            const size_t start = size_t(lag) + size_t(f) * d_len;
            gr_complex part;
            volk_32fc_x2_conjugate_dot_prod_32fc(&part, x + start, d_template.data(), d_len);
            c += part;
            ex += energy[start + d_len] - energy[start];
        }
        const double rho = ex > 0.0 ? std::norm(std::complex<double>(c)) / (d_frames * d_template_energy * ex) : 0.0;
        if (rho > best_rho) {
            best_rho = rho;
            best.lag = lag;
        }
    }
    best.metric = best_rho * d_frames * d_len;
    best.found = best.metric > d_threshold;
    if (!best.found)
        return best;
    // The best lag fixes the frame phase; the stream may start within the window (silence
    // or noise before it): the first frame is the first whose own metric L·ρ_f passes
    // threshold / F.
    for (int f = 0; f < d_frames; ++f) {
        const size_t start = size_t(best.lag) + size_t(f) * d_len;
        gr_complex c;
        volk_32fc_x2_conjugate_dot_prod_32fc(&c, x + start, d_template.data(), d_len);
        const double ex = energy[start + d_len] - energy[start];
        const double m = ex > 0.0 ? std::norm(std::complex<double>(c)) * d_len / (d_template_energy * ex) : 0.0;
        if (m > d_threshold / d_frames) {
            best.lag += f * d_len;
            break;
        }
    }
    return best;
}

} // namespace sems
} // namespace gr
