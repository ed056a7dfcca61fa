// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: one frame through the radio front end (front_end_frame.h has the chain). */
#include "core/common/checks.h"
#include "core/common/math_constants.h"
#include "core/kernels/gaussian_generator.h"
#include <gnuradio/sems/core/radio/front_end_frame.h>
#include <gnuradio/sems/core/radio/leakage_canceller.h>
#include <gnuradio/sems/core/frame/ofdm_modem.h>
#include <gnuradio/sems/core/radio/phase_noise.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <vector>

namespace gr {
namespace sems {

namespace {
// Seeds of the frame's draws, apart from each other.
constexpr uint64_t tx_osc_seed = 0x9E3779B97F4A7C15ULL, rx_osc_seed = 0xBF58476D1CE4E5B9ULL,
                   noise_seed = 0x94D049BB133111EBULL;
} // namespace

struct front_end_frame::impl {
    frame_settings fs;
    front_end_settings radio;
    int n, m, s;
    size_t frame_len;  // F = N·S
    double tx_power;
    bool cancel;
    leakage_canceller_settings canceller;
    std::vector<gr_complex> leak;  // the leakage taps
    std::vector<char> used;        // per subcarrier
    ofdm_modem modem;
    std::vector<gr_complex> x;        // 2N x M: the warm-up's and the frame's symbols
    std::vector<gr_complex> tx;       // 2F baseband transmitted samples
    std::vector<gr_complex> rx;       // 2F received samples
    std::vector<double> phi_tx, phi_rx; // lead + 2F phases (index 0 = sample −lead); phi_rx: separate only
    std::vector<gr_complex> osc_rx;     // e^{jφ_rx}, the same samples
    std::vector<gr_complex> sent;       // e^{jφ_tx}·tx, the same samples (0 before the warm-up)
    std::vector<gr_complex> hx;         // a symbol's H·X

    impl(const frame_settings& f, const front_end_settings& r)
        : fs(f),
          radio(r),
          n(f.n_symbols),
          m(f.n_subcarriers),
          s(f.n_subcarriers + f.cp_len),
          modem(f.n_subcarriers, f.cp_len)
    {
        frame_len = static_cast<size_t>(n) * s;
        used.assign(static_cast<size_t>(m), 1);
        int n_used = m;
        for (int g : fs.guard_subcarriers) {
            used[static_cast<size_t>(g)] = 0;
            --n_used;
        }
        tx_power = static_cast<double>(n_used) / m;
        leak = radio.leakage_response();
        cancel = radio.oscillator == oscillator_kind::shared && (radio.leakage_db || radio.dc_offset_db);
        canceller.window = static_cast<int>(frame_len);
        canceller.taps = std::max(canceller.taps, radio.leakage_db ? radio.leakage_taps : 1);
        canceller.validate();
        x.resize(2 * static_cast<size_t>(n) * m);
        tx.resize(2 * frame_len);
        rx.resize(2 * frame_len);
        hx.resize(static_cast<size_t>(m));
    }

