// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the azimuth bound of MIMO masks against the virtual array's closed form, the
 * coupling a block time division adds, and the maximum-likelihood estimator on the emulator's
 * own frames (exact when noiseless, at its bound at high SNR). */
#include <gnuradio/sems/baselines/mimo_angle.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/channel/mimo_pilots.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <iostream>
#include <random>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {

// The preset mimo2x4_3g: 4 receive elements d = 5 cm apart and 2 transmit elements 4d apart,
// centred: an 8-element virtual ULA.
array_geometry mimo2x4() { return array_geometry::find("mimo2x4_3g"); }

// Element 0 on (0,0), (2,2), element 1 on (0,2), (2,0): each element's pilots have the same
// centroid and spread in n and m, so the delay and Doppler take nothing from the angle.
mimo_mask balanced()
{
    const pilot_mask p(4, 4, { { 0, 0 }, { 0, 2 }, { 2, 0 }, { 2, 2 } });
    return mimo_mask(p, 2, { 0, 1, 1, 0 }); // mask order: (0,0) (0,2) (2,0) (2,2)
}

// A frame narrow against its carrier (30 kHz at 3 GHz): the pilots' frequencies differ by
// 1e-5 of it, so the virtual array's narrowband closed form holds to 1e-9 at their mean wavelength.
frame_settings narrow_frame(int n, int m)
{
    frame_settings fs;
    fs.n_symbols = n;
    fs.n_subcarriers = m;
    fs.bandwidth_hz = 30e3;
    fs.cp_len = 1;
    return fs;
}

double ula_crb(int k, double energy, double d, double lambda, double az)
{
    const double w = 2.0 * M_PI * d * std::cos(az) / lambda;
    return 6.0 / (energy * w * w * k * (double(k) * k - 1.0));
}

} // namespace

class qa_baselines_mimo : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_baselines_mimo);
    CPPUNIT_TEST(balanced_elements_reach_the_virtual_arrays_bound);
    CPPUNIT_TEST(same_pilots_are_the_receive_arrays_bound_with_the_transmit_array_factor);
    CPPUNIT_TEST(block_time_division_couples_the_angle_to_the_doppler);
    CPPUNIT_TEST(maximum_likelihood_is_exact_noiseless_and_at_its_bound_at_high_snr);
    CPPUNIT_TEST(bad_settings_are_refused_by_name);
    CPPUNIT_TEST_SUITE_END();

