// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the channel model at sample level (see td_channel.h for the equations). */
#include "core/checks.h"
#include "core/complex_kernels.h"
#include "core/complex_mul.h"
#include <gnuradio/fft/fft.h>
#include <gnuradio/sems/core/steering.h>
#include <gnuradio/sems/core/td_channel.h>
#include <volk/volk.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {

constexpr double two_pi = 2.0 * M_PI;
// Phase error allowed by the linear (secant) micro-Doppler phase inside a chunk (rad): about
// float's own phase resolution.
constexpr double md_phase_tolerance_rad = 1e-7;

inline double frac(double x) { return x - std::floor(x); }
inline std::complex<double> cis(double rad) { return { std::cos(rad), std::sin(rad) }; }
using detail::mul; // the operands here are finite

// cis for a per-sample phase step: below 0.01 rad the Taylor series to x⁵ (error < x⁶/720,
// ~1.4e-15) instead of a sine and a cosine.
inline std::complex<double> cis_small(double x)
{
    if (!(std::fabs(x) < 0.01))
        return cis(x);
    const double x2 = x * x;
    return { 1.0 - x2 / 2.0 * (1.0 - x2 / 12.0), x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0)) };
}

// dst[k] = scale · exp(j2π cycles_per_step · k), k < n: anchored exactly every 64 steps.
void fill_phasors(gr_complex* dst, int n, std::complex<double> scale, double cycles_per_step)
{
    const std::complex<double> step = cis(two_pi * frac(cycles_per_step));
    for (int k0 = 0; k0 < n; k0 += 64) {
        std::complex<double> v = scale * cis(two_pi * frac(cycles_per_step * k0));
        for (int k = k0; k < std::min(n, k0 + 64); ++k, v = mul(v, step))
            dst[k] = gr_complex(v);
    }
}

} // namespace

struct td_channel::impl {
    struct path {
        int shift = 0;        // D: whole samples
        double frac = 0.0;    // δ in [0, 1)
        bool fractional = false;
        bool moving = false;  // Doppler or micro-Doppler: per-sample phasor
        bool has_md = false;
        int anchor = 0;       // samples between exact phase anchors
        std::complex<double> md_step{ 1.0, 0.0 };      // exp(j ω anchor/B): the micro-Doppler's turn per chunk
        std::complex<double> md_step_last{ 1.0, 0.0 }; // the same over a symbol's last chunk
        channel_path p;
        std::vector<gr_complex> shift_phasor; // α·exp(-j2π m δ/M)/M
        std::vector<gr_complex> buf;          // α·[previous symbol | current symbol], shifted by δ
        std::vector<gr_complex> doppler;      // exp(j2π ν k/B), k = 0..S-1 (Doppler without micro-Doppler)
        std::vector<gr_complex> symbol_phase; // exp(j2π ν (first_symbol + n) T), n = 0..N-1
        gr_complex w0_prev{ 0.0f, 0.0f };     // the previous symbol's tone sum at -δ
        bool filled = false;                  // tables and buf hold p's (set_paths)
    };

    int m, cp, s, n;
    double b, t, md_scale;
    gr::fft::fft_complex_fwd fwd;
    gr::fft::fft_complex_rev rev;
    std::vector<gr_complex> x_prev, x_cur; // FFT of the symbols' last M samples
    std::vector<gr_complex> raw_prev;      // the previous symbol's samples
    std::vector<path> paths;
    size_t n_paths = 0;
    uint64_t first_symbol = 0;

    impl(const frame_settings& fs)
        : m(fs.n_subcarriers),
          cp(fs.cp_len),
          s(fs.n_subcarriers + fs.cp_len),
          n(fs.n_symbols),
          b(fs.bandwidth_hz),
          t(fs.symbol_interval_s),
          md_scale(4.0 * M_PI / fs.wavelength_m()),
          fwd(fs.n_subcarriers),
          rev(fs.n_subcarriers),
          x_prev(m),
          x_cur(m),
          raw_prev(s)
    {
    }

    // Inverse FFT of x ⊙ shift_phasor: the symbol's tone sum at times j - δ (j = 0..M-1),
    // left in rev's output buffer.
    const gr_complex* shifted_core(const path& pa, const std::vector<gr_complex>& x)
    {
        volk_32fc_x2_multiply_32fc(rev.get_inbuf(), x.data(), pa.shift_phasor.data(), m);
        rev.execute();
        return rev.get_outbuf();
    }

    // dst[i] = w[(i - CP) mod M], i = 0..S-1 (the symbol with its prefix, from its core).
    void with_prefix(const gr_complex* w, gr_complex* dst) const
    {
        // Whole copies of the core, starting at core index (-CP) mod M.
        int j = ((-cp) % m + m) % m;
        for (int i = 0; i < s;) {
            const int run = std::min(m - j, s - i);
            std::memcpy(dst + i, w + j, sizeof(gr_complex) * run);
            i += run;
            j = 0;
        }
    }

