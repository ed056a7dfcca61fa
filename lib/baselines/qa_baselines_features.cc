// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the Doppler-spectrum features against closed forms for synthetic tones,
 * and the feature SVM (libsvm) on separable data and on bad input. */
#include "baselines/qa_baselines_frames.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/baselines/doppler_features.h>
#include <gnuradio/sems/baselines/feature_svm.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using namespace gr::sems;

namespace {

const double bin_hz = 1.0 / (fs.n_symbols * fs.symbol_interval_s); // 31.25 Hz

// Sum of tones a_i exp(j2π f_i n T) observed at the pilots (any subcarrier phase).
std::vector<gr_complex> tones(const pilot_mask& mask, const std::vector<std::pair<double, double>>& amp_freq)
{
    std::vector<gr_complex> obs;
    for (const auto& p : mask.positions()) {
        std::complex<double> v = 0.0;
        for (const auto& [a, f] : amp_freq)
            v += a * std::polar(1.0, 2.0 * M_PI * f * p.n * fs.symbol_interval_s);
        v *= std::polar(1.0, -2.0 * M_PI * p.m * 0.37); // a delay phase per subcarrier
        obs.emplace_back(v);
    }
    return obs;
}

} // namespace

class qa_baselines_features : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_baselines_features);
    CPPUNIT_TEST(pure_tone_closed_form);
    CPPUNIT_TEST(two_tones_closed_form);
    CPPUNIT_TEST(zero_input_and_bad_input);
    CPPUNIT_TEST(svm_separates_blobs);
    CPPUNIT_TEST(svm_bad_input);
    CPPUNIT_TEST_SUITE_END();

