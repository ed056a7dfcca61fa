// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: td_channel (the sample-level synthesis) against the frequency-domain model
 * and its own bookkeeping: OFDM through it equals H·X when every delay is inside the
 * prefix; the micro-Doppler phase is the model's; bad settings and delays are refused. */
#include "qa/ofdm_modem.h"
#include "qa/qa_assert.h"
#include <gnuradio/fft/fft.h>
#include <gnuradio/sems/core/channel_model.h>
#include <gnuradio/sems/core/td_channel.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <random>
#include <vector>

using namespace gr::sems;

namespace {

using ofdm = gr::sems::qa::ofdm_modem; // unitary CP-OFDM, the maths of ofdm_tx/ofdm_rx

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
            o.tx(x.data(), t.data());
            td.apply_symbol(k, t.data(), y.data());
            o.rx(y.data(), rx.data());
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
        // One path at delay 0 on a constant input: out[k] is the path's phasor itself, to be
        // compared per sample with exp(j2π ν t) exp(jβ sin(ω t + φ)) in double (t reduced
        // modulo a cycle as the model states). Chunks of 38 samples (the defaults' drone-like
        // path) and of 6 with a last chunk of 2 (a fast rotor: 13 chunks per symbol), at a
        // symbol index past 10^9. Bound: the secant's 1e-7 rad plus the float rotator's
        // rounding over a chunk.
        frame_settings fs;
        const int n = fs.n_symbols, s = fs.n_subcarriers + fs.cp_len;
        const double beta_per_m = 4.0 * M_PI / fs.wavelength_m(), tt = fs.symbol_interval_s, b = fs.bandwidth_hz;
        struct md_case {
            double doppler, rate, amplitude, phase;
        };
        for (const md_case c : { md_case{ 240.0, 100.0, 0.01, 0.3 }, md_case{ -310.0, 400.0, 0.02, 2.0 } }) {
            channel_path p;
            p.doppler_hz = c.doppler;
            p.md_rate_hz = c.rate;
            p.md_amplitude_m = c.amplitude;
            p.md_phase_rad = c.phase;
            p.gain = { 0.8, -0.6 };
            td_channel td(fs);
            const uint64_t first = uint64_t(40000000) * n; // slow time past 10^9 symbols
            td.set_paths({ p }, first);
            std::vector<gr_complex> x(s, gr_complex(1.0f, 0.0f)), y(s);
            double worst = 0.0;
            for (int k = 0; k < n; ++k) {
                td.apply_symbol(k, x.data(), y.data());
                const double sd = static_cast<double>(first + k);
                for (int i = 1; i < s; ++i) { // sample 0 of the first symbol reads the silence before
                    const double dop = c.doppler * tt * sd, md = c.rate * tt * sd;
                    const double arg = 2 * M_PI * ((dop - std::floor(dop)) + c.doppler * i / b) +
                                       beta_per_m * c.amplitude *
                                           std::sin(2 * M_PI * ((md - std::floor(md)) + c.rate * i / b) + c.phase);
                    const std::complex<double> want = p.gain * std::polar(1.0, arg);
                    worst = std::max(worst, std::abs(std::complex<double>(y[i]) - want));
                }
            }
            CPPUNIT_ASSERT_LESS(2e-6, worst);
            CPPUNIT_ASSERT(worst > 0.0);
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
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_td_channel);
