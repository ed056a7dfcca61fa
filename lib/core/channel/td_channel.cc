// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the channel model at sample level (see td_channel.h for the equations). */
#include "core/common/checks.h"
#include "core/common/math_constants.h"
#include "core/kernels/complex_kernels.h"
#include "core/kernels/complex_mul.h"
#include "core/channel/scatterer_moments.h"
#include <gnuradio/fft/fft.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/td_channel.h>
#include <gnuradio/sems/core/scene/walker_model.h>
#include <volk/volk.h>
#include <algorithm>
#include <optional>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {

// Phase error allowed by the linear (secant) micro-Doppler phase inside a chunk (rad): about
// float's own phase resolution.
constexpr double md_phase_tolerance_rad = 1e-7;
// Error allowed by the interpolation of a scatterer body's terms between exact anchors,
// relative to a unit-power target (td_channel.h).
constexpr double body_interpolation_tolerance = 1e-6;

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

// ω, the fastest angular rate of a body's scatterer motion (td_channel.h): their radial
// displacement r has |r^(k)| ≤ v·ω^(k−1), v the peak speed (micro_motion_peak_speed_mps).
double motion_rate(const scatterer_body& b, double v)
{
    const double speed = std::fabs(b.speed_mps);
    struct {
        double v, speed;
        double operator()(const rotor_motion& r) const
        {
            const double reach = r.blade_length_m * std::cos(r.elevation_rad);
            return reach > 0.0 ? v / reach : 0.0; // 2π f_max
        }
        double operator()(const wheels_motion& w) const { return speed / w.wheel_radius_m; }
        double operator()(const scatterers_motion& s) const
        {
            double rate = 0.0;
            for (const auto& p : s.scatterers)
                for (const auto& h : p.harmonics)
                    if (h.amplitude_m > 0.0)
                        rate = std::max(rate, two_pi * h.rate_hz);
            return rate;
        }
        double operator()(const walker_motion& w) const
        {
            // the gait's trajectories: harmonics of the cycle, taken up to the 8th
            const double cycle = walker::cycle_duration_s(w.height_m, speed);
            return std::isfinite(cycle) && cycle > 0.0 ? 8.0 * two_pi / cycle : 0.0;
        }
    } rate{ v, speed };
    return std::visit(rate, b.motion);
}

} // namespace

struct td_channel::impl {
    // A scatterer body of the frame: its model, its expansion, and its terms at the chunk
    // anchors of the current symbol.
    struct body {
        detail::body_model model;
        detail::expansion_plan plan;
        std::vector<double> anchor_k;        // the anchors' sample offsets in the symbol (0 first)
        std::vector<int> base;               // per sample: its first anchor
        std::vector<float> weight;           // per sample: 4 weights of anchors base .. base + 3
        std::vector<std::complex<double>> g; // anchors x terms (double: exact anchors)
        std::vector<gr_complex> gf;          // the same in float, 3 anchors of zeros after
        uint64_t symbol = ~uint64_t(0);      // the symbol g holds
        std::optional<detail::body_steering> steering; // at an array element: where it is seen from
        body(const scatterer_body& b, const frame_settings& fs) : model(b, fs) {}
    };

    struct path {
        int shift = 0;        // D: whole samples
        double frac = 0.0;    // δ in [0, 1)
        bool fractional = false;
        bool moving = false;  // Doppler or micro-Doppler: per-sample phasor
        bool has_md = false;
        int anchor = 0;       // samples between exact phase anchors
        std::complex<double> md_step{ 1.0, 0.0 };      // exp(j ω anchor/B): the micro-Doppler's turn per chunk
        channel_path p;
        std::vector<gr_complex> shift_phasor; // α·exp(-j2π m δ/M)/M
        std::vector<gr_complex> buf;          // α·[previous symbol | current symbol], shifted by δ
        std::vector<gr_complex> doppler;      // exp(j2π ν k/B), k = 0..S-1 (Doppler without micro-Doppler)
        std::vector<gr_complex> symbol_phase; // exp(j2π ν (first_symbol + n) T), n = 0..N-1
        gr_complex tail_phase{ 1.0f, 0.0f };  // exp(−j2π ν (T − S/B)): the previous symbol's echo
        gr_complex w0_prev{ 0.0f, 0.0f };     // the previous symbol's tone sum at -δ
        bool filled = false;                  // tables and buf hold p's (set_paths)
        int body = -1;   // a term of a scatterer body's path: the body
        int term = 0;    // its term (band·(P+1) + p)
        int terms = 1;   // the path's terms (rows l − term .. l − term + terms − 1)
        double term_key = -1.0; // what its filter was built for (-1: a point path)
    };

