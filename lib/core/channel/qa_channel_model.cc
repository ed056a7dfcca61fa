// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the channel model against closed forms (docs/design.md §1). */
#include "core/common/math_constants.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <limits>
#include <numeric>
#include <vector>

using namespace gr::sems;

namespace {

const frame_settings fs{}; // the defaults: 32 x 64, B = 30 MHz, f_c = 3 GHz, T = 1 ms

// A fixed single-path scene with deterministic gain (no fading) so phases are testable.
scene one_path(double range_m, double velocity_mps, std::optional<micro_doppler> md = std::nullopt)
{
    target_spec t;
    t.cls = md ? target_class::drone : target_class::car;
    t.range_m = range_m;
    t.velocity_mps = velocity_mps;
    t.md = md;
    return scene::fixed({ t }, std::nullopt, 0, fading_kind::none);
}

// Slow-time series of subcarrier m over `frames` consecutive frames.
std::vector<std::complex<double>> slow_time(channel_model& cm, int frames, int m = 0)
{
    std::vector<gr_complex> h(size_t(frames) * fs.grid_size());
    cm.generate(frames, h.data());
    std::vector<std::complex<double>> out;
    for (int f = 0; f < frames; ++f)
        for (int n = 0; n < fs.n_symbols; ++n)
            out.emplace_back(h[size_t(f) * fs.grid_size() + size_t(n) * fs.n_subcarriers + m]);
    return out;
}

// |DFT| / L at integer bin k (direct evaluation: exact, no FFT library needed).
double dft_mag(const std::vector<std::complex<double>>& x, long k)
{
    const size_t L = x.size();
    std::complex<double> acc = 0.0;
    for (size_t i = 0; i < L; ++i) {
        const double ph = -2.0 * pi * double((k * long(i)) % long(L)) / double(L);
        acc += x[i] * std::complex<double>(std::cos(ph), std::sin(ph));
    }
    return std::abs(acc) / double(L);
}

double wrap(double a) { return std::remainder(a, 2.0 * pi); }

} // namespace

class qa_channel_model : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_channel_model);
    CPPUNIT_TEST(phase_slope_gives_delay);
    CPPUNIT_TEST(slow_time_peak_gives_doppler);
    CPPUNIT_TEST(doppler_at_plus_minus_500_hz);
    CPPUNIT_TEST(micro_doppler_bessel_lines);
    CPPUNIT_TEST(unit_mean_power_over_random_frames);
    CPPUNIT_TEST(noise_variance_matches_snr);
    CPPUNIT_TEST(noiseless_draws_nothing);
    CPPUNIT_TEST(extreme_snr_stays_finite);
    CPPUNIT_TEST(delay_extremes);
    CPPUNIT_TEST(phase_continuous_after_1e7_symbols);
    CPPUNIT_TEST(same_seed_same_frames_at_any_snr);
    CPPUNIT_TEST(multipath_is_sum_of_paths);
    CPPUNIT_TEST(clutter_takes_its_share);
    CPPUNIT_TEST(refuses_out_of_frame_scenes);
    CPPUNIT_TEST_SUITE_END();