    void fill_previous(path& pa)
    {
        pa.buf.resize(size_t(2) * s); // both halves are written before they are read
        if (!pa.fractional) {
            volk_32fc_s32fc_multiply_32fc(pa.buf.data(), raw_prev.data(), gr_complex(pa.p.gain), s);
            pa.w0_prev = 0.0f;
            return;
        }
        const gr_complex* w = shifted_core(pa, x_prev);
        with_prefix(w, pa.buf.data()); // its sample 0 is never read (delays < M ≤ S)
        pa.w0_prev = w[0];
    }

    void fill_current(path& pa, const gr_complex* in)
    {
        gr_complex* cur = pa.buf.data() + s;
        if (!pa.fractional) {
            volk_32fc_s32fc_multiply_32fc(cur, in, gr_complex(pa.p.gain), s);
            return;
        }
        const gr_complex* w = shifted_core(pa, x_cur);
        with_prefix(w, cur);
        cur[0] = pa.w0_prev; // time -δ lies in the previous symbol: its tone sum there
        pa.w0_prev = w[0];
    }

    // The next symbol reads this one's last D samples (its delay reaches back D < M ≤ S
    // samples): move them in front of the current half.
    void keep_tail(path& pa) const
    {
        std::memmove(pa.buf.data() + s - pa.shift, pa.buf.data() + 2 * s - pa.shift, sizeof(gr_complex) * pa.shift);
    }

    // out[k] += src[k] · exp(j2π ν t_k) · exp(j β sin(ω t_k + φ)),  t_k = sym·T + k/B (a
    // path with micro-Doppler). The phase is exact (double) at the symbol's start and at
    // each chunk start (there by recurrence in double: rounding ~1e-15 rad) and linear
    // within a chunk (detail::accumulate_rotator); the chunk is short enough that the
    // curvature left out, |θ''|·chunk²/8 (secant), stays below md_phase_tolerance_rad. Two
    // sines and cosines per symbol: exp(j(ω t + φ)) advances by a per-frame step per
    // chunk, and the phase over a chunk (well below 0.01 rad) turns by its Taylor series.
    void accumulate_micro_doppler(const path& pa, uint64_t sym, const gr_complex* src, gr_complex* out) const
    {
        const auto& p = pa.p;
        const double sd = static_cast<double>(sym);
        const double beta = md_scale * p.md_amplitude_m;
        const double doppler_rad_per_sample = two_pi * p.doppler_hz / b;
        std::complex<double> z = cis(two_pi * frac(p.md_rate_hz * t * sd) + p.md_phase_rad); // exp(j(ω t_k0 + φ))
        double th0 = beta * z.imag();
        std::complex<double> phase = cis(two_pi * frac(p.doppler_hz * t * sd) + th0); // at k0
        for (int k0 = 0; k0 < s; k0 += pa.anchor) {
            const int len = std::min(pa.anchor, s - k0);
            z = mul(z, len == pa.anchor ? pa.md_step : pa.md_step_last);
            const double th1 = beta * z.imag();
            const double turn = doppler_rad_per_sample * len + (th1 - th0); // the phase change over the chunk
            detail::accumulate_rotator(out + k0, src + k0, len, phase, cis_small(turn / len));
            phase = mul(phase, cis_small(turn));
            th0 = th1;
        }
    }
};

td_channel::td_channel(const frame_settings& fs) : d_fs(fs), d_s(fs.n_subcarriers + fs.cp_len)
{
    d_fs.validate();
    if (fs.cp_len < 0)
        throw std::invalid_argument("td_channel: cp_len must be >= 0, got " + std::to_string(fs.cp_len));
    const double symbol_s = d_s / fs.bandwidth_hz;
    if (fs.symbol_interval_s < symbol_s * (1.0 - 1e-12))
        throw std::invalid_argument(
            "td_channel: symbol_interval_s (T = " + std::to_string(fs.symbol_interval_s) +
            " s) is shorter than one symbol, (M + cp_len)/B = " + std::to_string(symbol_s) +
            " s: a symbol must fit its interval");
    d = std::make_unique<impl>(d_fs);
}

td_channel::~td_channel() = default;
td_channel::td_channel(td_channel&&) noexcept = default;
td_channel& td_channel::operator=(td_channel&&) noexcept = default;

void td_channel::reset()
{
    std::fill(d->x_prev.begin(), d->x_prev.end(), gr_complex(0.0f, 0.0f));
    std::fill(d->raw_prev.begin(), d->raw_prev.end(), gr_complex(0.0f, 0.0f));
    for (size_t l = 0; l < d->n_paths; ++l)
        d->fill_previous(d->paths[l]);
}

