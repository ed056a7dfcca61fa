// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: td_channel (the sample-level synthesis) against the frequency-domain model
 * and its own bookkeeping: OFDM through it equals H·X when every delay is inside the
 * prefix; the micro-Doppler phase is the model's; scatterer bodies (rotors, walkers, wheels,
 * point scatterers) equal the frequency-domain model's up to the motion within a symbol, and
 * follow the bodies' exact per-sample return; bad settings and delays are refused. */
#include "core/channel/scatterer_moments.h"
#include "qa/qa_assert.h"
#include <gnuradio/fft/fft.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/frame/ofdm_modem.h>
#include <gnuradio/sems/core/channel/td_channel.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <random>
#include <vector>

using namespace gr::sems;

namespace {

using ofdm = gr::sems::ofdm_modem; // unitary CP-OFDM, the maths of ofdm_tx/ofdm_rx

// NMSE of TD -> OFDM receiver against H·X of the frequency-domain model, same seed.
double nmse_against_fd(const frame_settings& fs, const scene& sc, int frames)
{
    channel_model fd(fs, sc, 7), tdm(fs, sc, 7);
    td_channel td(fs);
    ofdm o(fs.n_subcarriers, fs.cp_len);
    const int n = fs.n_symbols, m = fs.n_subcarriers, s = m + fs.cp_len;
    std::mt19937 g(1);
    std::vector<gr_complex> x(m), t(s), y(s), rx(m), h(m);
    double err = 0.0, pw = 0.0;
    for (int f = 0; f < frames; ++f) {
        const auto r = fd.draw(f);
        const auto fc = fd.factors(r, uint64_t(f) * n);
        td.set_paths(tdm.draw(f).paths, uint64_t(f) * n);
        for (int k = 0; k < n; ++k) {
            for (auto& v : x)
                v = gr_complex((g() & 1) ? 1.0f : -1.0f, (g() & 1) ? 1.0f : -1.0f) * float(M_SQRT1_2);
            o.modulate(x.data(), t.data());
            td.apply_symbol(k, t.data(), y.data());
            o.demodulate(y.data(), rx.data());
            fc.row(k, h.data());
            for (int i = 0; i < m; ++i) {
                err += std::norm(rx[i] - h[i] * x[i]);
                pw += std::norm(h[i] * x[i]);
            }
        }
    }
    return err / pw;
}

target_spec target(target_class c, double range, double v, std::vector<path_spec> paths = { path_spec{} })
{
    target_spec t;
    t.cls = c;
    t.range_m = range;
    t.velocity_mps = v;
    t.paths = std::move(paths);
    return t;
}

// A target with scatterer motion at speed `speed` (heading 0) and two paths.
target_spec body_target(const micro_motion& m, double range, double speed)
{
    auto t = target(target_class::car, range, speed, { { 0.0, 1.0 }, { 13.37, 0.5 } });
    t.speed_mps = speed;
    t.motion = m;
    return t;
}

struct body_result {
    double nmse;  // Σ|FFT(TD window) − H·X|² / (Σ_l |α_l|² · Σ|X|²)
    double bound; // the in-symbol bound of td_channel.h, (Σ|a|·κ·v·(S−1)/B)², in the same units
};

// One scatterer-body (or point) target through TD (set_frame) and FD (frame_channel on the
// same realization, at the same array element), its bulk Doppler set to 0 in both (its per-sample vs per-symbol difference is
// the point path's, doppler_error_is_closed_form): what remains is the body.
body_result body_against_fd(const frame_settings& fs, const target_spec& t, int frames,
                            const array_element& element = {})
{
    auto sc = scene::fixed({ t }, std::nullopt, 0, fading_kind::rayleigh);
    channel_model model(fs, sc, 11);
    td_channel td(fs, element);
    ofdm o(fs.n_subcarriers, fs.cp_len);
    const int n = fs.n_symbols, m = fs.n_subcarriers, s = m + fs.cp_len;
    std::mt19937 g(5);
    std::vector<gr_complex> x(m), tx(s), y(s), rx(m), h(m);
    double err = 0.0, ref = 0.0, gains = 0.0;
    for (int f = 0; f < frames; ++f) {
        auto r = model.draw(f);
        for (auto& p : r.paths)
            p.doppler_hz = 0.0;
        gains = 0.0;
        for (const auto& p : r.paths)
            gains += std::norm(p.gain);
        const uint64_t first = uint64_t(f) * n + 1000003; // far from 0: slow time is absolute
        const frame_channel fc(fs, r, first, element);
        td.set_frame(r, first);
        for (int k = 0; k < n; ++k) {
            for (auto& v : x)
                v = gr_complex((g() & 1) ? 1.0f : -1.0f, (g() & 1) ? 1.0f : -1.0f) * float(M_SQRT1_2);
            o.modulate(x.data(), tx.data());
            td.apply_symbol(k, tx.data(), y.data());
            o.demodulate(y.data(), rx.data());
            fc.row(k, h.data());
            for (int i = 0; i < m; ++i) {
                err += std::norm(rx[i] - h[i] * x[i]);
                ref += gains * std::norm(x[i]);
            }
        }
    }
    if (!t.motion) // a point target: no in-symbol bound of a body
        return { err / ref, 0.0 };
    const scatterer_body body{ *t.motion, target_speed_heading(t).first, target_speed_heading(t).second };
    const gr::sems::detail::body_model bm(body, fs);
    const double kappa = 4 * M_PI * (fs.carrier_hz + (m - 1) * fs.subcarrier_spacing_hz()) / speed_of_light_mps;
    const double d = bm.amplitude_sum() * kappa * micro_motion_peak_speed_mps(body.motion, body.speed_mps) *
                     (s - 1) / fs.bandwidth_hz;
    return { err / ref, d * d };
}

rotor_motion quadcopter(double rev_per_s)
{
    rotor_motion r; // 4 rotors of 2 blades
    r.blade_length_m = 0.13;
    r.rotation_hz = { rev_per_s, 0.93 * rev_per_s, 1.07 * rev_per_s, rev_per_s };
    r.phase_rad = { 0.1, 1.2, 2.3, 3.4 };
    r.elevation_rad = 0.2;
    return r;
}

wheels_motion car_wheels()
{
    wheels_motion w;
    w.spokes = 5;
    return w;
}

// A bicyclist-like body: a fixed torso, pedalling feet, rim points (harmonics; rate 0: offsets).
scatterers_motion bicyclist(double rate_scale)
{
    scatterers_motion s;
    s.scatterers.push_back({ 0.35, {} });
    s.scatterers.push_back({ 0.1, { { 0.17, 1.4 * rate_scale, 0.0 } } });
    s.scatterers.push_back({ 0.1, { { 0.17, 1.4 * rate_scale, M_PI } } });
    for (int i = 0; i < 4; ++i)
        s.scatterers.push_back({ 0.05, { { 0.5, 0.0, -M_PI / 2 }, { 0.34, 2.2 * rate_scale, i * M_PI / 2 } } });
    return s;
}

} // namespace