public:
    void phase_slope_gives_delay()
    {
        for (double range : { 0.0, 37.5, 123.4, 199.9 }) {
            channel_model cm(fs, one_path(range, 3.0), 1);
            std::vector<gr_complex> h(fs.grid_size());
            cm.generate(1, h.data());
            const double tau = fs.delay_from_range(range);
            for (int n : { 0, 17 }) {
                for (int m = 0; m + 1 < fs.n_subcarriers; ++m) {
                    const auto a = std::complex<double>(h[n * fs.n_subcarriers + m]);
                    const auto b = std::complex<double>(h[n * fs.n_subcarriers + m + 1]);
                    const double slope = std::arg(b * std::conj(a)); // -2π Δf τ (mod 2π)
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, wrap(slope + 2 * pi * fs.subcarrier_spacing_hz() * tau), 1e-5);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, std::abs(a), 1e-6); // unit power, no fading
                }
            }
        }
    }

    void slow_time_peak_gives_doppler()
    {
        // 32 frames = 1024 symbols; bin width 1/(1024 T). Place ν on bin 100.
        const int frames = 32, L = frames * fs.n_symbols;
        const long k = 100;
        const double nu = k / (L * fs.symbol_interval_s);
        channel_model cm(fs, one_path(60.0, nu * fs.wavelength_m() / 2.0), 2);
        auto x = slow_time(cm, frames, 5);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, dft_mag(x, k), 1e-5);
        for (long j : { k - 1, k + 1, k + 7, long(L) - k })
            CPPUNIT_ASSERT(dft_mag(x, j) < 1e-5); // a pure tone: nothing elsewhere
    }

    void doppler_at_plus_minus_500_hz()
    {
        for (double sign : { 1.0, -1.0 }) {
            const double v = sign * fs.max_speed_mps(); // ν = ±1/(2T) = ±500 Hz
            channel_model cm(fs, one_path(10.0, v), 3);
            auto x = slow_time(cm, 4, 0);
            for (size_t i = 1; i < x.size(); ++i) // phase advances by π per symbol
                CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(x[i] + x[i - 1]), 1e-5);
        }
        // Just beyond the unambiguous Doppler is refused, not folded.
        CPPUNIT_ASSERT_THROW(channel_model(fs, one_path(10.0, fs.max_speed_mps() * 1.001), 0), std::invalid_argument);
    }

    void micro_doppler_bessel_lines()
    {
        // exp(jβ sin(ωt + φ)) = Σ_k J_k(β) e^{jkφ} e^{jkωt}: lines at ν + k f_md of |J_k(β)|.
        const int frames = 32, L = frames * fs.n_symbols;
        const double bin = 1.0 / (L * fs.symbol_interval_s);
        const long k_nu = 150, k_md = 100;
        const double beta = 1.2;
        micro_doppler md{ k_md * bin, beta * fs.wavelength_m() / (4 * pi), 0.3 };
        channel_model cm(fs, one_path(80.0, k_nu * bin * fs.wavelength_m() / 2.0, md), 4);
        auto x = slow_time(cm, frames, 9);
        for (int k = -3; k <= 3; ++k) {
            const double expected = std::fabs(std::cyl_bessel_j(std::abs(k), beta));
            const long b = ((k_nu + k * k_md) % L + L) % L;
            CPPUNIT_ASSERT_DOUBLES_EQUAL(expected, dft_mag(x, b), 2e-5);
        }
        CPPUNIT_ASSERT(dft_mag(x, k_nu + 50) < 1e-5); // nothing between the lines
    }

    void unit_mean_power_over_random_frames()
    {
        random_spec spec;
        spec.paths_per_target = 3;
        spec.n_targets = 2;
        clutter_spec clutter;
        clutter.csr_db = 3.0;
        channel_model cm(fs, scene::random(spec, clutter), 5);
        const int frames = 4000;
        std::vector<gr_complex> h(size_t(frames) * fs.grid_size());
        cm.generate(frames, h.data());
        double p = 0.0;
        for (const auto& v : h)
            p += std::norm(std::complex<double>(v));
        p /= double(h.size());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, p, 0.05); // ~3 standard errors
    }

    void noise_variance_matches_snr()
    {
        channel_model cm(fs, one_path(10.0, 1.0), 6);
        const size_t n = 200000;
        for (double snr : { -10.0, 0.0, 10.0, 30.0 }) {
            std::vector<gr_complex> y(n, gr_complex(0, 0));
            cm.add_noise(y.data(), n, snr);
            double p = 0, re = 0;
            for (const auto& v : y) {
                p += std::norm(std::complex<double>(v));
                re += double(v.real()) * v.real();
            }
            const double var = std::pow(10.0, -snr / 10.0);
            // Relative standard error of the power estimate is 1/sqrt(n) ≈ 0.22 %.
            CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, p / n / var, 0.01);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.5, re / p, 0.01); // circular: half in each rail
            CPPUNIT_ASSERT_DOUBLES_EQUAL(snr, 10 * std::log10(1.0 / (p / n)), 0.05);
        }
    }

    void noiseless_draws_nothing()
    {
        channel_model a(fs, one_path(10.0, 1.0), 7), b(fs, one_path(10.0, 1.0), 7);
        std::vector<gr_complex> y(64, gr_complex(1, 2)), ya(16), yb(16);
        a.add_noise(y.data(), y.size(), std::numeric_limits<double>::infinity());
        for (const auto& v : y)
            CPPUNIT_ASSERT(v == gr_complex(1, 2));
        a.add_noise(ya.data(), ya.size(), 0.0); // the +inf call consumed no draws
        b.add_noise(yb.data(), yb.size(), 0.0);
        CPPUNIT_ASSERT(ya == yb);
        CPPUNIT_ASSERT_THROW(channel_model::noise_variance(std::nan("")), std::invalid_argument);
    }

    void extreme_snr_stays_finite()
    {
        channel_model cm(fs, one_path(10.0, 1.0), 8);
        for (double snr : { -50.0, 300.0 }) {
            const size_t n = 20000;
            std::vector<gr_complex> y(n, gr_complex(0, 0));
            cm.add_noise(y.data(), n, snr);
            double p = 0;
            for (const auto& v : y) {
                CPPUNIT_ASSERT(std::isfinite(v.real()) && std::isfinite(v.imag()));
                p += std::norm(std::complex<double>(v));
            }
            CPPUNIT_ASSERT_DOUBLES_EQUAL(snr, -10 * std::log10(p / n), 0.1);
        }
    }

    void delay_extremes()
    {
        // Delay 0: flat across subcarriers. Just below 1/Δf: slope ≈ -2π (one cycle less a hair).
        for (double frac : { 0.0, 1.0 - 1e-6 }) {
            const double range = frac * fs.max_range_m();
            channel_model cm(fs, one_path(range, 0.0), 9);
            std::vector<gr_complex> h(fs.grid_size());
            cm.generate(1, h.data());
            const double tau = fs.delay_from_range(range);
            for (int m = 0; m < fs.n_subcarriers; ++m) {
                const auto v = std::complex<double>(h[m]);
                CPPUNIT_ASSERT(std::isfinite(v.real()) && std::isfinite(v.imag()));
                CPPUNIT_ASSERT_DOUBLES_EQUAL(
                    0.0, wrap(std::arg(v) + 2 * pi * m * fs.subcarrier_spacing_hz() * tau), 1e-5);
            }
        }
        CPPUNIT_ASSERT_THROW(channel_model(fs, one_path(fs.max_range_m(), 0.0), 0), std::invalid_argument);
    }

    void phase_continuous_after_1e7_symbols()
    {
        // The Doppler phase is evaluated from the absolute symbol index, reduced modulo one
        // cycle in double precision: compare with a long-double reference at 10^7 symbols
        // and beyond, and check the step across a frame boundary.
        const double v = 6.1728; // ν = 123.456 Hz: not commensurate with anything
        channel_model cm(fs, one_path(0.0, v), 10);
        const auto r = cm.draw(0);
        const double nu = fs.doppler_from_velocity(v);
        for (uint64_t frame : { uint64_t(312499), uint64_t(312500), uint64_t(31250000000ULL) }) {
            const uint64_t s0 = frame * fs.n_symbols;
            // float storage limits us to ~1e-7 rad; at 10^12 symbols double has ~1e-5 cycles left.
            const double tol = frame > 1000000 ? 1e-3 : 2e-6;
            std::vector<gr_complex> h(fs.grid_size());
            cm.factors(r, s0).fill(h.data());
            for (int n = 0; n < fs.n_symbols; n += 7) {
                const long double cyc = static_cast<long double>(nu) * fs.symbol_interval_s * (s0 + n);
                const double ref = double(2.0L * M_PIl * (cyc - std::floor(cyc)));
                CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, wrap(std::arg(std::complex<double>(h[n * fs.n_subcarriers])) - ref),
                                             tol);
            }
            // Last symbol of the previous frame to the first of this one: exactly one step.
            std::vector<gr_complex> prev(fs.grid_size());
            cm.factors(r, s0 - fs.n_symbols).fill(prev.data());
            const double step = std::arg(std::complex<double>(h[0]) *
                                         std::conj(std::complex<double>(prev[(fs.n_symbols - 1) * fs.n_subcarriers])));
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, wrap(step - 2 * pi * nu * fs.symbol_interval_s), tol);
        }
    }

    void same_seed_same_frames_at_any_snr()
    {
        auto sc = scene::random(random_spec{});
        channel_model a(fs, sc, 42), b(fs, sc, 42), c(fs, sc, 43);
        std::vector<gr_complex> ha(3 * fs.grid_size()), hb(ha.size()), hc(ha.size());
        std::vector<gr_complex> noise(100);
        a.generate(1, ha.data(), 0);
        a.add_noise(noise.data(), noise.size(), 5.0); // noise draws do not disturb frame draws
        a.generate(2, ha.data() + fs.grid_size(), 1);
        b.generate(3, hb.data(), 0);
        c.generate(3, hc.data(), 0);
        CPPUNIT_ASSERT(ha == hb);
        CPPUNIT_ASSERT(ha != hc);
    }

    void multipath_is_sum_of_paths()
    {
        target_spec t;
        t.range_m = 40.0;
        t.velocity_mps = 12.0;
        t.paths = { { 0.0, 1.0 }, { 10.0, 0.5 }, { 25.0, 0.25 } };
        channel_model cm(fs, scene::fixed({ t }, std::nullopt, 0, fading_kind::none), 11);
        const auto r = cm.draw(0);
        CPPUNIT_ASSERT_EQUAL(3, int(r.paths.size()));
        double psum = 0;
        for (const auto& p : r.paths)
            psum += p.mean_power;
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, psum, 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0 / 1.75, r.paths[0].mean_power, 1e-12);
        std::vector<gr_complex> h(fs.grid_size());
        cm.factors(r, 0).fill(h.data());
        const double df = fs.subcarrier_spacing_hz(), nu = fs.doppler_from_velocity(12.0);
        for (int n : { 0, 31 })
            for (int m : { 0, 13, 63 }) {
                std::complex<double> ref = 0;
                for (const auto& p : r.paths)
                    ref += p.gain * std::polar(1.0, -2 * pi * m * df * p.delay_s) *
                           std::polar(1.0, 2 * pi * nu * n * fs.symbol_interval_s);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(std::complex<double>(h[n * 64 + m]) - ref), 1e-5);
            }
        CPPUNIT_ASSERT_DOUBLES_EQUAL(fs.delay_from_range(40.0), r.truth.delay_s, 1e-18);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(8.0, r.truth.delay_index, 1e-9); // 40 m = 8 × 5 m
    }

    void clutter_takes_its_share()
    {
        clutter_spec c;
        c.csr_db = 10.0;
        c.ranges_m = { 20.0, 90.0 };
        target_spec t;
        channel_model cm(fs, scene::fixed({ t }, c, 0, fading_kind::none), 12);
        const auto r = cm.draw(0);
        CPPUNIT_ASSERT_EQUAL(3, int(r.paths.size()));
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0 / 11.0, r.paths[0].mean_power, 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(5.0 / 11.0, r.paths[1].mean_power, 1e-12);
        CPPUNIT_ASSERT_EQUAL(0.0, r.paths[2].doppler_hz); // static
    }

    void refuses_out_of_frame_scenes()
    {
        frame_settings slow = fs;
        slow.symbol_interval_s = 4e-3; // ±125 Hz: cars (up to 400 Hz) cannot be represented
        CPPUNIT_ASSERT_THROW(channel_model(slow, scene::random(random_spec{}), 0), std::invalid_argument);
        frame_settings bad = fs;
        bad.bandwidth_hz = -1;
        CPPUNIT_ASSERT_THROW(channel_model(bad, one_path(1.0, 1.0), 0), std::invalid_argument);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_channel_model);
