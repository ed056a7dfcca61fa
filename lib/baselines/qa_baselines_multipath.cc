// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the multipath references on frames drawn by THE channel model: the off-grid
 * least-squares fit (exact on noiseless frames, also the shared Doppler), the oracle-order
 * LS estimator (exact grid recovery on the grid, exact off it), OMP + LS refinement
 * (removes OMP's grid floor), the multipath CRB (the single-path closed form with one
 * path, never below it with more), and clear errors on bad input. */
#include "baselines/qa_baselines_frames.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/baselines/delay_crb.h>
#include <gnuradio/sems/baselines/ls_delay_estimator.h>
#include <gnuradio/sems/baselines/multipath_fit.h>
#include <gnuradio/sems/baselines/omp_delay_estimator.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using namespace gr::sems;

namespace {

// 32 distinct random subcarriers on one symbol (row `n`), or split over two rows.
pilot_mask subcarrier_mask(uint64_t seed, int n, int second_row = -1)
{
    std::vector<int> m(fs.n_subcarriers);
    for (int i = 0; i < fs.n_subcarriers; ++i)
        m[i] = i;
    std::mt19937_64 g(seed);
    std::shuffle(m.begin(), m.end(), g);
    std::vector<pilot_position> pos;
    for (int k = 0; k < 32; ++k)
        pos.push_back({ second_row >= 0 && k % 2 ? second_row : n, m[k] });
    return pilot_mask(fs.n_symbols, fs.n_subcarriers, pos);
}

// One target with paths at the given delay indices (the first is the direct path),
// deterministic gains (power 1, 0.5, 0.25, ...), the given Doppler.
scene paths_at(const std::vector<double>& delays, double doppler_hz)
{
    target_spec t;
    t.cls = target_class::car;
    t.range_m = delays[0] * fs.range_per_delay_index_m();
    t.velocity_mps = doppler_hz * fs.wavelength_m() / 2.0;
    t.paths.clear();
    for (size_t l = 0; l < delays.size(); ++l)
        t.paths.push_back({ (delays[l] - delays[0]) * fs.range_per_delay_index_m(), std::pow(0.5, double(l)) });
    return scene::fixed({ t }, std::nullopt, 0, fading_kind::none);
}

double energy(const std::vector<gr_complex>& y)
{
    double e = 0.0;
    for (auto v : y)
        e += std::norm(v);
    return e;
}

} // namespace