    int m, cp, s, n;
    double b, t, md_scale;
    gr::fft::fft_complex_fwd fwd;
    gr::fft::fft_complex_rev rev;
    std::vector<gr_complex> x_prev, x_cur; // FFT of the symbols' last M samples
    std::vector<gr_complex> raw_prev;      // the previous symbol's samples
    std::vector<path> paths; // rows: one per point path, plan.terms() per body path
    size_t n_paths = 0;
    uint64_t first_symbol = 0;
    frame_settings fs;
    std::vector<body> bodies;
    size_t n_bodies = 0;
    detail::body_snapshot snap, steered_snap;
    std::vector<gr_complex> acc; // a body path's terms summed before its Doppler
    std::vector<channel_path> steered; // at an array element: the frame's paths as it receives them

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
          raw_prev(s),
          fs(fs),
          acc(s)
    {
    }

    // The body's terms at the anchors of symbol sym (once per symbol, shared by its paths).
    void body_anchors(body& bd, uint64_t sym)
    {
        if (bd.symbol == sym)
            return;
        bd.symbol = sym;
        const int terms = bd.plan.terms();
        const double t0 = static_cast<double>(sym) * t; // the frequency-domain model's t_n
        for (size_t j = 0; j < bd.anchor_k.size(); ++j) {
            const double k = bd.anchor_k[j];
            std::complex<double>* g = bd.g.data() + j * terms;
            const double at = k == 0.0 ? t0 : t0 + k / b;
            if (bd.steering) { // each scatterer from its own direction (steer_snapshot)
                bd.model.snapshots(&at, 1, snap, true);
                detail::steer_snapshot(snap, *bd.steering, steered_snap);
                detail::snapshot_terms(steered_snap, bd.plan, fs, g);
            } else {
                detail::body_terms(bd.model, bd.plan, fs, at, snap, g);
            }
            for (int i = 0; i < terms; ++i)
                bd.gf[size_t(j) * terms + i] = gr_complex(g[i]);
        }
    }

    // acc[k] += src[k] · g(k), g interpolated between the body's anchors (term `term`).
    static void accumulate_interpolated(gr_complex* accum, const gr_complex* src, const body& bd, int term, int s)
    {
        const size_t terms = static_cast<size_t>(bd.plan.terms());
        const gr_complex* g = bd.gf.data() + term;
        for (int k = 0; k < s; ++k) {
            const gr_complex* a = g + size_t(bd.base[k]) * terms;
            const float* w = bd.weight.data() + 4 * size_t(k);
            accum[k] += src[k] * (w[0] * a[0] + w[1] * a[terms] + w[2] * a[2 * terms] + w[3] * a[3 * terms]);
        }
    }