void td_channel::set_paths(const std::vector<channel_path>& paths, uint64_t first_symbol)
{
    auto& I = *d;
    if (I.paths.size() < paths.size())
        I.paths.resize(paths.size());
    I.n_paths = paths.size();
    I.first_symbol = first_symbol;
    const int m = I.m;
    for (size_t l = 0; l < paths.size(); ++l) {
        const auto& p = paths[l];
        auto& pa = I.paths[l];
        const double samples = p.delay_s * I.b;
        if (!checks::non_negative(samples) || samples >= m)
            throw std::invalid_argument("td_channel: path " + std::to_string(l) + " delay " +
                                        std::to_string(p.delay_s) + " s is outside [0, 1/Δf) = [0, " +
                                        std::to_string(m / I.b) + ") s");
        // A fixed scene's path keeps its tables, and its delayed samples of the previous
        // symbol (which depend on the delay and gain only) stay valid across the frame start.
        const bool same_samples = pa.filled && pa.p.delay_s == p.delay_s && pa.p.gain == p.gain;
        const bool same_doppler = pa.filled && pa.p.doppler_hz == p.doppler_hz;
        pa.p = p;
        pa.shift = static_cast<int>(std::floor(samples));
        pa.frac = samples - pa.shift;
        pa.fractional = pa.frac > 0.0;
        pa.has_md = p.md_rate_hz > 0.0 && p.md_amplitude_m > 0.0;
        pa.moving = pa.has_md || p.doppler_hz != 0.0;
        pa.anchor = I.s;
        if (pa.has_md) {
            const double beta = I.md_scale * p.md_amplitude_m, omega = two_pi * p.md_rate_hz;
            // |θ''| ≤ β ω² / B² per sample²; the secant's worst error over a chunk of K is |θ''| K²/8.
            const double k = std::sqrt(8.0 * md_phase_tolerance_rad * I.b * I.b / (beta * omega * omega));
            pa.anchor = std::max(1, std::min(I.s, static_cast<int>(std::floor(k))));
            pa.md_step = cis_cycles(p.md_rate_hz * pa.anchor / I.b);
            const int last = I.s % pa.anchor == 0 ? pa.anchor : I.s % pa.anchor;
            pa.md_step_last = cis_cycles(p.md_rate_hz * last / I.b);
        }
        // Phasor tables by recurrence in double, re-anchored every 64 steps (rounding ~1e-15).
        if (!same_doppler) {
            pa.doppler.resize(I.s);
            fill_phasors(pa.doppler.data(), I.s, 1.0, p.doppler_hz / I.b);
        }
        pa.symbol_phase.resize(I.n);
        fill_phasors(pa.symbol_phase.data(),
                     I.n,
                     doppler_phasor(static_cast<double>(first_symbol), p.doppler_hz, I.t),
                     p.doppler_hz * I.t);
        if (!same_samples) {
            pa.shift_phasor.resize(m);
            fill_phasors(pa.shift_phasor.data(), m, p.gain / static_cast<double>(m), -pa.frac / m);
            I.fill_previous(pa);
        }
        pa.filled = true;
    }
}

void td_channel::apply_symbol(int n, const gr_complex* in, gr_complex* out)
{
    auto& I = *d;
    if (n < 0 || n >= I.n)
        throw std::out_of_range("td_channel::apply_symbol: symbol index " + std::to_string(n) +
                                " is outside the frame's 0.." + std::to_string(I.n - 1));
    const int s = I.s;
    std::memcpy(I.fwd.get_inbuf(), in + I.cp, sizeof(gr_complex) * I.m);
    I.fwd.execute();
    std::memcpy(I.x_cur.data(), I.fwd.get_outbuf(), sizeof(gr_complex) * I.m);

    std::fill(out, out + s, gr_complex(0.0f, 0.0f));
    const uint64_t sym = I.first_symbol + static_cast<uint64_t>(n);
    for (size_t l = 0; l < I.n_paths; ++l) {
        auto& pa = I.paths[l];
        I.fill_current(pa, in);
        const gr_complex* src = pa.buf.data() + s - pa.shift;
        if (pa.has_md)
            I.accumulate_micro_doppler(pa, sym, src, out);
        else if (pa.moving)
            detail::accumulate_rotated(out, src, pa.doppler.data(), pa.symbol_phase[n], s);
        else // a static path
            volk_32f_x2_add_32f(reinterpret_cast<float*>(out),
                                reinterpret_cast<const float*>(out),
                                reinterpret_cast<const float*>(src),
                                2 * s);
        I.keep_tail(pa);
    }
    std::swap(I.x_prev, I.x_cur);
    std::memcpy(I.raw_prev.data(), in, sizeof(gr_complex) * s);
}

} // namespace sems
} // namespace gr
