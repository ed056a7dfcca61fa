// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: one frame through the radio front end against closed forms: the ideal radio is
 * H plus white noise, the IQ image, the converter's quantization noise, the DC and the
 * leakage's phase-noise floor each as their formulas say, the draws seeded. */
#include <gnuradio/sems/core/radio/front_end_frame.h>
#include <gnuradio/sems/core/radio/leakage_canceller.h>
#include <gnuradio/sems/core/radio/phase_noise.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <limits>
#include <random>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {
using cd = std::complex<double>;

// A random channel of unit mean power per resource element (a Rayleigh grid), seeded.
std::vector<gr_complex> rayleigh(const frame_settings& fs, uint64_t seed)
{
    std::mt19937_64 g(seed);
    std::normal_distribution<float> n(0.0f, std::sqrt(0.5f));
    std::vector<gr_complex> h(static_cast<size_t>(fs.n_symbols) * fs.n_subcarriers);
    for (auto& v : h)
        v = gr_complex(n(g), n(g));
    return h;
}

// Statistics of the estimate over `frames` frames of fresh channels: E|Ĥ − c·H|² with c the
// least-squares gain of Ĥ on H, and c itself.
struct fit {
    double error_power;
    cd gain;
};

fit estimate_error(const frame_settings& fs, const front_end_settings& r, double noise, int frames, double delay = 0.0)
{
    front_end_frame f(fs, r);
    cd hh(0), hy(0);
    std::vector<std::vector<gr_complex>> hs, ys;
    for (int i = 0; i < frames; ++i) {
        hs.push_back(rayleigh(fs, 100 + i));
        ys.emplace_back(hs.back().size());
        f.observe(hs.back().data(), delay, noise, 7 + i, ys.back().data());
        for (size_t k = 0; k < hs.back().size(); ++k) {
            if (fs.is_guard(static_cast<int>(k % fs.n_subcarriers)))
                continue;
            hh += std::norm(hs.back()[k]);
            hy += std::conj(cd(hs.back()[k])) * cd(ys.back()[k]);
        }
    }
    const cd c = hy / hh;
    double e = 0.0;
    size_t count = 0;
    for (int i = 0; i < frames; ++i)
        for (size_t k = 0; k < hs[i].size(); ++k) {
            if (fs.is_guard(static_cast<int>(k % fs.n_subcarriers)))
                continue;
            e += std::norm(cd(ys[i][k]) - c * cd(hs[i][k]));
            ++count;
        }
    return { e / static_cast<double>(count), c };
}

void assert_near_rel(const char* what, double expected, double got, double rel)
{
    CPPUNIT_ASSERT_MESSAGE(std::string(what) + ": expected " + std::to_string(expected) + ", got " +
                               std::to_string(got),
                           std::fabs(got - expected) <= rel * expected);
}
} // namespace

