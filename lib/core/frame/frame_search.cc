// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: frame-start search (see frame_search.h). */
#include "core/common/checks.h"
#include <gnuradio/fft/fft.h>
#include <gnuradio/sems/core/frame/frame_search.h>
#include <gnuradio/sems/core/frame/ofdm_modem.h>
#include <volk/volk.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

// The window's correlation with the template at every lag: c = IFFT(FFT(x)·conj(FFT(t))) over
// W = (F + 1)·L points. Lags θ < F·L need x up to θ + L − 1 < W: no circular wrap.
struct frame_search::correlator {
    gr::fft::fft_complex_fwd fwd;
    gr::fft::fft_complex_rev rev;
    std::vector<gr_complex> template_spectrum; // conj(FFT(t)) / W
    std::vector<gr_complex> corr;              // c at lags 0 .. W − 1
    std::vector<double> energy;                // prefix sums of |x|²
    explicit correlator(int w) : fwd(w), rev(w), template_spectrum(size_t(w)), corr(size_t(w)), energy(size_t(w) + 1) {}
};

double frame_search::false_lock_probability(double threshold, int frames, int frame_len, bool noncoherent)
{
    if (!checks::positive(threshold))
        throw std::invalid_argument("frame_search: threshold must be a finite number > 0, got " +
                                    std::to_string(threshold));
    if (frames < 1)
        throw std::invalid_argument("frame_search: frames must be >= 1, got " + std::to_string(frames));
    if (frame_len < 1)
        throw std::invalid_argument("frame_search: frame_len must be >= 1, got " + std::to_string(frame_len));
    double tail = 1.0; // Σ_{k<F} T^k/k! (non-coherent), 1 (coherent)
    if (noncoherent) {
        double term = 1.0;
        for (int k = 1; k < frames; ++k) {
            term *= threshold / k;
            tail += term;
        }
    }
    return std::min(1.0, double(frame_len) * std::exp(-threshold) * tail);
}

double frame_search::threshold_for(double p, int frames, int frame_len, bool noncoherent)
{
    if (!(p > 0.0 && p < 1.0))
        throw std::invalid_argument("frame_search: the false-lock probability p must be in (0, 1), got " +
                                    std::to_string(p));
    double lo = 1e-9, hi = 1.0;
    while (false_lock_probability(hi, frames, frame_len, noncoherent) > p)
        hi *= 2.0;
    for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        (false_lock_probability(mid, frames, frame_len, noncoherent) > p ? lo : hi) = mid;
    }
    return hi;
}

frame_search::frame_search(
    const pilot_mask& mask, int cp_len, double pilot_power, int frames, double threshold, bool noncoherent)
    : d_len(0), d_frames(frames), d_threshold(threshold), d_template_energy(0.0), d_noncoherent(noncoherent)
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
    ofdm_modem modem(m, cp_len); // the pilots alone, as ofdm_tx sends them
    const float amplitude = static_cast<float>(std::sqrt(pilot_power));
    const auto rows = mask.carrier_lists();
    const auto values = mask.pilot_symbol_lists(); // sqrt(p_k)·s_p, as the mapper sends them
    std::vector<gr_complex> x(static_cast<size_t>(m));
    for (int k = 0; k < n; ++k) {
        if (rows[k].empty())
            continue;
        std::fill(x.begin(), x.end(), gr_complex(0.0f, 0.0f));
        for (size_t j = 0; j < rows[k].size(); ++j)
            x[static_cast<size_t>(rows[k][j])] = values[k][j] * amplitude;
        modem.modulate(x.data(), &d_template[size_t(k) * s]);
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

    const int w = window_len();
    d_corr = std::make_shared<correlator>(w);
    std::fill(d_corr->fwd.get_inbuf(), d_corr->fwd.get_inbuf() + w, gr_complex(0.0f, 0.0f));
    std::copy(d_template.begin(), d_template.end(), d_corr->fwd.get_inbuf());
    d_corr->fwd.execute();
    for (int i = 0; i < w; ++i)
        d_corr->template_spectrum[size_t(i)] = std::conj(d_corr->fwd.get_outbuf()[i]) / float(w);
}

frame_search_result frame_search::search(const gr_complex* x) const
{
    correlator& k = *d_corr;
    const int w = window_len();
    std::vector<double>& energy = k.energy;
    energy[0] = 0.0;
    for (int i = 0; i < w; ++i)
        energy[size_t(i) + 1] = energy[size_t(i)] + std::norm(x[i]);
    std::copy(x, x + w, k.fwd.get_inbuf());
    k.fwd.execute();
    volk_32fc_x2_multiply_32fc(k.rev.get_inbuf(), k.fwd.get_outbuf(), k.template_spectrum.data(), w);
    k.rev.execute();
    std::copy(k.rev.get_outbuf(), k.rev.get_outbuf() + w, k.corr.begin());

    // z_f(θ) = L·|c_f|²/(Σ|t|²·E_f): one frame's own metric (Exp(1) on noise)
    auto frame_metric = [&](size_t start) {
        const double ex = energy[start + d_len] - energy[start];
        return ex > 0.0 ? std::norm(std::complex<double>(k.corr[start])) * d_len / (d_template_energy * ex) : 0.0;
    };
    frame_search_result best;
    best.metric = -1.0;
    for (int lag = 0; lag < d_len; ++lag) {
        double m = 0.0;
        if (d_noncoherent) {
            for (int f = 0; f < d_frames; ++f)
                m += frame_metric(size_t(lag) + size_t(f) * d_len);
        } else {
            std::complex<double> c(0.0, 0.0);
            double ex = 0.0;
            for (int f = 0; f < d_frames; ++f) {
                const size_t start = size_t(lag) + size_t(f) * d_len;
                c += std::complex<double>(k.corr[start]);
                ex += energy[start + d_len] - energy[start];
            }
            m = ex > 0.0 ? std::norm(c) * d_len / (d_template_energy * ex) : 0.0;
        }
        if (m > best.metric) {
            best.metric = m;
            best.lag = lag;
        }
    }
    best.found = best.metric > d_threshold;
    if (!best.found)
        return best;
    // The best lag fixes the frame phase; the stream may start within the window (silence
    // or noise before it): the first frame is the first whose own metric passes threshold / F.
    for (int f = 0; f < d_frames; ++f) {
        if (frame_metric(size_t(best.lag) + size_t(f) * d_len) > d_threshold / d_frames) {
            best.lag += f * d_len;
            break;
        }
    }
    return best;
}

} // namespace sems
} // namespace gr