    // The body's anchors and each sample's weights: a constant for a still body, else
    // Lagrange interpolation of degree d = 1, 2 or 3 through d + 1 anchors h apart per segment,
    // the degree and segments needing the fewest anchors within body_interpolation_tolerance:
    // error ≤ |h^(d+1)|·C_d·h^(d+1)/(d+1)!, C_d = max over the segment of |Π_i (u − i)| (1/4,
    // 2/(3√3), 1), |h^(n)| ≤ Σ|a|(c + 2ω)^n for n ≤ 4 (c = κv, td_channel.h).
    void plan_anchors(body& bd, double amplitude_sum, double kappa_v, double omega) const
    {
        bd.anchor_k.clear();
        const double rate = (kappa_v + 2.0 * omega) / b; // per sample
        int degree = 0, segments = 1;
        if (rate > 0.0) {
            int best = 0;
            const double c_d[] = { 0.0, 0.25, 2.0 / (3.0 * std::sqrt(3.0)), 1.0 };
            for (int d = 1, factorial = 2; d <= 3; ++d, factorial *= d + 1) {
                const double h_max =
                    std::pow(body_interpolation_tolerance * factorial / (amplitude_sum * c_d[d]), 1.0 / (d + 1)) / rate;
                // anchors on samples for d = 1 (the segment a whole number of samples)
                const double h = d == 1 ? std::floor(h_max) : h_max;
                const int seg = h >= 1.0 ? std::max(1, static_cast<int>(std::ceil(s / (d * h)))) : s;
                if (best == 0 || d * seg + 1 < best) {
                    best = d * seg + 1;
                    degree = d;
                    segments = seg;
                }
            }
        }
        const int n_anchors = degree * segments + 1;
        for (int j = 0; j < n_anchors; ++j)
            bd.anchor_k.push_back(degree == 0 ? 0.0 : double(s) * j / (n_anchors - 1));
        bd.base.resize(s);
        bd.weight.resize(size_t(4) * s);
        for (int k = 0; k < s; ++k) {
            float* wk = bd.weight.data() + 4 * size_t(k);
            std::fill(wk, wk + 4, 0.0f);
            if (degree == 0) {
                bd.base[k] = 0;
                wk[0] = 1.0f;
                continue;
            }
            const double h = double(s) / (n_anchors - 1);
            const int seg = std::min(segments - 1, static_cast<int>(k / (degree * h)));
            bd.base[k] = degree * seg;
            const double u = (k - bd.anchor_k[degree * seg]) / h; // in [0, degree]
            for (int i = 0; i <= degree; ++i) {
                double w = 1.0;
                for (int j = 0; j <= degree; ++j)
                    if (j != i)
                        w *= (u - j) / (i - j);
                wk[i] = static_cast<float>(w);
            }
        }
        bd.g.resize(size_t(n_anchors) * bd.plan.terms());
        bd.gf.assign(size_t(n_anchors + 3) * bd.plan.terms(), gr_complex(0.0f, 0.0f));
        bd.symbol = ~uint64_t(0);
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
        if (pa.frac > 0.0) // time -δ lies in the previous symbol: its tone sum there
            cur[0] = pa.w0_prev;
        pa.w0_prev = w[0];
    }

    // The next symbol reads this one's last D samples (its delay reaches back D < M ≤ S
    // samples): move them in front of the current half.
    void keep_tail(path& pa) const
    {
        std::memmove(pa.buf.data() + s - pa.shift, pa.buf.data() + 2 * s - pa.shift, sizeof(gr_complex) * pa.shift);
    }

    // out[k] += src[k] · exp(j2π ν t_k) over symbol n (a path with Doppler alone). The echo
    // of one transmitted symbol keeps one slow time: its first D samples (D = the path's
    // whole-sample delay) end the previous symbol's echo and keep that symbol's phase,
    // t_k = (sym − 1)·T + (S + k)/B, i.e. this symbol's times shifted by T − S/B.
    void accumulate_doppler(const path& pa, int n, const gr_complex* src, gr_complex* out) const
    {
        const int d = std::min(pa.shift, s);
        const gr_complex now = pa.symbol_phase[n];
        if (d > 0)
            detail::accumulate_rotated(out, src, pa.doppler.data(), now * pa.tail_phase, d);
        detail::accumulate_rotated(out + d, src + d, pa.doppler.data() + d, now, s - d);
    }

