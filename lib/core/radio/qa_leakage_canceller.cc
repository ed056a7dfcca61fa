// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: leakage_canceller against its model: a noiseless leakage of L taps with its IQ
 * image and DC is cancelled by >= 60 dB; an echo delayed past the taps passes within 0.1 dB;
 * with noise the fit's error is the least-squares closed form σ²·K/W (and its steady state
 * with forgetting); what is not modelled (the image with widely_linear off) is left; bad
 * settings are refused by name; a converter clipping the leakage costs the echo tens of dB
 * unless the canceller is given its full scale, which bounds each clipped rail's error by the
 * echo's own value there. */
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/radio/leakage_canceller.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {

struct stream {
    std::mt19937 g;
    std::normal_distribution<float> n{ 0.0f, float(M_SQRT1_2) };
    explicit stream(unsigned seed) : g(seed) {}
    gr_complex cn(float sigma = 1.0f) { return gr_complex(n(g), n(g)) * sigma; } // CN(0, σ²)
};

// The leakage of the file comment: taps h (40 dB over a unit echo), image g 25 dB below it, DC.
struct leakage {
    std::vector<gr_complex> h, g;
    gr_complex c{ 3.0f, -2.0f };
    explicit leakage(int taps, stream& s)
    {
        for (int d = 0; d < taps; ++d) {
            h.push_back(s.cn(100.0f / float(d + 1)));
            g.push_back(h.back() * gr_complex(0.03f, 0.04f)); // |g/h| = 0.05: −26 dB
        }
    }
    gr_complex at(const std::vector<gr_complex>& tx, size_t n) const
    {
        gr_complex y = c;
        for (size_t d = 0; d < h.size() && d <= n; ++d)
            y += h[d] * tx[n - d] + g[d] * std::conj(tx[n - d]);
        return y;
    }
};

double power(const std::vector<gr_complex>& x, size_t from, size_t to)
{
    double p = 0.0;
    for (size_t i = from; i < to; ++i)
        p += std::norm(x[i]);
    return p / double(to - from);
}

} // namespace