public:
    void pure_tone_closed_form()
    {
        // Doppler pattern: every symbol on two subcarriers; a tone on a DFT bin is one line.
        const auto mask = pilot_mask::doppler(fs.n_symbols, fs.n_subcarriers, 64);
        doppler_features fx(fs, mask);
        CPPUNIT_ASSERT_EQUAL(size_t(32), fx.frequencies_hz().size());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-500.0, fx.frequencies_hz().front(), 1e-9);
        for (int k : { -16, -3, 0, 5, 12 }) {
            const double f0 = k * bin_hz;
            const auto obs = tones(mask, { { 2.0, f0 } });
            const auto s = fx.spectrum(obs.data());
            // S(f0) = Σ_subcarriers |2 · 32|², zero elsewhere.
            CPPUNIT_ASSERT_DOUBLES_EQUAL(2.0 * 64.0 * 64.0, s[k + 16], 1e-2);
            const auto v = fx.extract(obs.data());
            CPPUNIT_ASSERT_DOUBLES_EQUAL(f0, v[0], 1e-6);  // mean
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, v[1], 1e-3);  // std
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, v[2], 1e-12); // skewness (σ = 0)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, v[3], 1e-12); // kurtosis (σ = 0)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(f0, v[4], 1e-9);   // peak
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, v[5], 1e-6);  // entropy
        }
    }

    void two_tones_closed_form()
    {
        // Lines of weight w1 = a1²/(a1²+a2²) at f1 and w2 at f2: the spectrum is a two-point
        // distribution: mean w1 f1 + w2 f2, std √(w1 w2)|f2-f1|, skewness (1-2w2)/√(w1 w2),
        // kurtosis (1 - 3 w1 w2)/(w1 w2), entropy -(w1 ln w1 + w2 ln w2)/ln F.
        const auto mask = pilot_mask::doppler(fs.n_symbols, fs.n_subcarriers, 32);
        doppler_features fx(fs, mask);
        const double f1 = -3 * bin_hz, f2 = 8 * bin_hz, a1 = 1.0, a2 = 0.5;
        const auto v = fx.extract(tones(mask, { { a1, f1 }, { a2, f2 } }).data());
        const double w1 = a1 * a1 / (a1 * a1 + a2 * a2), w2 = 1.0 - w1;
        CPPUNIT_ASSERT_DOUBLES_EQUAL(w1 * f1 + w2 * f2, v[0], 1e-6);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(w1 * w2) * (f2 - f1), v[1], 1e-6);
        CPPUNIT_ASSERT_DOUBLES_EQUAL((1.0 - 2.0 * w2) / std::sqrt(w1 * w2), v[2], 1e-6);
        CPPUNIT_ASSERT_DOUBLES_EQUAL((1.0 - 3.0 * w1 * w2) / (w1 * w2), v[3], 1e-6);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(f1, v[4], 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-(w1 * std::log(w1) + w2 * std::log(w2)) / std::log(32.0), v[5], 1e-6);
        CPPUNIT_ASSERT_EQUAL(size_t(doppler_features::n_features), doppler_features::names().size());
    }

    void zero_input_and_bad_input()
    {
        const auto mask = pilot_mask::doppler(fs.n_symbols, fs.n_subcarriers, 32);
        doppler_features fx(fs, mask);
        std::vector<gr_complex> obs(32, gr_complex(0.0f, 0.0f));
        for (double v : fx.extract(obs.data()))
            CPPUNIT_ASSERT_EQUAL(0.0, v);
        obs[3] = gr_complex(0.0f, std::numeric_limits<float>::quiet_NaN());
        CPPUNIT_ASSERT_THROW(fx.extract(obs.data()), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(fx.extract(nullptr), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(doppler_features(fs, mask, 0), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(doppler_features(fs, pilot_mask::doppler(16, 64, 32)), std::invalid_argument);
    }

    void svm_separates_blobs()
    {
        // Three well-separated Gaussian blobs with very different feature scales:
        // the standardisation makes them equally easy.
        std::mt19937 gen(1);
        std::normal_distribution<double> nd(0.0, 1.0);
        auto sample = [&](int c) {
            return std::vector<double>{ 1000.0 * (8 * c + nd(gen)), 0.001 * nd(gen), (c == 2 ? 5.0 : 0.0) + nd(gen) };
        };
        std::vector<std::vector<double>> x;
        std::vector<int> y;
        for (int i = 0; i < 300; ++i) {
            x.push_back(sample(i % 3));
            y.push_back(i % 3);
        }
        feature_svm svm(x, y);
        CPPUNIT_ASSERT_EQUAL(3, svm.n_features());
        CPPUNIT_ASSERT(svm.n_support_vectors() > 0);
        int correct = 0;
        for (int i = 0; i < 300; ++i)
            correct += svm.predict(sample(i % 3)) == i % 3;
        CPPUNIT_ASSERT(correct >= 290);
    }

    void svm_bad_input()
    {
        const std::vector<std::vector<double>> x{ { 0.0, 1.0 }, { 1.0, 0.0 } };
        CPPUNIT_ASSERT_THROW(feature_svm({}, {}), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(feature_svm(x, { 0 }), std::invalid_argument);            // count mismatch
        CPPUNIT_ASSERT_THROW(feature_svm(x, { 1, 1 }), std::invalid_argument);         // one class
        CPPUNIT_ASSERT_THROW(feature_svm(x, { 0, -1 }), std::invalid_argument);        // negative label
        CPPUNIT_ASSERT_THROW(feature_svm({ { 0.0, 1.0 }, { 1.0 } }, { 0, 1 }), std::invalid_argument); // ragged
        CPPUNIT_ASSERT_THROW(feature_svm({ { 0.0, NAN }, { 1.0, 0.0 } }, { 0, 1 }), std::invalid_argument);
        feature_svm::settings s;
        s.c = 0.0;
        CPPUNIT_ASSERT_THROW(feature_svm(x, { 0, 1 }, s), std::invalid_argument);
        feature_svm ok(x, { 0, 1 });
        CPPUNIT_ASSERT_THROW(ok.predict({ 1.0 }), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(ok.predict({ 1.0, INFINITY }), std::invalid_argument);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_baselines_features);