class qa_td_channel : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_td_channel);
    CPPUNIT_TEST(equals_frequency_domain_inside_prefix);
    CPPUNIT_TEST(past_prefix_is_not_frequency_domain);
    CPPUNIT_TEST(doppler_error_is_closed_form);
    CPPUNIT_TEST(kept_path_equals_refilled_path);
    CPPUNIT_TEST(micro_doppler_phase_per_sample);
    CPPUNIT_TEST(bad_settings_and_delays);
    CPPUNIT_TEST(still_bodies_equal_frequency_domain);
    CPPUNIT_TEST(array_elements_equal_frequency_domain);
    CPPUNIT_TEST(moving_bodies_within_in_symbol_bound);
    CPPUNIT_TEST(body_return_per_sample);
    CPPUNIT_TEST(bodies_at_extremes_are_finite);
    CPPUNIT_TEST(body_paths_need_set_frame);
    CPPUNIT_TEST_SUITE_END();

public:
    void equals_frequency_domain_inside_prefix()
    {
        frame_settings fs; // M 64, CP 16: fractional delays up to 80 m, multipath, Rayleigh, clutter
        auto sc = scene::fixed({ target(target_class::car, 7.3, 0.0, { { 0.0, 1.0 }, { 31.1, 0.5 } }),
                                 target(target_class::pedestrian, 66.6, 0.0) },
                               clutter_spec{ 0.0, 3, 0.0, 79.0, {} });
        CPPUNIT_ASSERT_LESS(1e-11, nmse_against_fd(fs, sc, 3));
    }

    void past_prefix_is_not_frequency_domain()
    {
        // One static path 4 samples past a 16-sample prefix: the FD model's NMSE is 2e/M
        // (closed form, data-dependent estimate: 10 %).
        frame_settings fs;
        auto sc = scene::fixed({ target(target_class::car, 100.0, 0.0) }, std::nullopt, 0, fading_kind::none);
        const double got = nmse_against_fd(fs, sc, 4);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(2.0 * 4 / 64, got, 0.1 * 2.0 * 4 / 64);
    }

    void doppler_error_is_closed_form()
    {
        // Doppler ν: the FD model's NMSE is 2 - 2|S(ε)| cos ψ, ψ = 2πν(CP + (M-1)/2)/B.
        frame_settings fs;
        fs.carrier_hz = 300e9;
        fs.symbol_interval_s = 80 / fs.bandwidth_hz; // a contiguous OFDM stream
        const double v = 10.0, nu = fs.doppler_from_velocity(v), eps = nu / fs.subcarrier_spacing_hz();
        auto sc = scene::fixed({ target(target_class::car, 20.0, v) }, std::nullopt, 0, fading_kind::none);
        const int m = fs.n_subcarriers;
        const double s_eps = std::sin(M_PI * eps) / (m * std::sin(M_PI * eps / m));
        const double psi = 2 * M_PI * nu * (fs.cp_len + (m - 1) / 2.0) / fs.bandwidth_hz;
        const double expected = 2 - 2 * s_eps * std::cos(psi);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(expected, nmse_against_fd(fs, sc, 2), 0.1 * expected);
    }

    void kept_path_equals_refilled_path()
    {
        // A path that is the same in the next frame keeps its tables and its delayed
        // samples of the previous symbol; they must be exactly those set_paths would
        // rebuild. Channel b is made to rebuild them (a different gain in between).
        frame_settings fs;
        const int n = fs.n_symbols, s = fs.n_subcarriers + fs.cp_len;
        std::vector<channel_path> paths(3);
        for (int l = 0; l < 3; ++l) {
            paths[l].delay_s = (3.0 + 17.37 * l) / fs.bandwidth_hz; // past the prefix for l = 2
            paths[l].doppler_hz = 1500.0 * (l + 1);
            paths[l].gain = { 0.6 - 0.1 * l, 0.8 };
        }
        std::mt19937 g(3);
        std::normal_distribution<float> nd;
        std::vector<gr_complex> in(size_t(2) * n * s), ya(in.size()), yb(in.size());
        for (auto& v : in)
            v = { nd(g), nd(g) };
        td_channel a(fs), b(fs);
        for (int f = 0; f < 2; ++f) {
            a.set_paths(paths, uint64_t(f) * n);
            if (f == 1) {
                auto other = paths;
                other[0].gain *= 2.0;
                other[2].delay_s += 0.25 / fs.bandwidth_hz;
                b.set_paths(other, uint64_t(f) * n);
            }
            b.set_paths(paths, uint64_t(f) * n);
            for (int k = 0; k < n; ++k) {
                const size_t at = (size_t(f) * n + k) * s;
                a.apply_symbol(k, in.data() + at, ya.data() + at);
                b.apply_symbol(k, in.data() + at, yb.data() + at);
            }
        }
        for (size_t i = 0; i < ya.size(); ++i) {
            CPPUNIT_ASSERT_EQUAL(ya[i].real(), yb[i].real());
            CPPUNIT_ASSERT_EQUAL(ya[i].imag(), yb[i].imag());
        }
        CPPUNIT_ASSERT(std::norm(ya[size_t(n) * s + 1]) > 0.0f);
    }

    void micro_doppler_phase_per_sample()
    {
        // One path D whole samples late on a constant input: out[k] is the path's phasor
        // itself, to be compared per sample with exp(j2π ν t) exp(jβ sin(ω t + φ)) in double
        // (t reduced modulo a cycle as the model states). Chunks of 38 samples (the defaults'
        // drone-like path) and of 6 with a last chunk of 2 (a fast rotor: 13 chunks per
        // symbol), at a symbol index past 10^9. Sample i of symbol k is at t = k·T + i/B, but
        // for i < D it ends the echo of symbol k − 1 and keeps that symbol's slow time,
        // t = (k − 1)·T + (S + i)/B (D inside the prefix, 5, and past it, 23; with k·T + i/B
        // there it would be wrong by 2πν(T − S/B), over 1.5 rad here). Bound: the secant's
        // 1e-7 rad plus the float rotator's rounding over a chunk.
        frame_settings fs;
        const int n = fs.n_symbols, s = fs.n_subcarriers + fs.cp_len;
        const double beta_per_m = 4.0 * M_PI / fs.wavelength_m(), tt = fs.symbol_interval_s, b = fs.bandwidth_hz;
        struct md_case {
            double doppler, rate, amplitude, phase;
            int delay;
        };
        for (const md_case c : { md_case{ 240.0, 100.0, 0.01, 0.3, 0 },
                                 md_case{ -310.0, 400.0, 0.02, 2.0, 0 },
                                 md_case{ 240.0, 100.0, 0.01, 0.3, 23 },
                                 md_case{ -310.0, 400.0, 0.02, 2.0, 5 },
                                 md_case{ 240.0, 0.0, 0.0, 0.0, 5 },
                                 md_case{ -310.0, 0.0, 0.0, 0.0, 23 } }) {
            channel_path p;
            p.delay_s = c.delay / b;
            p.doppler_hz = c.doppler;
            p.md_rate_hz = c.rate;
            p.md_amplitude_m = c.amplitude;
            p.md_phase_rad = c.phase;
            p.gain = { 0.8, -0.6 };
            const int d = static_cast<int>(std::floor(p.delay_s * b)); // D as the model rounds it
            td_channel td(fs);
            const uint64_t first = uint64_t(40000000) * n; // slow time past 10^9 symbols
            td.set_paths({ p }, first);
            std::vector<gr_complex> x(s, gr_complex(1.0f, 0.0f)), y(s);
            double worst = 0.0, worst_tail = 0.0;
            for (int k = 0; k < n; ++k) {
                td.apply_symbol(k, x.data(), y.data());
                // symbol 0 reads the silence before up to sample D (sample 0 at D = 0)
                for (int i = (k == 0 ? std::max(d, 1) : 0); i < s; ++i) {
                    const bool tail = i < d;
                    const double sd = static_cast<double>(first + k) - (tail ? 1.0 : 0.0);
                    const double in = (i + (tail ? s : 0)) / b; // s after symbol sd's start
                    const double dop = c.doppler * tt * sd, md = c.rate * tt * sd;
                    const double arg = 2 * M_PI * ((dop - std::floor(dop)) + c.doppler * in) +
                                       beta_per_m * c.amplitude *
                                           std::sin(2 * M_PI * ((md - std::floor(md)) + c.rate * in) + c.phase);
                    const double err = std::abs(std::complex<double>(y[i]) - p.gain * std::polar(1.0, arg));
                    worst = std::max(worst, err);
                    if (tail)
                        worst_tail = std::max(worst_tail, err);
                }
            }
            CPPUNIT_ASSERT_LESS(2e-6, worst);
            CPPUNIT_ASSERT(worst > 0.0);
            CPPUNIT_ASSERT(d == 0 || worst_tail > 0.0); // the tail samples were compared
        }
    }

    void bad_settings_and_delays()
    {
        frame_settings fs;
        fs.symbol_interval_s = 1e-6; // shorter than 80 samples at 30 MHz
        qa::assert_error([&] { td_channel td(fs); }, "symbol_interval_s", "shorter than one symbol");
        td_channel td(frame_settings{});
        channel_path p;
        p.delay_s = 64 / 30e6; // = 1/Δf: outside [0, 1/Δf)
        qa::assert_error([&] { td.set_paths({ p }, 0); }, "path 0", "outside");
        p.delay_s = std::nan("");
        qa::assert_error([&] { td.set_paths({ p }, 0); }, "path 0", "delay");
        p.delay_s = 0.0;
        td.set_paths({ p }, 0);
        std::vector<gr_complex> x(80), y(80);
        CPPUNIT_ASSERT_THROW(td.apply_symbol(32, x.data(), y.data()), std::out_of_range); // N = 32
        CPPUNIT_ASSERT_THROW(td.apply_symbol(-1, x.data(), y.data()), std::out_of_range);
    }

    void still_bodies_equal_frequency_domain()
    {
        // Bodies that do not move within a symbol: every separable term (sub-bands and
        // powers of δk) through its own filter must give H·X as the point paths do (< 1e-11).
        // Fractional delays with the body's extent inside the prefix (16 samples = 80 m).
        frame_settings fs;
        walker_motion walker;
        auto still_rotor = quadcopter(0.0);
        auto still_cyclist = bicyclist(0.0);
        const std::vector<target_spec> targets = { body_target(still_rotor, 41.3, 0.0),
                                                   body_target(walker, 57.1, 0.0),
                                                   body_target(car_wheels(), 33.3, 0.0),
                                                   body_target(still_cyclist, 60.7, 0.0) };
        for (const auto& t : targets) {
            const auto got = body_against_fd(fs, t, 2);
            CPPUNIT_ASSERT_LESS(1e-11, got.nmse);
        }
        // More than one expansion term per body (else the filters are not exercised).
        const gr::sems::detail::body_model wheels(scatterer_body{ car_wheels(), 0.0, 0.0 }, fs);
        CPPUNIT_ASSERT(gr::sems::detail::plan_expansion(fs, wheels.extent_m(), wheels.amplitude_sum()).terms() > 4);
    }

    void array_elements_equal_frequency_domain()
    {
        // At array elements (the farthest of a 0.3 m ULA, a cosine element off the y axis) the
        // time-domain emulator gives the frequency-domain model's H·X at that element (< 1e-11):
        // each path's steering phasor and its exact plane-wave delay inside the fractional
        // delay, still bodies' scatterers each from their own direction; the origin's stays
        // what it was.
        frame_settings fs;
        walker_motion walker;
        auto still_rotor = quadcopter(0.0);
        std::vector<target_spec> targets = { body_target(still_rotor, 41.3, 0.0), body_target(walker, 12.1, 0.0),
                                             target(target_class::car, 30.7, 0.0, { { 0.0, 1.0 }, { 21.1, 0.4 } }) };
        for (auto& t : targets)
            t.azimuth_rad = 0.6;
        const array_element edge{ { 0.0, 0.15, 0.0 }, element_pattern::isotropic };
        const array_element tilted{ { 0.02, -0.1, 0.07 }, element_pattern::cosine };
        for (const auto& t : targets)
            for (const auto& e : { edge, tilted }) {
                const auto got = body_against_fd(fs, t, 2, e);
                CPPUNIT_ASSERT_LESS(1e-11, got.nmse);
            }
        const td_channel origin(fs);
        CPPUNIT_ASSERT(origin.element().is_origin());
    }

    void moving_bodies_within_in_symbol_bound()
    {
        // Moving bodies: TD evaluates them per sample, FD once per symbol; their difference
        // stays inside the in-symbol bound of td_channel.h. Slow motion (a 2 rev/s rotor, a
        // walker at 1.4 m/s, wheels at 2 m/s, the pedalling cyclist) keeps it near zero; a
        // 100 rev/s rotor makes it visible (~1e-4), still inside the bound.
        frame_settings fs;
        walker_motion walker;
        const std::vector<target_spec> slow = { body_target(quadcopter(2.0), 41.3, 0.0),
                                                body_target(walker, 57.1, 1.4),
                                                body_target(car_wheels(), 33.3, 2.0),
                                                body_target(bicyclist(1.0), 60.7, 4.7) };
        for (const auto& t : slow) {
            const auto got = body_against_fd(fs, t, 2);
            CPPUNIT_ASSERT_LESS(1e-11 + got.bound, got.nmse);
            CPPUNIT_ASSERT_LESS(1e-6, got.nmse);
        }
        const auto fast = body_against_fd(fs, body_target(quadcopter(100.0), 41.3, 0.0), 2);
        CPPUNIT_ASSERT_LESS(fast.bound, fast.nmse);
        CPPUNIT_ASSERT(fast.nmse > 1e-6); // the motion within a symbol is there
    }

    void body_return_per_sample()
    {
        // One body path at delay 0 on a single tone m: out[k] = α·h_m(t_k)·(the tone), with
        // h_m(t) = Σ_s a_s e^{-jκ_m r_s(t)} (a line: a·sinc(κ_m e/2)·e^{-jκ_m(r0 + e/2)})
        // evaluated directly at every sample's time t_k = s·T + k/B: a fast-vibrating point,
        // a fast quadcopter, wheels and a walker at their speeds. Bound: the
        // interpolation's 1e-6 plus the float rounding of the expansion's terms.
        frame_settings fs;
        const int n = 4, m = fs.n_subcarriers, s = m + fs.cp_len, cp = fs.cp_len;
        walker_motion walker;
        scatterers_motion vibrating; // one point at 94 m/s: the bound is nearly reached
        vibrating.scatterers.push_back({ 1.0, { { 0.05, 300.0, 0.4 } } });
        const std::vector<scatterer_body> bodies = { { vibrating, 0.0, 0.0 },
                                                     { quadcopter(110.0), 3.0, 0.0 },
                                                     { car_wheels(), 15.0, 0.3 },
                                                     { walker, 1.8, 0.0 } };
        for (const auto& body : bodies) {
            const gr::sems::detail::body_model bm(body, fs);
            // Float rounding of the terms: each is at most Σ|a|·x^p/p! (x = δk_max·extent), their
            // sum at most Σ|a|·e^x, rounded to ~1e-7 (a car's wheels over 2.5 m: ~6e-6).
            const auto plan = gr::sems::detail::plan_expansion(fs, bm.extent_m(), bm.amplitude_sum());
            const double x_max = gr::sems::detail::band_scale(fs, plan) * bm.extent_m();
            const double rounding = 2e-7 * bm.amplitude_sum() * std::exp(x_max);
            for (int tone : { 0, 23, m - 1 }) {
                frame_realization r;
                r.bodies = { body };
                channel_path p;
                p.body = 0;
                p.gain = { 0.6, 0.8 };
                r.paths = { p };
                td_channel td(fs);
                const uint64_t first = uint64_t(3000017) * fs.n_symbols;
                td.set_frame(r, first);
                std::vector<gr_complex> x(s), y(s);
                for (int k = 0; k < s; ++k)
                    x[k] = std::polar(1.0f, float(2 * M_PI * tone * ((k - cp + m) % m) / m));
                const double kappa =
                    4 * M_PI * (fs.carrier_hz + tone * fs.subcarrier_spacing_hz()) / speed_of_light_mps;
                gr::sems::detail::body_snapshot snap;
                double worst = 0.0;
                for (int sym = 0; sym < n; ++sym) {
                    td.apply_symbol(sym, x.data(), y.data());
                    for (int k = 0; k < s; ++k) {
                        bm.snapshot(double(first + sym) * fs.symbol_interval_s + k / fs.bandwidth_hz, snap);
                        std::complex<double> h(0.0, 0.0);
                        for (size_t i = 0; i < snap.point_r.size(); ++i)
                            h += snap.point_a[i] * std::polar(1.0, -kappa * snap.point_r[i]);
                        for (size_t i = 0; i < snap.line_e.size(); ++i) {
                            const double z = 0.5 * kappa * snap.line_e[i];
                            const double sinc = std::fabs(z) < 1e-9 ? 1.0 : std::sin(z) / z;
                            h += snap.line_a[i] * sinc * std::polar(1.0, -z - kappa * snap.line_r0[i]);
                        }
                        const std::complex<double> want = p.gain * h * std::complex<double>(x[k]);
                        worst = std::max(worst, std::abs(std::complex<double>(y[k]) - want));
                    }
                }
                CPPUNIT_ASSERT_LESS(1e-6 + rounding, worst);
            }
        }
    }

    void bodies_at_extremes_are_finite()
    {
        // 8 rotors of 16 blades at 200 rev/s and 256 point scatterers of 16 harmonics: every
        // output sample finite, and the target not lost.
        frame_settings fs;
        rotor_motion rotors;
        rotors.rotors = 8;
        rotors.blades = 16;
        rotors.blade_length_m = 0.3;
        rotors.rotation_hz = { 200.0 };
        scatterers_motion many;
        for (int i = 0; i < 256; ++i) {
            point_scatterer p;
            p.power = 1.0 + i % 7;
            for (int h = 0; h < 16; ++h)
                p.harmonics.push_back({ 0.02 * (1 + h % 3), 0.5 + 37.0 * h + i, 0.1 * i + h });
            many.scatterers.push_back(p);
        }
        std::mt19937 g(9);
        std::normal_distribution<float> nd;
        for (const micro_motion& motion : { micro_motion(rotors), micro_motion(many) }) {
            auto sc = scene::fixed({ body_target(motion, 60.0, 5.0) }, std::nullopt, 0, fading_kind::rayleigh);
            channel_model model(fs, sc, 3);
            td_channel td(fs);
            const int s = td.symbol_len();
            std::vector<gr_complex> x(s), y(s);
            double power = 0.0, in_power = 0.0;
            for (int f = 0; f < 2; ++f) {
                td.set_frame(model.draw(f), uint64_t(f) * fs.n_symbols);
                for (int k = 0; k < fs.n_symbols; ++k) {
                    for (auto& v : x)
                        v = { nd(g), nd(g) };
                    td.apply_symbol(k, x.data(), y.data());
                    for (int i = 0; i < s; ++i) {
                        CPPUNIT_ASSERT(std::isfinite(y[i].real()) && std::isfinite(y[i].imag()));
                        power += std::norm(y[i]);
                        in_power += std::norm(x[i]);
                    }
                }
            }
            CPPUNIT_ASSERT(power > 1e-3 * in_power && power < 1e3 * in_power);
        }
    }

    void body_paths_need_set_frame()
    {
        frame_settings fs;
        td_channel td(fs);
        frame_realization r;
        r.bodies = { scatterer_body{ quadcopter(100.0), 0.0, 0.0 } };
        channel_path p;
        p.delay_s = 3 / fs.bandwidth_hz;
        r.paths = { channel_path{}, p };
        r.paths[1].body = 0;
        qa::assert_error([&] { td.set_paths(r.paths, 0); }, "path 1 refers to scatterer body 0", "set_frame");
        r.paths[1].body = 1;
        qa::assert_error([&] { td.set_frame(r, 0); }, "path 1 refers to scatterer body 1", "the frame has 1");
        r.paths[1].body = 0;
        td.set_frame(r, 0); // the same frame through set_frame
        std::vector<gr_complex> x(td.symbol_len(), gr_complex(1.0f, 0.0f)), y(x.size());
        td.apply_symbol(0, x.data(), y.data());
        CPPUNIT_ASSERT(std::norm(y[td.symbol_len() - 1]) > 0.0f);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_td_channel);