class qa_leakage_canceller : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_leakage_canceller);
    CPPUNIT_TEST(test_noiseless_leakage_image_dc_cancelled_60_db);
    CPPUNIT_TEST(test_echo_past_the_taps_passes);
    CPPUNIT_TEST(test_residual_is_the_least_squares_closed_form);
    CPPUNIT_TEST(test_unmodelled_image_is_left);
    CPPUNIT_TEST(test_clipped_leakage_bounded_by_the_echo);
    CPPUNIT_TEST(test_clip_level_above_the_stream_changes_nothing);
    CPPUNIT_TEST(test_held_steady_state_is_a_long_stream_of_that_window);
    CPPUNIT_TEST(test_bad_settings_refused_by_name);
    CPPUNIT_TEST_SUITE_END();

    // rx = leakage(tx) + extra[n] through the canceller, window by window; returns out.
    static std::vector<gr_complex> run(leakage_fit& lc,
                                       const leakage& lk,
                                       const std::vector<gr_complex>& tx,
                                       const std::vector<gr_complex>& extra)
    {
        const size_t w = size_t(lc.window());
        std::vector<gr_complex> rx(tx.size()), out(tx.size());
        for (size_t n = 0; n < tx.size(); ++n)
            rx[n] = lk.at(tx, n) + extra[n];
        for (size_t s = 0; s + w <= tx.size(); s += w)
            lc.process(rx.data() + s, tx.data() + s, out.data() + s);
        return out;
    }

    void test_noiseless_leakage_image_dc_cancelled_60_db()
    {
        for (double lambda : { 0.0, 0.9 }) {
            stream s(1);
            leakage_canceller_settings set;
            set.taps = 5;
            set.window = 1000;
            set.forgetting = lambda;
            leakage_fit lc(set);
            const leakage lk(5, s);
            std::vector<gr_complex> tx(10000), none(tx.size());
            for (auto& v : tx)
                v = s.cn();
            const auto out = run(lc, lk, tx, none);
            std::vector<gr_complex> rx(tx.size());
            for (size_t n = 0; n < tx.size(); ++n)
                rx[n] = lk.at(tx, n);
            const double db = 10.0 * std::log10(power(out, 0, out.size()) / power(rx, 0, rx.size()));
            CPPUNIT_ASSERT_MESSAGE("cancelled by " + std::to_string(-db) + " dB only", db < -60.0);
            for (size_t d = 0; d < 5; ++d) {
                CPPUNIT_ASSERT(std::abs(lc.taps()[d] - lk.h[d]) < 1e-3f * std::abs(lk.h[d]));
                CPPUNIT_ASSERT(std::abs(lc.image_taps()[d] - lk.g[d]) < 1e-3f * std::abs(lk.h[d]));
            }
            CPPUNIT_ASSERT(std::abs(lc.dc() - lk.c) < 1e-3f);
            CPPUNIT_ASSERT_EQUAL(10ULL, lc.windows());
        }
    }

    void test_echo_past_the_taps_passes()
    {
        stream s(2);
        leakage_canceller_settings set; // L = 4, W = 2560, λ = 0.9
        leakage_fit lc(set);
        const leakage lk(4, s);
        const size_t delay = 20, w = size_t(set.window);
        std::vector<gr_complex> tx(20 * w), echo(tx.size());
        for (auto& v : tx)
            v = s.cn();
        const gr_complex a(0.6f, -0.8f); // unit echo, 40 dB under the leakage
        for (size_t n = delay; n < tx.size(); ++n)
            echo[n] = a * tx[n - delay] * std::polar(1.0f, 0.001f * float(n)); // and Doppler
        const auto out = run(lc, lk, tx, echo);
        std::vector<gr_complex> err(tx.size());
        for (size_t n = 0; n < tx.size(); ++n)
            err[n] = out[n] - echo[n];
        const double db = 10.0 * std::log10(power(out, w, out.size()) / power(echo, w, echo.size()));
        CPPUNIT_ASSERT_MESSAGE("the echo's power changed by " + std::to_string(db) + " dB", std::abs(db) < 0.1);
        // and it is the echo, sample by sample (what is left of the leakage is 30 dB below)
        CPPUNIT_ASSERT(power(err, w, err.size()) < 1e-3 * power(echo, w, echo.size()));
    }

    void test_held_steady_state_is_a_long_stream_of_that_window()
    {
        // One window then hold_as_steady_state() is the same fit as that window repeated for
        // ever (Σ λ^k): the next window comes out the same (float rounding of 200 repeats).
        stream s(5);
        leakage_canceller_settings set;
        set.window = 400;
        const leakage lk(set.taps, s);
        const size_t w = size_t(set.window);
        std::vector<gr_complex> tx(w), rx(w), tx2(w), rx2(w);
        // Silent first and last taps − 1 samples: whatever window came before, the leakage
        // reaching into this one is the same (none), so a repeated window is the same data.
        const size_t edge = size_t(set.taps) - 1;
        for (size_t n = edge; n + edge < w; ++n) {
            tx[n] = s.cn();
            tx2[n] = s.cn();
        }
        for (size_t n = 0; n < w; ++n) {
            rx[n] = lk.at(tx, n) + s.cn(2.0f);
            rx2[n] = lk.at(tx2, n) + s.cn(2.0f) + s.cn(); // and an echo-like part the fit should not take
        }
        leakage_fit held(set), repeated(set), fresh(set);
        std::vector<gr_complex> scratch(w), a(w), b(w), c(w);
        held.process(rx.data(), tx.data(), scratch.data());
        held.hold_as_steady_state();
        fresh.process(rx.data(), tx.data(), scratch.data());
        for (int k = 0; k < 200; ++k)
            repeated.process(rx.data(), tx.data(), scratch.data());
        held.process(rx2.data(), tx2.data(), a.data());
        repeated.process(rx2.data(), tx2.data(), b.data());
        fresh.process(rx2.data(), tx2.data(), c.data());
        double diff = 0.0, fresh_diff = 0.0;
        for (size_t n = 0; n < w; ++n) {
            diff = std::max(diff, double(std::abs(a[n] - b[n])));
            fresh_diff = std::max(fresh_diff, double(std::abs(c[n] - b[n])));
        }
        CPPUNIT_ASSERT_MESSAGE("held vs repeated: " + std::to_string(diff), diff < 1e-3);
        CPPUNIT_ASSERT_MESSAGE("without holding the fit differs: " + std::to_string(fresh_diff), fresh_diff > 1e-2);
    }

    void test_residual_is_the_least_squares_closed_form()
    {
        // rx = leakage + noise of variance σ²: what the fit leaves of the leakage (out − noise)
        // has power σ²·K/W (λ = 0) and σ²·K·(1 − λ)/((1 + λ)·W) in the steady state.
        for (double lambda : { 0.0, 0.9 }) {
            stream s(3);
            leakage_canceller_settings set;
            set.window = 500;
            set.forgetting = lambda;
            leakage_fit lc(set);
            const leakage lk(set.taps, s);
            const double sigma2 = 4.0;
            const size_t w = size_t(set.window), windows = 600, burn = 50;
            std::vector<gr_complex> tx(windows * w), noise(tx.size());
            for (size_t n = 0; n < tx.size(); ++n) {
                tx[n] = s.cn();
                noise[n] = s.cn(float(std::sqrt(sigma2)));
            }
            const auto out = run(lc, lk, tx, noise);
            std::vector<gr_complex> left(tx.size());
            for (size_t n = 0; n < tx.size(); ++n)
                left[n] = out[n] - noise[n];
            const double k = set.regressors();
            const double expect = sigma2 * k * (1.0 - lambda) / ((1.0 + lambda) * double(w));
            const double got = power(left, burn * w, left.size());
            CPPUNIT_ASSERT_MESSAGE("λ = " + std::to_string(lambda) + ": residual " + std::to_string(got) +
                                       ", closed form " + std::to_string(expect),
                                   std::abs(got / expect - 1.0) < (lambda == 0.0 ? 0.1 : 0.25));
        }
    }

    void test_unmodelled_image_is_left()
    {
        stream s(4);
        leakage_canceller_settings set;
        set.widely_linear = false;
        set.forgetting = 0.0;
        leakage_fit lc(set);
        const leakage lk(set.taps, s);
        std::vector<gr_complex> tx(4 * size_t(set.window)), none(tx.size()), image(tx.size());
        for (auto& v : tx)
            v = s.cn();
        const auto out = run(lc, lk, tx, none);
        for (size_t n = 0; n < tx.size(); ++n)
            for (size_t d = 0; d < lk.g.size() && d <= n; ++d)
                image[n] += lk.g[d] * std::conj(tx[n - d]);
        const double db = 10.0 * std::log10(power(out, 0, out.size()) / power(image, 0, image.size()));
        CPPUNIT_ASSERT_MESSAGE("the image changed by " + std::to_string(db) + " dB", std::abs(db) < 0.2);
        for (const auto& g : lc.image_taps())
            CPPUNIT_ASSERT_EQUAL(gr_complex(0.0f, 0.0f), g);
    }

    // Leakage 40 dB over a unit echo 20 samples behind, each rail clipped at `full_scale`:
    // returns {received, echo, out} with the canceller given `clip_level`.
    struct clipped_run {
        std::vector<gr_complex> rx, echo, out;
    };
    static clipped_run run_clipped(float full_scale, double clip_level)
    {
        stream s(7);
        leakage_canceller_settings set; // L = 4, W = 2560, λ = 0.9
        set.clip_level = clip_level;
        leakage_fit lc(set);
        const leakage lk(4, s);
        const size_t w = size_t(set.window);
        std::vector<gr_complex> tx(20 * w);
        for (auto& v : tx)
            v = s.cn();
        clipped_run r{ std::vector<gr_complex>(tx.size()), std::vector<gr_complex>(tx.size()),
                       std::vector<gr_complex>(tx.size()) };
        auto clip = [full_scale](float v) { return std::max(-full_scale, std::min(full_scale, v)); };
        for (size_t n = 0; n < tx.size(); ++n) {
            r.echo[n] = n >= 20 ? gr_complex(0.6f, -0.8f) * tx[n - 20] : gr_complex(0.0f, 0.0f);
            const gr_complex y = lk.at(tx, n) + r.echo[n];
            r.rx[n] = gr_complex(clip(y.real()), clip(y.imag()));
        }
        for (size_t k = 0; k + w <= tx.size(); k += w)
            lc.process(r.rx.data() + k, tx.data() + k, r.out.data() + k);
        return r;
    }

    void test_clipped_leakage_bounded_by_the_echo()
    {
        // The leakage's rails have rms ~ 100·(1 + 1/4 + 1/9 + 1/16)^½/√2 ≈ 83: full scale
        // at 200 clips about 0.5 % of the rails, where the leakage peaks.
        const float full_scale = 200.0f;
        const auto raw = run_clipped(full_scale, 0.0);
        const auto handled = run_clipped(full_scale, full_scale);
        const size_t w = size_t(leakage_canceller_settings{}.window);
        std::vector<gr_complex> err_raw(raw.rx.size()), err(raw.rx.size());
        size_t clipped = 0;
        for (size_t n = 0; n < raw.rx.size(); ++n) {
            err_raw[n] = raw.out[n] - raw.echo[n];
            err[n] = handled.out[n] - handled.echo[n];
            const float rails[2][3] = { { handled.rx[n].real(), err[n].real(), handled.echo[n].real() },
                                        { handled.rx[n].imag(), err[n].imag(), handled.echo[n].imag() } };
            for (const auto& r : rails)
                if (std::abs(r[0]) >= full_scale && n >= w) {
                    ++clipped; // what a clipped rail keeps of the echo: never more error than the echo itself
                    CPPUNIT_ASSERT_MESSAGE("clipped rail at sample " + std::to_string(n) + ": error " +
                                               std::to_string(r[1]) + " against the echo's " + std::to_string(r[2]),
                                           std::abs(r[1]) <= std::abs(r[2]) + 0.1f);
                }
        }
        CPPUNIT_ASSERT_MESSAGE("only " + std::to_string(clipped) + " clipped rails", clipped > 100);
        const double echo = power(raw.echo, w, raw.echo.size());
        const double db_raw = 10.0 * std::log10(power(err_raw, w, err_raw.size()) / echo);
        const double db = 10.0 * std::log10(power(err, w, err.size()) / echo);
        CPPUNIT_ASSERT_MESSAGE("unhandled clipping left only " + std::to_string(db_raw) + " dB against the echo",
                               db_raw > 0.0);
        CPPUNIT_ASSERT_MESSAGE("with the full scale given, the error is " + std::to_string(db) +
                                   " dB against the echo",
                               db < -20.0);
    }

    void test_clip_level_above_the_stream_changes_nothing()
    {
        const auto plain = run_clipped(1e9f, 0.0);
        const auto given = run_clipped(1e9f, 1e6); // above every sample: nothing is clipped
        CPPUNIT_ASSERT(plain.out == given.out);
    }

    void test_bad_settings_refused_by_name()
    {
        for (double level : { -1.0, std::nan(""), HUGE_VAL }) {
            leakage_canceller_settings set;
            set.clip_level = level;
            assert_error([&] { leakage_fit lc(set); }, "clip_level", "full scale");
        }
        auto make = [](int taps, int window, double lambda) {
            leakage_canceller_settings set;
            set.taps = taps;
            set.window = window;
            set.forgetting = lambda;
            leakage_fit lc(set);
        };
        assert_error([&] { make(0, 2560, 0.9); }, "taps", "got 0");
        assert_error([&] { make(65, 2560, 0.9); }, "taps", "got 65");
        assert_error([&] { make(4, 10, 0.9); }, "window", "got 10");
        assert_error([&] { make(4, 2560, 1.0); }, "forgetting", "[0, 1)");
        assert_error([&] { make(4, 2560, -0.1); }, "forgetting");
        assert_error([&] { make(4, 2560, std::nan("")); }, "forgetting");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_leakage_canceller);
