// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 8's spectrogram CNN: its image against closed forms (a Doppler tone and
 * a delay put their peaks where f_D·N·T and τ·M·Δf say, normalised to the frame's power, zero
 * past the track's end), and the network: it learns two separable classes from a seeded toy
 * set, answers -1 for a track shorter than the time asked, and refuses bad shapes by name. */
#include "spectrogram_cnn.h"
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <stdexcept>

using gr::sems::frame_settings;
using sems_eval::track_spectrogram;

namespace {

// len frames of a point target: Doppler bin q0 (f_D = q0 / (N T)) and delay bin d0
// (τ = d0 / (M Δf)), with a frame gain `gain[f]`.
std::vector<gr_complex> point_target(const frame_settings& fs, int frames, int q0, int d0, const std::vector<float>& gain)
{
    const int n = fs.n_symbols, m = fs.n_subcarriers;
    std::vector<gr_complex> g(size_t(frames) * n * m);
    for (int f = 0; f < frames; ++f)
        for (int s = 0; s < n; ++s)
            for (int k = 0; k < m; ++k)
                g[(size_t(f) * n + s) * m + k] =
                    gain[f] * std::polar(1.0f, float(2.0 * M_PI * (double(q0) * s / n - double(d0) * k / m)));
    return g;
}

int argmax_rows(const std::vector<float>& img, int frames, int f, int row0, int rows)
{
    int best = row0;
    for (int r = row0; r < row0 + rows; ++r)
        if (img[size_t(r) * frames + f] > img[size_t(best) * frames + f])
            best = r;
    return best - row0;
}

} // namespace

class qa_spectrogram_cnn : public CppUnit::TestCase
{
    CPPUNIT_TEST_SUITE(qa_spectrogram_cnn);
    CPPUNIT_TEST(test_image_against_closed_form);
    CPPUNIT_TEST(test_network_learns_and_answers_by_length);
    CPPUNIT_TEST_SUITE_END();

    void test_image_against_closed_form()
    {
        const frame_settings fs; // N = 32 symbols, M = 64 subcarriers
        const int n = fs.n_symbols, m = fs.n_subcarriers, frames = 6, len = 4;
        for (const auto& [q0, d0] : { std::pair<int, int>{ 5, 10 }, { -7, 0 }, { 0, 63 } }) {
            // Gains of very different size: the image is relative to each frame's power.
            const auto g = point_target(fs, frames, q0, d0, { 1.0f, 30.0f, 0.01f, 2.0f, 1.0f, 1.0f });
            const auto img = track_spectrogram(fs, g.data(), frames, len);
            CPPUNIT_ASSERT_EQUAL(size_t(n + m) * frames, img.size());
            for (int f = 0; f < len; ++f) {
                CPPUNIT_ASSERT_EQUAL(n / 2 + q0, argmax_rows(img, frames, f, 0, n)); // bin q0, centred
                CPPUNIT_ASSERT_EQUAL(d0, argmax_rows(img, frames, f, n, m));
                // One range bin holds all the power (0 dB -> 1); the Hann window's main lobe
                // spreads the tone over three Doppler bins: 1/4 : 1/2 : 1/4 in amplitude, so
                // the peak holds (1/2)^2 / (2 (1/4)^2 + (1/2)^2) = 2/3 of the power.
                CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, img[size_t(n + d0) * frames + f], 1e-4);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0 + 10.0 * std::log10(2.0 / 3.0) / 60.0,
                                             img[size_t(n / 2 + q0) * frames + f], 0.02);
                for (int r = 0; r < n + m; ++r) {
                    CPPUNIT_ASSERT(img[size_t(r) * frames + f] >= 0.0f);
                    CPPUNIT_ASSERT(img[size_t(r) * frames + f] <= 1.0f + 1e-6f);
                }
                // The same image whatever the frame's gain.
                CPPUNIT_ASSERT_DOUBLES_EQUAL(img[size_t(n / 2 + q0) * frames + 0],
                                             img[size_t(n / 2 + q0) * frames + f], 1e-5);
            }
            for (int f = len; f < frames; ++f)
                for (int r = 0; r < n + m; ++r)
                    CPPUNIT_ASSERT_EQUAL(0.0f, img[size_t(r) * frames + f]);
        }
    }

    void test_network_learns_and_answers_by_length()
    {
        // Two classes: a target receding (Doppler bin -6) or approaching (+6), at any delay,
        // tracks of 1..4 frames.
        const frame_settings fs;
        const int rows = fs.n_symbols + fs.n_subcarriers, frames = 4, count = 160;
        std::vector<float> images;
        std::vector<int> length, label;
        for (int i = 0; i < count; ++i) {
            const int c = i % 2, len = 1 + (i / 2) % frames;
            const auto g = point_target(fs, frames, c ? 6 : -6, (7 * i) % fs.n_subcarriers, { 1, 1, 1, 1 });
            const auto img = track_spectrogram(fs, g.data(), frames, len);
            images.insert(images.end(), img.begin(), img.end());
            length.push_back(len);
            label.push_back(c);
        }
        sems_eval::spectrogram_cnn cnn(rows, frames, 2, 7, 1);
        std::ostringstream log;
        cnn.train(images, length, label, 6, log);
        CPPUNIT_ASSERT(log.str().find("validation accuracy") != std::string::npos);
        const auto pred = cnn.predict(images, length, 3);
        int right = 0, judged = 0;
        for (int i = 0; i < count; ++i) {
            if (length[i] < 3) {
                CPPUNIT_ASSERT_EQUAL(-1, pred[i]); // too short to answer after 3 frames
                continue;
            }
            ++judged;
            right += pred[i] == label[i];
        }
        CPPUNIT_ASSERT_EQUAL(count / 2, judged);
        CPPUNIT_ASSERT_MESSAGE(std::to_string(right) + " of " + std::to_string(judged), right >= judged * 95 / 100);

        for (const auto& [r, k, c] : { std::tuple<int, int, int>{ 6, 4, 2 }, { 96, 0, 2 }, { 96, 4, 1 } }) {
            try {
                sems_eval::spectrogram_cnn bad(r, k, c, 1, 1);
                CPPUNIT_FAIL("a bad shape was accepted");
            } catch (const std::invalid_argument& e) {
                CPPUNIT_ASSERT(std::string(e.what()).find("spectrogram CNN") != std::string::npos);
            }
        }
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_spectrogram_cnn);