    // The same with micro-Doppler, over symbol sym: the first D samples end the previous
    // symbol's echo and continue its slow time, as in accumulate_doppler().
    void accumulate_micro_doppler_symbol(const path& pa, uint64_t sym, const gr_complex* src, gr_complex* out) const
    {
        const int d = std::min(pa.shift, s);
        const double sd = static_cast<double>(sym);
        if (d > 0)
            accumulate_micro_doppler(pa, sd - 1.0, 0, d, s, src, out);
        accumulate_micro_doppler(pa, sd, d, s, 0, src, out);
    }

    // out[k] += src[k] · exp(j2π ν t_k) · exp(j β sin(ω t_k + φ)) for k_from ≤ k < k_to,
    // t_k = sym·T + (k + k_time)/B (a path with micro-Doppler; k_time = S with sym − 1 for the
    // samples that end the previous symbol's echo). The phase is exact (double) at the
    // segment's start and at each chunk start (there by recurrence in double: rounding
    // ~1e-15 rad) and linear within a chunk (detail::accumulate_rotator); the chunk is short
    // enough that the curvature left out, |θ''|·chunk²/8 (secant), stays below
    // md_phase_tolerance_rad. Two sines and cosines per segment: exp(j(ω t + φ)) advances by a
    // per-frame step per chunk, and the phase over a chunk (well below 0.01 rad) turns by its
    // Taylor series.
    void accumulate_micro_doppler(const path& pa,
                                  double sym,
                                  int k_from,
                                  int k_to,
                                  int k_time,
                                  const gr_complex* src,
                                  gr_complex* out) const
    {
        const auto& p = pa.p;
        const double beta = md_scale * p.md_amplitude_m;
        const double doppler_rad_per_sample = two_pi * p.doppler_hz / b;
        const double k_start = static_cast<double>(k_from + k_time) / b; // s after the symbol's start
        std::complex<double> z = cis(two_pi * (frac(p.md_rate_hz * t * sym) + frac(p.md_rate_hz * k_start)) +
                                     p.md_phase_rad); // exp(j(ω t_k0 + φ))
        double th0 = beta * z.imag();
        std::complex<double> phase =
            cis(two_pi * (frac(p.doppler_hz * t * sym) + frac(p.doppler_hz * k_start)) + th0); // at k0
        for (int k0 = k_from; k0 < k_to; k0 += pa.anchor) {
            const int len = std::min(pa.anchor, k_to - k0);
            z = mul(z, len == pa.anchor ? pa.md_step : cis_cycles(p.md_rate_hz * len / b));
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

td_channel::td_channel(const frame_settings& fs, const array_element& element) : td_channel(fs)
{
    d_element = element;
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
    for (size_t l = 0; l < paths.size(); ++l)
        if (paths[l].body >= 0)
            throw std::invalid_argument("td_channel: path " + std::to_string(l) + " refers to scatterer body " +
                                        std::to_string(paths[l].body) +
                                        ": set_paths takes point paths only, set_frame a frame with its bodies");
    set_paths(paths, nullptr, first_symbol);
}

void td_channel::set_frame(const frame_realization& r, uint64_t first_symbol)
{
    set_paths(r.paths, &r.bodies, r.clock_symbol.value_or(first_symbol));
}

void td_channel::set_paths(const std::vector<channel_path>& frame_paths,
                           const std::vector<scatterer_body>* bodies,
                           uint64_t first_symbol)
{
    auto& I = *d;
    const int m = I.m;
    // At an array element: the paths as it receives them (steered_path, the frequency-domain
    // model's); each body seen from its first path's range and direction.
    const bool steered = !d_element.is_origin();
    if (steered) {
        I.steered.resize(frame_paths.size());
        for (size_t l = 0; l < frame_paths.size(); ++l)
            I.steered[l] = detail::steered_path(frame_paths[l], d_element, d_fs.wavelength_m());
    }
    const std::vector<channel_path>& paths = steered ? I.steered : frame_paths;
    // Scatterer bodies: a model, its expansion and its anchors, kept while its parameters stay
    // (a fixed scene's are set up once).
    const size_t n_bodies = bodies ? bodies->size() : 0;
    if (I.bodies.size() > n_bodies)
        I.bodies.erase(I.bodies.begin() + n_bodies, I.bodies.end());
    const double kappa_max =
        4.0 * M_PI * (d_fs.carrier_hz + (m - 1) * d_fs.subcarrier_spacing_hz()) / speed_of_light_mps;
    for (size_t b = 0; b < n_bodies; ++b) {
        const auto& rb = (*bodies)[b];
        if (b >= I.bodies.size())
            I.bodies.emplace_back(rb, d_fs);
        else if (!detail::same_body(I.bodies[b].model.body(), rb))
            I.bodies[b] = impl::body(rb, d_fs);
        else
            continue;
        auto& bd = I.bodies[b];
        // At an element a scatterer's displacement moves by at most the element's reach, |o|.
        const double reach = steered ? std::hypot(d_element.offset[0], d_element.offset[1], d_element.offset[2]) : 0.0;
        bd.plan = detail::plan_expansion(d_fs, bd.model.extent_m() + reach, bd.model.amplitude_sum());
        const double v = micro_motion_peak_speed_mps(rb.motion, rb.speed_mps);
        I.plan_anchors(bd, bd.model.amplitude_sum(), kappa_max * v, motion_rate(rb, v));
    }
    I.n_bodies = n_bodies;
    for (size_t b = 0; b < n_bodies; ++b) { // where each body is seen from (its first path)
        auto& bd = I.bodies[b];
        const std::optional<detail::body_steering> before = bd.steering;
        bd.steering.reset();
        if (steered)
            for (const auto& p : frame_paths)
                if (p.body == static_cast<int>(b)) {
                    bd.steering = detail::make_body_steering(0.5 * speed_of_light_mps * p.delay_s, p.azimuth_rad,
                                                             p.elevation_rad, d_element);
                    break;
                }
        const bool same = before.has_value() == bd.steering.has_value() &&
                          (!before || (before->range_m == bd.steering->range_m && before->u == bd.steering->u));
        if (!same)
            bd.symbol = ~uint64_t(0); // its anchors were for another geometry
    }

    // Rows: one per point path, plan.terms() per body path.
    size_t rows = 0;
    for (size_t l = 0; l < paths.size(); ++l) {
        const int body = paths[l].body;
        if (body >= 0 && static_cast<size_t>(body) >= n_bodies)
            throw std::invalid_argument("td_channel: path " + std::to_string(l) + " refers to scatterer body " +
                                        std::to_string(body) + " but the frame has " + std::to_string(n_bodies));
        rows += body >= 0 ? static_cast<size_t>(I.bodies[body].plan.terms()) : 1;
    }
    if (I.paths.size() < rows)
        I.paths.resize(rows);
    I.n_paths = rows;
    I.first_symbol = first_symbol;
    size_t row = 0;
    for (size_t l = 0; l < paths.size(); ++l) {
        const auto& p = paths[l];
        const double samples = p.delay_s * I.b;
        if (!checks::non_negative(samples) || samples >= m)
            throw std::invalid_argument("td_channel: path " + std::to_string(l) + " delay " +
                                        std::to_string(p.delay_s) + " s is outside [0, 1/Δf) = [0, " +
                                        std::to_string(m / I.b) + ") s");
        const impl::body* bd = p.body >= 0 ? &I.bodies[p.body] : nullptr;
        const int terms = bd ? bd->plan.terms() : 1;
        for (int term = 0; term < terms; ++term, ++row) {
            auto& pa = I.paths[row];
            // What the term's filter depends on besides delay and gain (FD's delay-row key).
            const double term_key =
                bd ? term + 1000.0 * bd->plan.order + 1e6 * bd->plan.band_len : -1.0;
            // A fixed scene's path keeps its tables, and its delayed samples of the previous
            // symbol (which depend on the delay, gain and filter only) stay valid across the
            // frame start.
            const bool same_samples =
                pa.filled && pa.p.delay_s == p.delay_s && pa.p.gain == p.gain && pa.term_key == term_key;
            const bool same_doppler =
                pa.filled && pa.p.doppler_hz == p.doppler_hz && pa.doppler.size() == static_cast<size_t>(I.s);
            pa.p = p;
            pa.body = p.body;
            pa.term = term;
            pa.terms = terms;
            pa.term_key = term_key;
            pa.shift = static_cast<int>(std::floor(samples));
            pa.frac = samples - pa.shift;
            pa.fractional = bd || pa.frac > 0.0; // a body's terms are filtered per symbol
            pa.has_md = !bd && p.md_rate_hz > 0.0 && p.md_amplitude_m > 0.0; // a body has no sinusoid (as FD)
            pa.moving = pa.has_md || p.doppler_hz != 0.0;
            pa.anchor = I.s;
            if (pa.has_md) {
                const double beta = I.md_scale * p.md_amplitude_m, omega = two_pi * p.md_rate_hz;
                // |θ''| ≤ β ω² / B² per sample²; the secant's worst error over a chunk of K is |θ''| K²/8.
                const double k = std::sqrt(8.0 * md_phase_tolerance_rad * I.b * I.b / (beta * omega * omega));
                pa.anchor = std::max(1, static_cast<int>(std::min<double>(I.s, std::floor(k)))); // k may pass INT_MAX
                pa.md_step = cis_cycles(p.md_rate_hz * pa.anchor / I.b);
            }
            // Phasor tables by recurrence in double, re-anchored every 64 steps (rounding ~1e-15);
            // a body path's Doppler is applied once, after its terms: its first row holds the tables.
            if (term == 0) {
                if (!same_doppler) {
                    pa.doppler.resize(I.s);
                    fill_phasors(pa.doppler.data(), I.s, 1.0, p.doppler_hz / I.b);
                }
                pa.symbol_phase.resize(I.n);
                fill_phasors(pa.symbol_phase.data(),
                             I.n,
                             doppler_phasor(static_cast<double>(first_symbol), p.doppler_hz, I.t),
                             p.doppler_hz * I.t);
                pa.tail_phase = gr_complex(cis_cycles(-p.doppler_hz * (I.t - I.s / I.b)));
            } else {
                pa.doppler.clear(); // not this row's: filled again if it becomes a path's first
            }
            if (!same_samples) {
                pa.shift_phasor.resize(m);
                fill_phasors(pa.shift_phasor.data(), m, p.gain / static_cast<double>(m), -pa.frac / m);
                if (bd)
                    for (int i = 0; i < m; ++i)
                        pa.shift_phasor[i] *= static_cast<float>(detail::term_factor(d_fs, bd->plan, term, i));
                I.fill_previous(pa);
            }
            pa.filled = true;
        }
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
        if (pa.body >= 0) { // a term of a body path: summed, then the path's Doppler
            auto& bd = I.bodies[pa.body];
            I.body_anchors(bd, sym);
            if (pa.term == 0)
                std::fill(I.acc.begin(), I.acc.end(), gr_complex(0.0f, 0.0f));
            impl::accumulate_interpolated(I.acc.data(), src, bd, pa.term, s);
            I.keep_tail(pa);
            if (pa.term + 1 < pa.terms)
                continue;
            const auto& first = I.paths[l - pa.term]; // the path's first row holds its Doppler tables
            if (first.moving)
                I.accumulate_doppler(first, n, I.acc.data(), out);
            else
                volk_32f_x2_add_32f(reinterpret_cast<float*>(out),
                                    reinterpret_cast<const float*>(out),
                                    reinterpret_cast<const float*>(I.acc.data()),
                                    2 * s);
            continue;
        }
        if (pa.has_md)
            I.accumulate_micro_doppler_symbol(pa, sym, src, out);
        else if (pa.moving)
            I.accumulate_doppler(pa, n, src, out);
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