class qa_baselines_multipath : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_baselines_multipath);
    CPPUNIT_TEST(fit_recovers_off_grid_paths_exactly);
    CPPUNIT_TEST(fit_recovers_the_shared_doppler);
    CPPUNIT_TEST(anchored_fit_finds_the_later_paths);
    CPPUNIT_TEST(ls_reference_is_exact_on_and_off_the_grid);
    CPPUNIT_TEST(omp_refinement_removes_the_grid_floor);
    CPPUNIT_TEST(multipath_crb_reduces_to_the_single_path_closed_form);
    CPPUNIT_TEST(multipath_crb_grows_with_a_close_second_path);
    CPPUNIT_TEST(bad_input_is_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    void fit_recovers_off_grid_paths_exactly()
    {
        const auto mask = subcarrier_mask(1, 16);
        const std::vector<double> truth{ 10.3, 11.9, 14.45 };
        const auto y = qa::noiseless_observations(fs, paths_at(truth, 150.0), mask);
        const multipath_fitter f(fs, mask);
        CPPUNIT_ASSERT(!f.doppler_identifiable());
        const auto fit = f.refine(y.data(), { 10.15, 12.1, 14.3 }, 0.0);
        CPPUNIT_ASSERT_EQUAL(size_t(3), fit.delay_index.size());
        for (int l = 0; l < 3; ++l)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(truth[l], fit.delay_index[l], 1e-6);
        CPPUNIT_ASSERT(fit.residual < 1e-9 * energy(y));
        // Gains: powers 1, 0.5, 0.25 of the total 1.75, up to the common slow-time phase.
        for (int l = 0; l < 3; ++l)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::pow(0.5, l) / 1.75, std::norm(fit.gain[l]), 1e-5);
        // The start itself is not a fit: the cost is far above round-off there.
        CPPUNIT_ASSERT(f.evaluate(y.data(), { 10.15, 12.1, 14.3 }, 0.0).residual > 1e-3 * energy(y));
    }

    void fit_recovers_the_shared_doppler()
    {
        const auto mask = subcarrier_mask(2, 4, 20); // two symbols, 16 apart
        const std::vector<double> truth{ 22.2, 24.7 };
        const auto y = qa::noiseless_observations(fs, paths_at(truth, 130.0), mask);
        const multipath_fitter f(fs, mask);
        CPPUNIT_ASSERT(f.doppler_identifiable());
        const auto fit = f.refine(y.data(), { 22.0, 24.9 }, 125.0);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(130.0, fit.doppler_hz, 1e-4);
        for (int l = 0; l < 2; ++l)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(truth[l], fit.delay_index[l], 1e-6);
    }

    void anchored_fit_finds_the_later_paths()
    {
        const auto mask = subcarrier_mask(3, 8);
        const std::vector<double> truth{ 30.1, 31.6, 35.2 };
        const auto y = qa::noiseless_observations(fs, paths_at(truth, 60.0), mask);
        const multipath_fitter f(fs, mask);
        const auto fit = f.refine_anchored(y.data(), 30.3, 3, 7.0);
        for (int l = 0; l < 3; ++l)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(truth[l], fit.delay_index[l], 1e-6);
    }

    void ls_reference_is_exact_on_and_off_the_grid()
    {
        const auto mask = subcarrier_mask(4, 0);
        ls_delay_estimator::settings s;
        s.n_paths = 3;
        s.search.min_index = -2.0;
        s.search.max_index = 50.0;
        const ls_delay_estimator est(fs, mask, s);
        // On the 1/8 grid: the grid search alone is exact.
        const std::vector<double> on{ 12.625, 14.0, 16.375 };
        const auto y_on = qa::noiseless_observations(fs, paths_at(on, 80.0), mask);
        auto g = est.grid_search(y_on.data()).delay_index;
        std::sort(g.begin(), g.end());
        for (int l = 0; l < 3; ++l)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(on[l], g[l], 1e-12);
        // The fit then moves only by the float rounding of the observations.
        CPPUNIT_ASSERT_DOUBLES_EQUAL(on[0], est.estimate_index(y_on.data()), 1e-6);
        // Off the grid: the least-squares stage removes the grid mismatch.
        const std::vector<double> off{ 7.31, 8.77, 12.04 };
        const auto y_off = qa::noiseless_observations(fs, paths_at(off, 80.0), mask);
        const auto fit = est.fit(y_off.data());
        for (int l = 0; l < 3; ++l)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(off[l], fit.delay_index[l], 1e-6);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(off[0], est.estimate_index(y_off.data()), 1e-6);
    }

    void omp_refinement_removes_the_grid_floor()
    {
        const auto mask = pilot_mask::random(fs.n_symbols, fs.n_subcarriers, 32, 1);
        const std::vector<double> truth{ 20.37, 23.81 };
        const auto y = qa::noiseless_observations(fs, paths_at(truth, 170.0), mask);
        omp_delay_estimator::settings s;
        s.n_atoms = 2;
        const omp_delay_estimator grid_only(fs, mask, s);
        s.refine = true;
        const omp_delay_estimator refined(fs, mask, s);
        const double e_grid = std::abs(grid_only.estimate_index(y.data()) - truth[0]);
        const double e_ref = std::abs(refined.estimate_index(y.data()) - truth[0]);
        CPPUNIT_ASSERT(e_grid > 1e-3); // 20.37 is 0.005 from the nearest 1/8 point
        CPPUNIT_ASSERT(e_ref < 1e-6);
        const auto atoms = refined.refined_atoms(y.data());
        CPPUNIT_ASSERT_EQUAL(size_t(2), atoms.size());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(truth[1], atoms[1].delay_index, 1e-6);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(170.0, atoms[0].doppler_hz, 1e-3);
    }

    void multipath_crb_reduces_to_the_single_path_closed_form()
    {
        for (const auto& mask : { pilot_mask::random(fs.n_symbols, fs.n_subcarriers, 32, 7), subcarrier_mask(5, 9) })
            for (bool known : { false, true }) {
                const std::complex<double> g(0.6, -0.3);
                const double v1 = delay_crb::multipath_variance_index(fs, mask, 20.0, { { 17.3, g } }, known);
                const double closed = delay_crb::variance_index(fs, mask, 20.0, known, std::norm(g));
                CPPUNIT_ASSERT_DOUBLES_EQUAL(closed, v1, 1e-9 * closed);
            }
        const auto mask = subcarrier_mask(5, 9);
        // The Rayleigh MAE at mean power p: √(2·var₁/p).
        const double v = delay_crb::variance_index(fs, mask, 30.0, false, 1.0);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(2.0 * v / 0.5), delay_crb::mae_index(fs, mask, 30.0, false, true, 0.5),
                                     1e-12);
        CPPUNIT_ASSERT_EQUAL(0.0, delay_crb::multipath_variance_index(fs, mask, std::numeric_limits<double>::infinity(),
                                                                      { { 3.0, 1.0 } }));
    }

    void multipath_crb_grows_with_a_close_second_path()
    {
        const auto mask = subcarrier_mask(6, 3);
        const std::complex<double> g1(1.0, 0.0), g2(0.0, 0.7);
        const double single = delay_crb::multipath_variance_index(fs, mask, 30.0, { { 20.0, g1 } });
        const double far = delay_crb::multipath_variance_index(fs, mask, 30.0, { { 20.0, g1 }, { 40.0, g2 } });
        const double near = delay_crb::multipath_variance_index(fs, mask, 30.0, { { 20.0, g1 }, { 20.4, g2 } });
        // More unknowns never help; a path 0.4 indices behind (below the 1-index resolution)
        // costs far more than one 20 indices away.
        CPPUNIT_ASSERT(far >= single * (1 - 1e-12));
        CPPUNIT_ASSERT(near > 4.0 * far);
        // Coincident paths: the information is singular.
        CPPUNIT_ASSERT(std::isinf(delay_crb::multipath_variance_index(fs, mask, 30.0, { { 20.0, g1 }, { 20.0, g2 } })));
    }

    void bad_input_is_refused()
    {
        const auto mask = subcarrier_mask(7, 5);
        const std::vector<gr_complex> y(32, gr_complex(1.0f, 0.0f));
        auto nan_y = y;
        nan_y[4] = gr_complex(std::nanf(""), 0.0f);
        const multipath_fitter f(fs, mask);
        qa::assert_error([&] { f.refine(y.data(), {}, 0.0); }, "start delays");
        qa::assert_error([&] { f.refine(nullptr, { 1.0 }, 0.0); }, "null");
        qa::assert_error([&] { f.refine(nan_y.data(), { 1.0 }, 0.0); }, "observation 4", "not finite");
        qa::assert_error([&] { f.refine_anchored(y.data(), 3.0, 0, 5.0); }, "n_paths");
        qa::assert_error([&] { f.refine_anchored(y.data(), 3.0, 2, 0.1); }, "span_index");
        multipath_fitter::settings fsb;
        fsb.max_iterations = 0;
        qa::assert_error([&] { multipath_fitter(fs, mask, fsb); }, "max_iterations");
        ls_delay_estimator::settings s;
        s.n_paths = 33;
        qa::assert_error([&] { ls_delay_estimator(fs, mask, s); }, "n_paths");
        s.n_paths = 2;
        s.sweeps = -1;
        qa::assert_error([&] { ls_delay_estimator(fs, mask, s); }, "sweeps");
        qa::assert_error([&] { delay_crb::multipath_variance_index(fs, mask, 10.0, {}); }, "no paths");
        qa::assert_error([&] { delay_crb::multipath_variance_index(fs, mask, std::nan(""), { { 1.0, 1.0 } }); },
                         "NaN");
        qa::assert_error([&] { delay_crb::multipath_variance_index(fs, mask, 10.0, { { 1.0, 0.0 } }); }, "zero gain");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_baselines_multipath);