class qa_front_end_frame : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_front_end_frame);
    CPPUNIT_TEST(ideal_radio_is_the_channel);
    CPPUNIT_TEST(ideal_radio_adds_white_noise_of_the_snr);
    CPPUNIT_TEST(iq_imbalance_gives_mu_and_the_image);
    CPPUNIT_TEST(converter_adds_quantization_noise);
    CPPUNIT_TEST(leakage_is_cancelled_to_the_noise);
    CPPUNIT_TEST(shared_phase_noise_on_leakage_is_a_floor);
    CPPUNIT_TEST(separate_oscillators_turn_the_echo);
    CPPUNIT_TEST(seeded);
    CPPUNIT_TEST(bad_input_is_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    void ideal_radio_is_the_channel()
    {
        frame_settings fs;
        fs.guard_subcarriers = { 0, 63 };
        front_end_frame f(fs, front_end_settings{});
        CPPUNIT_ASSERT_DOUBLES_EQUAL(62.0 / 64.0, f.tx_power(), 1e-12);
        CPPUNIT_ASSERT(!f.cancels());
        const auto h = rayleigh(fs, 1);
        std::vector<gr_complex> y(h.size());
        f.observe(h.data(), 3.5, 0.0, 1, y.data());
        double worst = 0.0;
        for (size_t k = 0; k < h.size(); ++k)
            if (!fs.is_guard(static_cast<int>(k % 64)))
                worst = std::max(worst, static_cast<double>(std::abs(y[k] - h[k])));
            else
                CPPUNIT_ASSERT(std::abs(y[k]) < 1e-6); // nothing sent on a guard
        CPPUNIT_ASSERT_MESSAGE("IFFT, FFT and division round trip: " + std::to_string(worst), worst < 1e-5);
    }

    void ideal_radio_adds_white_noise_of_the_snr()
    {
        const double noise = 0.1; // 10 dB
        const auto r = estimate_error(frame_settings{}, front_end_settings{}, noise, 40);
        assert_near_rel("noise per resource element", noise, r.error_power, 0.03);
        CPPUNIT_ASSERT(std::abs(r.gain - 1.0) < 0.01);
    }

    void iq_imbalance_gives_mu_and_the_image()
    {
        // Ĥ_m = μ·H_m + ν·conj(H_{−m}·X_{−m})/X_m + noise: the gain is μ and the image adds
        // |ν|² of the mirrored channel's power (1), independent of H_m (random data).
        front_end_settings r;
        r.iq_gain_db = 1.0;
        r.iq_phase_deg = 5.0;
        const double noise = 0.01;
        const auto e = estimate_error(frame_settings{}, r, noise, 40);
        CPPUNIT_ASSERT_MESSAGE("gain is mu", std::abs(e.gain - r.iq_mu()) < 0.01 * std::abs(r.iq_mu()));
        // Subcarrier 0 and M/2 mirror onto themselves (their image is coherent): 2 of 64.
        const double expected = std::norm(r.iq_nu()) + (std::norm(r.iq_mu()) + std::norm(r.iq_nu())) * noise;
        assert_near_rel("image plus noise", expected, e.error_power, 0.1);
    }

    void converter_adds_quantization_noise()
    {
        // Δ = 2·FS/2^b per rail, uniform rounding error Δ²/12 per rail, 2·Δ²/12 per complex sample
        // and per resource element (unitary FFT). Full scale 8x rms: clipping is negligible.
        front_end_settings r;
        r.adc_enob = 6.0;
        r.adc_full_scale_rms = 8.0;
        const double noise = 1e-4;
        const double fs_rail = r.full_scale(1.0, noise);
        const double step = 2.0 * fs_rail / std::pow(2.0, 6.0);
        const auto e = estimate_error(frame_settings{}, r, noise, 40);
        assert_near_rel("quantization noise", 2.0 * step * step / 12.0 + noise, e.error_power, 0.1);
    }

    void leakage_is_cancelled_to_the_noise()
    {
        // Leakage 40 dB over the echo, clean oscillators: the canceller leaves the noise (its
        // fit error is σ²·K/W per sample, 0.4 % of it).
        front_end_settings r;
        r.leakage_db = 40.0;
        r.dc_offset_db = -20.0;
        const double noise = 0.01;
        front_end_frame f(frame_settings{}, r);
        CPPUNIT_ASSERT(f.cancels());
        const auto e = estimate_error(frame_settings{}, r, noise, 30, 2.0);
        // The fit also takes the echo's chance correlation with its K regressors, K/W of the
        // echo's power (1) in one window; in the steady state the window's own weight in the
        // fit is 1 − λ of the whole.
        const leakage_canceller_settings cs;
        const double fit_share = static_cast<double>(cs.regressors()) / cs.window * (1.0 - cs.forgetting);
        assert_near_rel("cancelled to the noise", noise + fit_share, e.error_power, 0.1);
        // Without a canceller (separate oscillators, bistatic) the leakage stays, 40 dB up.
        r.oscillator = oscillator_kind::separate;
        CPPUNIT_ASSERT(!front_end_frame(frame_settings{}, r).cancels());
        CPPUNIT_ASSERT(estimate_error(frame_settings{}, r, noise, 4, 2.0).error_power > 1e3);
    }

    void shared_phase_noise_on_leakage_is_a_floor()
    {
        // Tap k of the leakage carries e^{j(φ(t−k) − φ(t))}, a Wiener increment of variance
        // k·D/B: what no static fit follows is |h_k|²·(1 − e^{−kD/B}) per sample, white, so per
        // resource element too.
        frame_settings fs;
        front_end_settings r;
        r.leakage_db = 40.0;
        r.phase_noise_dbc_hz = -90.0;
        const double noise = 1e-6;
        const auto taps = r.leakage_response();
        const double var = r.phase_diffusion() / fs.bandwidth_hz;
        double floor = 0.0;
        for (size_t k = 0; k < taps.size(); ++k)
            floor += std::norm(taps[k]) * (1.0 - std::exp(-static_cast<double>(k) * var));
        const auto e = estimate_error(fs, r, noise, 30, 1.0);
        assert_near_rel("phase-noise floor of the leakage", floor + noise, e.error_power, 0.15);
    }

    void separate_oscillators_turn_the_echo()
    {
        // Two oscillators: the echo carries e^{jθ(t)}, θ = φ_tx − φ_rx a Wiener phase of
        // diffusion 2D started a warm-up frame before, so at symbol n (window centre t_n
        // samples after the start) E e^{jθ} = e^{−σ_n²/2} with σ_n² = 2D·t_n/B. The best gain
        // is c = mean_n e^{−σ_n²/2} and the error 1 − c² (θ barely moves within a symbol).
        frame_settings fs;
        front_end_settings r;
        r.oscillator = oscillator_kind::separate;
        r.phase_noise_dbc_hz = -100.0;
        const double noise = 1e-6, d = r.phase_diffusion();
        const int s = fs.n_subcarriers + fs.cp_len, frame = fs.n_symbols * s;
        double c = 0.0;
        for (int n = 0; n < fs.n_symbols; ++n)
            c += std::exp(-d * (frame + n * s + fs.cp_len + fs.n_subcarriers / 2.0) / fs.bandwidth_hz);
        c /= fs.n_symbols;
        const auto e = estimate_error(fs, r, noise, 200);
        assert_near_rel("wandering echo phase", 1.0 - c * c + noise, e.error_power, 0.15);
        CPPUNIT_ASSERT(std::abs(std::abs(e.gain) - c) < 0.01);
    }

    void seeded()
    {
        front_end_settings r;
        r.leakage_db = 30.0;
        r.phase_noise_dbc_hz = -90.0;
        r.adc_enob = 10.0;
        front_end_frame a(frame_settings{}, r), b(frame_settings{}, r);
        const auto h = rayleigh(frame_settings{}, 3);
        std::vector<gr_complex> ya(h.size()), yb(h.size()), yc(h.size());
        a.observe(h.data(), 1.5, 0.01, 42, ya.data());
        b.observe(h.data(), 1.5, 0.01, 42, yb.data());
        a.observe(h.data(), 1.5, 0.01, 43, yc.data());
        CPPUNIT_ASSERT(ya == yb);
        CPPUNIT_ASSERT(ya != yc);
    }

    void bad_input_is_refused()
    {
        front_end_settings r;
        r.sfo_ppm = 5.0;
        assert_error([&] { front_end_frame(frame_settings{}, r); }, "sfo_ppm", "5");
        r.sfo_ppm = 0.0;
        r.adc_enob = -1.0;
        assert_error([&] { front_end_frame(frame_settings{}, r); }, "adc_enob", "-1");
        front_end_frame f(frame_settings{}, front_end_settings{});
        std::vector<gr_complex> h(64 * 32), y(h.size());
        assert_error([&] { f.observe(h.data(), -1.0, 0.0, 1, y.data()); }, "delay_index", "-1");
        assert_error([&] { f.observe(h.data(), 0.0, std::nan(""), 1, y.data()); }, "noise_variance", "nan");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_front_end_frame);