public:
    void balanced_elements_reach_the_virtual_arrays_bound()
    {
        const auto fs = narrow_frame(4, 4);
        const double lambda = pilot_wavelength_m(fs, balanced().mask()), d = 0.05;
        const auto a = mimo2x4();
        for (double az : { -0.9, -0.3, 0.0, 0.5, 1.1 }) {
            // Each virtual element sees 2 pilots at SNR 10: E = 20.
            const double crb = mimo_angle_crb_rad2(a, balanced(), fs, az, 0.0, 10.0);
            const double closed = ula_crb(8, 20.0, d, lambda, az);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, crb / closed, 1e-6);
        }
    }

    void same_pilots_are_the_receive_arrays_bound_with_the_transmit_array_factor()
    {
        // Both elements send every pilot at 1/sqrt(2): each receive element sees the transmit
        // array factor AF(φ) = 1 + exp(j2π u_y·4d/λ) over sqrt(2), whose gain and common phase
        // slope the unknown complex gain absorbs: the 4-element receive ULA's bound at an
        // energy of |AF|²/2 per pilot.
        const auto fs = narrow_frame(4, 4);
        const double d = 0.05;
        const auto a = mimo2x4();
        const auto m = mimo_mask::same_pilots(balanced().mask(), 2);
        const double lambda = pilot_wavelength_m(fs, m.mask());
        for (double az : { 0.0, 0.1, -0.2, 0.6 }) {
            const double af2 = std::norm(1.0 + std::exp(std::complex<double>(0.0, 2.0 * M_PI * std::sin(az) * 4.0 * d / lambda)));
            const double crb = mimo_angle_crb_rad2(a, m, fs, az, 0.0, 10.0);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, crb / ula_crb(4, 4 * 10.0 * af2 / 2.0, d, lambda, az), 1e-6);
        }
    }

    void block_time_division_couples_the_angle_to_the_doppler()
    {
        // Element 0 on symbols 0..3, element 1 on 4..7: the transmit phase step looks like a
        // Doppler ramp, and the bound rises above the interleaved division of the same pilots.
        const auto fs = narrow_frame(8, 16);
        const double d = 0.05;
        const auto a = mimo2x4();
        std::vector<pilot_position> pos;
        for (int n = 0; n < 8; ++n)
            for (int m = 0; m < 4; ++m)
                pos.push_back({ n, m * 4 });
        const pilot_mask p(8, 16, pos);
        std::vector<int> block;
        for (const auto& q : p.positions())
            block.push_back(q.n < 4 ? 0 : 1);
        const mimo_mask blocks(p, 2, block);
        const auto interleaved = mimo_mask::time_division(p, 2);
        for (double az : { -0.6, 0.2, 0.7 }) {
            const double cb = mimo_angle_crb_rad2(a, blocks, fs, az, 0.0, 1.0);
            const double ci = mimo_angle_crb_rad2(a, interleaved, fs, az, 0.0, 1.0);
            CPPUNIT_ASSERT(std::isfinite(cb));
            CPPUNIT_ASSERT(cb > 1.5 * ci);
            // Known Doppler would leave the blocks' virtual array whole: the same pilots
            // interleaved lose only the one-symbol offset between the elements' centroids.
            CPPUNIT_ASSERT(ci < 1.2 * ula_crb(8, 16.0, d, pilot_wavelength_m(fs, p), az));
        }
    }

    void maximum_likelihood_is_exact_noiseless_and_at_its_bound_at_high_snr()
    {
        frame_settings fs;
        const auto a = mimo2x4();
        const auto mask = mimo_mask::time_division(pilot_mask::from_pattern("staggered", fs.n_symbols, fs.n_subcarriers, 32), 2);
        angle_search search;
        search.min_rad = -1.0;
        search.max_rad = 1.0;
        search.grid = 64;
        const mimo_ml_angle_estimator ml(a, mask, fs, 0.0, search, 2);
        std::mt19937_64 g(11);
        std::uniform_real_distribution<double> uaz(-0.8, 0.8), urange(20.0, 120.0), uvel(-20.0, 20.0);
        std::normal_distribution<float> w(0.0f, std::sqrt(0.5f));
        const double snr = 100.0; // 20 dB per pilot
        double se = 0.0, crb = 0.0;
        const int frames = 400;
        for (int f = 0; f < frames; ++f) {
            target_spec t;
            t.cls = target_class::car;
            t.range_m = urange(g);
            t.velocity_mps = uvel(g);
            t.azimuth_rad = uaz(g);
            channel_model cm(fs, scene::fixed({ t }, std::nullopt, 0, fading_kind::none).with_array(a), 1);
            const auto r = cm.draw(0);
            auto y = mimo_pilots(cm, r, 0, mask);
            const double gain2 = std::norm(r.paths.at(0).gain);
            if (f < 5) {
                const auto e = ml.estimate(y.data());
                CPPUNIT_ASSERT_DOUBLES_EQUAL(t.azimuth_rad, e.azimuth_rad, 1e-6);
            }
            const float sigma = float(std::sqrt(gain2 / snr));
            for (auto& x : y)
                x += sigma * gr_complex(w(g), w(g));
            const double err = ml.estimate(y.data()).azimuth_rad - t.azimuth_rad;
            se += err * err;
            crb += mimo_angle_crb_rad2(a, mask, fs, t.azimuth_rad, 0.0, snr);
        }
        // 400 frames measure the RMSE within about 3.5 % (one standard error): 15 % is four.
        const double ratio = std::sqrt(se / crb);
        CPPUNIT_ASSERT_MESSAGE("RMSE / root mean CRB = " + std::to_string(ratio), ratio > 0.85 && ratio < 1.15);
        if (std::getenv("SEMS_QA_VERBOSE"))
            std::cerr << "RMSE / root mean CRB " << ratio << std::endl;
    }

    void bad_settings_are_refused_by_name()
    {
        const auto fs = narrow_frame(4, 4);
        const auto a = mimo2x4();
        const auto three = mimo_mask::same_pilots(balanced().mask(), 3);
        assert_error([&] { mimo_angle_crb_rad2(a, three, fs, 0.0, 0.0, 1.0); }, "2 transmit elements", "the MIMO mask 3");
        assert_error([&] { mimo_angle_crb_rad2(a, balanced(), fs, 0.0, 0.0, 0.0); }, "snr", "> 0");
        assert_error([&] { mimo_angle_crb_rad2(a, balanced(), narrow_frame(2, 4), 0.0, 0.0, 1.0); }, "mimo_angle_crb_rad2");
        assert_error([&] { mimo_ml_angle_estimator(a, three, fs, 0.0); }, "2 transmit elements", "the MIMO mask 3");
        assert_error([&] { mimo_ml_angle_estimator(a, balanced(), fs, 0.0, {}, 0); }, "oversample", "got 0");
        const mimo_ml_angle_estimator ml(a, balanced(), fs, 0.0, angle_search{ -1.0, 1.0, 16 }, 1);
        std::vector<gr_complex> y(16, gr_complex(1.0f, 0.0f));
        y[5] = gr_complex(NAN, 0.0f);
        assert_error([&] { ml.estimate(y.data()); }, "observation 5", "not finite");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_baselines_mimo);