    // φ at fractional sample t (from the lead-in on), linear between samples.
    static double phase_at(const std::vector<double>& phi, double t)
    {
        const double f = std::floor(t);
        const size_t i = static_cast<size_t>(f);
        const double w = t - f;
        return w == 0.0 ? phi[i] : (1.0 - w) * phi[i] + w * phi[i + 1];
    }
};

front_end_frame::front_end_frame(const frame_settings& frame, const front_end_settings& radio)
{
    frame.validate();
    radio.validate();
    if (radio.sfo_ppm != 0.0)
        throw std::invalid_argument("front end frame: sfo_ppm is " + checks::text(radio.sfo_ppm) +
                                    ", but a sample clock offset is not modelled per frame (set it to 0)");
    d = std::make_unique<impl>(frame, radio);
}

front_end_frame::~front_end_frame() = default;

double front_end_frame::tx_power() const { return d->tx_power; }
bool front_end_frame::cancels() const { return d->cancel; }
const frame_settings& front_end_frame::frame() const { return d->fs; }

void front_end_frame::observe(const gr_complex* h, double delay_index, double noise_variance, uint64_t seed,
                              gr_complex* out)
{
    if (!checks::non_negative(delay_index))
        throw std::invalid_argument("front end frame: delay_index must be finite and >= 0, got " +
                                    checks::text(delay_index));
    if (!checks::non_negative(noise_variance))
        throw std::invalid_argument("front end frame: noise_variance must be finite and >= 0, got " +
                                    checks::text(noise_variance));
    impl& p = *d;
    const front_end_settings& r = p.radio;
    const int n = p.n, m = p.m, s = p.s;
    const size_t F = p.frame_len, total = 2 * F;
    std::mt19937_64 bits(seed);

    // 1-2. Symbols (QPSK on used subcarriers) and the baseband transmitted samples.
    const float a = static_cast<float>(std::sqrt(0.5));
    for (int sym = 0; sym < 2 * n; ++sym) {
        gr_complex* xs = &p.x[static_cast<size_t>(sym) * m];
        uint64_t b = 0;
        for (int k = 0; k < m; ++k) {
            if (k % 32 == 0)
                b = bits();
            const unsigned q = static_cast<unsigned>(b >> (2 * (k % 32))) & 3u;
            xs[k] = p.used[static_cast<size_t>(k)] ? gr_complex(q & 1u ? -a : a, q & 2u ? -a : a) : gr_complex(0, 0);
        }
        p.modem.modulate(xs, &p.tx[static_cast<size_t>(sym) * s]);
    }

    // Oscillators from `lead` samples before the warm-up (the echo's and the leakage's reach).
    const size_t lead = static_cast<size_t>(std::ceil(delay_index)) + p.leak.size() + 1;
    const double diffusion = r.phase_diffusion();
    p.phi_tx.assign(lead + total, 0.0);
    if (diffusion > 0.0) {
        phase_noise_process tx_osc(diffusion, p.fs.bandwidth_hz, seed + tx_osc_seed);
        for (auto& v : p.phi_tx)
            v = tx_osc.next();
        if (r.oscillator == oscillator_kind::separate) {
            phase_noise_process rx_osc(diffusion, p.fs.bandwidth_hz, seed + rx_osc_seed);
            p.phi_rx.resize(lead + total);
            for (auto& v : p.phi_rx)
                v = rx_osc.next();
        }
    }
    // One oscillator (monostatic) or none: the receiver's phases are the transmitter's.
    const std::vector<double>& phi_rx =
        diffusion > 0.0 && r.oscillator == oscillator_kind::separate ? p.phi_rx : p.phi_tx;
    // The oscillators as phasors: e^{jφ_tx}·x is what leaves the transmitter.
    const bool noisy_osc = diffusion > 0.0;
    if (noisy_osc) {
        p.osc_rx.resize(lead + total);
        p.sent.resize(lead + total);
        for (size_t i = 0; i < lead + total; ++i) {
            p.osc_rx[i] = std::polar(1.0f, static_cast<float>(phi_rx[i]));
            const gr_complex x = i < lead ? gr_complex(0, 0) : p.tx[i - lead];
            p.sent[i] = x * std::polar(1.0f, static_cast<float>(p.phi_tx[i]));
        }
    } else {
        p.sent.assign(lead, gr_complex(0, 0));
        p.sent.insert(p.sent.end(), p.tx.begin(), p.tx.end());
    }

    // 3-4. Echo (the frame only) and leakage (the warm-up and the frame), down-converted.
    std::fill(p.rx.begin(), p.rx.end(), gr_complex(0, 0));
    for (int sym = 0; sym < n; ++sym) {
        const gr_complex* xs = &p.x[static_cast<size_t>(n + sym) * m];
        for (int k = 0; k < m; ++k)
            p.hx[static_cast<size_t>(k)] = h[static_cast<size_t>(sym) * m + k] * xs[k];
        p.modem.modulate(p.hx.data(), &p.rx[F + static_cast<size_t>(sym) * s]);
    }
    if (noisy_osc)
        for (size_t t = F; t < total; ++t) {
            const double turn = p.phase_at(p.phi_tx, static_cast<double>(lead + t) - delay_index) - phi_rx[lead + t];
            p.rx[t] *= std::polar(1.0f, static_cast<float>(turn));
        }
    if (!p.leak.empty())
        for (size_t t = 0; t < total; ++t) {
            gr_complex y(0, 0);
            for (size_t k = 0; k < p.leak.size(); ++k)
                y += p.leak[k] * p.sent[lead + t - k];
            p.rx[t] += noisy_osc ? y * std::conj(p.osc_rx[lead + t]) : y;
        }

    // 5. Noise.
    gaussian_generator noise(seed + noise_seed);
    noise.add(p.rx.data(), total, static_cast<float>(std::sqrt(noise_variance)));

    // 6. CFO, IQ imbalance, DC, converter.
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double theta0 = 2.0 * pi * unit(bits);
    const double w_cfo = 2.0 * pi * r.cfo_hz / p.fs.bandwidth_hz;
    const std::complex<double> mu = r.iq_mu(), nu = r.iq_nu();
    const double dc = r.dc_amplitude(p.tx_power, noise_variance);
    const std::complex<double> dc_c = std::polar(dc, pi / 4.0);
    const double full = r.full_scale(p.tx_power, noise_variance);
    const double steps = r.adc_enob ? std::pow(2.0, *r.adc_enob - 1.0) : 0.0;
    auto convert = [&](float v) {
        const float u = std::clamp(v * static_cast<float>(1.0 / full), -1.0f, 1.0f);
        return static_cast<float>(std::nearbyint(u * steps) / steps * full);
    };
    for (size_t t = 0; t < total; ++t) {
        std::complex<double> y(p.rx[t]);
        if (w_cfo != 0.0)
            y *= std::polar(1.0, w_cfo * static_cast<double>(t) + theta0);
        y = mu * y + nu * std::conj(y) + dc_c;
        gr_complex z(y);
        if (full > 0.0)
            z = gr_complex(convert(z.real()), convert(z.imag()));
        p.rx[t] = z;
    }

    // 7. The canceller: a window of the leakage alone, then the frame.
    if (p.cancel) {
        leakage_canceller_settings cs = p.canceller;
        cs.clip_level = full;
        leakage_fit fit(cs);
        fit.process(p.rx.data(), p.tx.data(), p.rx.data());
        fit.hold_as_steady_state(); // that window stands for the stream's earlier ones
        fit.process(p.rx.data() + F, p.tx.data() + F, p.rx.data() + F);
    }

    // 8. FFT of each prefix-free window, divided by X.
    for (int sym = 0; sym < n; ++sym) {
        const gr_complex* xs = &p.x[static_cast<size_t>(n + sym) * m];
        gr_complex* o = out + static_cast<size_t>(sym) * m;
        p.modem.demodulate(&p.rx[F + static_cast<size_t>(sym) * s], o);
        for (int k = 0; k < m; ++k)
            if (p.used[static_cast<size_t>(k)])
                o[k] = o[k] * std::conj(xs[k]) / std::norm(xs[k]);
    }
}

} // namespace sems
} // namespace gr
