// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the classical delay estimators (periodogram, OMP, co-array MUSIC) on
 * channels drawn by THE channel model: exact recovery of a noiseless on-grid path,
 * and clear errors on bad input. */
#include "baselines/qa_baselines_frames.h"
#include <gnuradio/sems/baselines/subcarrier_masks.h>
#include <gnuradio/sems/baselines/music_delay_estimator.h>
#include <gnuradio/sems/baselines/omp_delay_estimator.h>
#include <gnuradio/sems/baselines/periodogram_delay_estimator.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

using namespace gr::sems;

namespace {

// One path, deterministic gain. Delay index idx -> range idx · c/(2B) = idx · 5 m.
scene one_path(double delay_index, double doppler_hz, bool md = false)
{
    target_spec t;
    t.cls = md ? target_class::drone : target_class::car;
    t.range_m = delay_index * fs.range_per_delay_index_m();
    t.velocity_mps = doppler_hz * fs.wavelength_m() / 2.0;
    if (md)
        t.md = micro_doppler{ 100.0, 0.01, 0.3 };
    return scene::fixed({ t }, std::nullopt, 0, fading_kind::none);
}

} // namespace

class qa_baselines_delay : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_baselines_delay);
    CPPUNIT_TEST(periodogram_recovers_on_grid_path);
    CPPUNIT_TEST(per_symbol_periodogram_ignores_micro_doppler);
    CPPUNIT_TEST(omp_recovers_on_grid_path);
    CPPUNIT_TEST(omp_finds_two_paths_and_reports_the_first);
    CPPUNIT_TEST(music_recovers_on_grid_path);
    CPPUNIT_TEST(music_coarray_of_the_patterns);
    CPPUNIT_TEST(uniform_lattice_aliases_in_music);
    CPPUNIT_TEST(bad_input_is_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    void periodogram_recovers_on_grid_path()
    {
        // 23.25 is on the 1/8 grid; 125 Hz is on the 1/(2NT) = 15.625 Hz Doppler grid.
        const auto mask = pilot_mask::random(fs.n_symbols, fs.n_subcarriers, 32, 7);
        const auto obs = qa::noiseless_observations(fs, one_path(23.25, 125.0), mask);
        periodogram_delay_estimator est(fs, mask);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(23.25, est.estimate_index(obs.data()), 1e-6);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(23.25 / fs.bandwidth_hz, est.estimate_delay_s(obs.data()), 1e-15);
        // Off the grid, the parabola brings the estimate within a small fraction of a step.
        const auto off = qa::noiseless_observations(fs, one_path(17.41, 125.0), mask);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(17.41, est.estimate_index(off.data()), 0.02);
    }

    void per_symbol_periodogram_ignores_micro_doppler()
    {
        // Several pilots per symbol: the non-coherent sum needs no Doppler model.
        std::vector<pilot_position> pos; // 4 symbols x 16 subcarriers at spacing 4
        for (int n : { 0, 8, 16, 24 })
            for (int j = 0; j < 16; ++j)
                pos.push_back({ n, 4 * j });
        const pilot_mask mask(fs.n_symbols, fs.n_subcarriers, pos);
        const auto obs = qa::noiseless_observations(fs, one_path(2.5, -300.0, true), mask);
        periodogram_delay_estimator::settings s;
        s.slow_time = slow_time_model::per_symbol;
        s.search.max_index = 16.0; // one alias period of the spacing-4 lattice
        periodogram_delay_estimator est(fs, mask, s);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(2.5, est.estimate_index(obs.data()), 1e-6);
    }

    void omp_recovers_on_grid_path()
    {
        const auto mask = pilot_mask::random(fs.n_symbols, fs.n_subcarriers, 32, 7);
        for (double idx : { 0.0, 11.5, 39.875, 63.875 }) {
            const auto obs = qa::noiseless_observations(fs, one_path(idx, -250.0), mask);
            omp_delay_estimator est(fs, mask);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(idx, est.estimate_index(obs.data()), 1e-12);
            const auto atoms = est.decompose(obs.data());
            CPPUNIT_ASSERT_EQUAL(size_t(1), atoms.size());
            CPPUNIT_ASSERT_DOUBLES_EQUAL(-250.0, atoms[0].doppler_hz, 1e-9);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, std::abs(atoms[0].gain), 1e-5);
        }
    }

    void omp_finds_two_paths_and_reports_the_first()
    {
        target_spec t;
        t.cls = target_class::car;
        t.range_m = 20.0 * fs.range_per_delay_index_m();
        t.velocity_mps = 15.625 * 8 * fs.wavelength_m() / 2.0;
        t.paths = { path_spec{ 0.0, 1.0 }, path_spec{ 6.0 * fs.range_per_delay_index_m(), 2.0 } };
        const auto sc = scene::fixed({ t }, std::nullopt, 0, fading_kind::none);
        const auto mask = pilot_mask::random(fs.n_symbols, fs.n_subcarriers, 48, 3);
        const auto obs = qa::noiseless_observations(fs, sc, mask);
        omp_delay_estimator::settings s;
        s.n_atoms = 2;
        omp_delay_estimator est(fs, mask, s);
        // The stronger echo (26) is found first, the direct path (20) is reported.
        const auto atoms = est.decompose(obs.data());
        CPPUNIT_ASSERT_EQUAL(size_t(2), atoms.size());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(26.0, atoms[0].delay_index, 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(20.0, est.estimate_index(obs.data()), 1e-12);
    }

    void music_recovers_on_grid_path()
    {
        const auto op = nested_subcarrier_mask(fs.n_symbols, fs.n_subcarriers, 32);
        const auto rp = random_subcarrier_mask(fs.n_symbols, fs.n_subcarriers, 32, 1);
        for (const auto* mask : { &op, &rp })
            for (double idx : { 0.5, 23.25, 47.0 }) {
                // MUSIC works within symbols: Doppler and micro-Doppler do not matter.
                const auto obs = qa::noiseless_observations(fs, one_path(idx, 300.0, true), *mask);
                music_delay_estimator est(fs, *mask);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(idx, est.estimate_index(obs.data()), 1e-12);
            }
    }

    void music_coarray_of_the_patterns()
    {
        // OP: 2 symbols x 16 nested subcarriers {0..3} ∪ {5k-1}: lags 0..59 at spacing 1.
        music_delay_estimator op(fs, nested_subcarrier_mask(fs.n_symbols, fs.n_subcarriers, 32));
        CPPUNIT_ASSERT_EQUAL(1, op.coarray_spacing());
        CPPUNIT_ASSERT_EQUAL(60, op.coarray_length());
        // UP: the 4 x 8 lattice has spacing 8: 8 lags of 8 subcarriers.
        music_delay_estimator up(fs, pilot_mask::uniform(fs.n_symbols, fs.n_subcarriers, 32));
        CPPUNIT_ASSERT_EQUAL(8, up.coarray_spacing());
        CPPUNIT_ASSERT_EQUAL(8, up.coarray_length());
    }

    void uniform_lattice_aliases_in_music()
    {
        // Spacing 8 repeats the pseudo-spectrum every 64/8 = 8 delay indices: exact
        // inside one period, ambiguous over the whole window.
        const auto up = pilot_mask::uniform(fs.n_symbols, fs.n_subcarriers, 32);
        const auto obs = qa::noiseless_observations(fs, one_path(21.5, 100.0), up);
        music_delay_estimator::settings s;
        s.search.max_index = 8.0;
        music_delay_estimator est(fs, up, s);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(5.5, est.estimate_index(obs.data()), 1e-12);
        music_delay_estimator whole(fs, up);
        const double e = whole.estimate_index(obs.data());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::remainder(e - 21.5, 8.0), 1e-9);
    }

    void bad_input_is_refused()
    {
        const auto mask = pilot_mask::random(fs.n_symbols, fs.n_subcarriers, 32, 7);
        std::vector<gr_complex> obs(32, gr_complex(1.0f, 0.0f));
        periodogram_delay_estimator pg(fs, mask);
        omp_delay_estimator omp(fs, mask);
        obs[5] = gr_complex(std::numeric_limits<float>::quiet_NaN(), 0.0f);
        CPPUNIT_ASSERT_THROW(pg.estimate_index(obs.data()), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(omp.estimate_index(obs.data()), std::invalid_argument);
        obs[5] = gr_complex(std::numeric_limits<float>::infinity(), 0.0f);
        CPPUNIT_ASSERT_THROW(pg.estimate_index(obs.data()), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(pg.estimate_index(nullptr), std::invalid_argument);

        omp_delay_estimator::settings so;
        so.n_atoms = 0;
        CPPUNIT_ASSERT_THROW(omp_delay_estimator(fs, mask, so), std::invalid_argument);
        so.n_atoms = 33;
        CPPUNIT_ASSERT_THROW(omp_delay_estimator(fs, mask, so), std::invalid_argument);
        so.n_atoms = 1;
        so.relative_power = 0.0;
        CPPUNIT_ASSERT_THROW(omp_delay_estimator(fs, mask, so), std::invalid_argument);

        periodogram_delay_estimator::settings sp;
        sp.search.min_index = 10.0;
        sp.search.max_index = 5.0; // empty window
        CPPUNIT_ASSERT_THROW(periodogram_delay_estimator(fs, mask, sp), std::invalid_argument);
        sp.search.min_index = -10.0;
        sp.search.max_index = 60.0; // wider than the unambiguous 64
        CPPUNIT_ASSERT_THROW(periodogram_delay_estimator(fs, mask, sp), std::invalid_argument);
        // A negative max_index other than the -1 sentinel was silently taken as M.
        sp.search = delay_search{};
        sp.search.max_index = -5.0;
        gr::sems::qa::assert_error([&] { periodogram_delay_estimator(fs, mask, sp); }, "max_index = -5",
                                   "-1 for the whole window");
        sp.search.max_index = -1.0; // the sentinel: the whole window
        periodogram_delay_estimator(fs, mask, sp);
        sp.search = delay_search{};
        sp.search.oversample = 0;
        CPPUNIT_ASSERT_THROW(periodogram_delay_estimator(fs, mask, sp), std::invalid_argument);

        // A mask for another frame.
        const auto small = pilot_mask::random(16, 64, 32, 7);
        CPPUNIT_ASSERT_THROW(periodogram_delay_estimator(fs, small), std::invalid_argument);
        CPPUNIT_ASSERT_THROW(music_delay_estimator(fs, small), std::invalid_argument);
        // One pilot per symbol has no same-symbol co-array: MUSIC refuses, saying why.
        CPPUNIT_ASSERT_THROW(music_delay_estimator(fs, pilot_mask::doppler(fs.n_symbols, fs.n_subcarriers, 32)),
                             std::invalid_argument);
        music_delay_estimator::settings sm;
        sm.n_paths = 0;
        CPPUNIT_ASSERT_THROW(music_delay_estimator(fs, nested_subcarrier_mask(32, 64, 32), sm), std::invalid_argument);
        sm.n_paths = 8; // the UP co-array has L = 8 < 9
        CPPUNIT_ASSERT_THROW(music_delay_estimator(fs, pilot_mask::uniform(32, 64, 32), sm), std::invalid_argument);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_baselines_delay);
