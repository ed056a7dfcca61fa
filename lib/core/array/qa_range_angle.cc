// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the range–angle map on the emulator's array channel — a point target on its cell at
 * 0 dB, two targets at one range on their own rows, a sparse mask's loss against its closed
 * form, and bad settings. */
#include <gnuradio/sems/core/array/range_angle.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {

// Fixed unfaded point targets (range, azimuth) seen by array a; the noiseless observations of
// frame 0 at the mask's pilots, element-major (what the pilot extractor gives with x = 1).
std::vector<gr_complex> observe(const frame_settings& fs, const array_geometry& a, const pilot_mask& mask,
                                const std::vector<std::array<double, 3>>& targets) // range, azimuth, velocity
{
    std::vector<target_spec> ts;
    for (const auto& [range, az, v] : targets) {
        target_spec t;
        t.cls = target_class::car;
        t.range_m = range;
        t.velocity_mps = v;
        t.azimuth_rad = az;
        ts.push_back(t);
    }
    channel_model cm(fs, scene::fixed(ts, std::nullopt, 0, fading_kind::none).with_array(a), 1);
    const auto r = cm.draw(0);
    std::vector<gr_complex> h(size_t(fs.grid_size())), y;
    const auto flat = mask.flat_indices();
    for (int k = 0; k < cm.n_elements(); ++k) {
        cm.factors(r, 0, k).fill(h.data());
        for (int i : flat)
            y.push_back(h[size_t(i)]);
    }
    return y;
}

pilot_mask full_grid(const frame_settings& fs)
{
    std::vector<pilot_position> p;
    for (int n = 0; n < fs.n_symbols; ++n)
        for (int m = 0; m < fs.n_subcarriers; ++m)
            p.push_back({ n, m });
    return pilot_mask(fs.n_symbols, fs.n_subcarriers, p);
}

} // namespace

class qa_range_angle : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_range_angle);
    CPPUNIT_TEST(a_point_target_reads_0_db_on_its_cell);
    CPPUNIT_TEST(two_targets_at_one_range_sit_on_their_rows);
    CPPUNIT_TEST(bad_settings_are_refused_by_name);
    CPPUNIT_TEST_SUITE_END();

public:
    void a_point_target_reads_0_db_on_its_cell()
    {
        // Delay index 9 (45 m at 30 MHz) and the azimuth of row 40 of 64: 0 dB there (within the
        // plane wave's per-element delay, under 0.004 of a delay index), the map's maximum; with
        // cosine elements the same cell holds the maximum at the pattern's power, (cos² φ)²; a
        // uniform 128-pilot mask reads its windowed fill at the same cell.
        const frame_settings fs;
        for (auto pattern : { element_pattern::isotropic, element_pattern::cosine }) {
            const auto a = array_geometry::ula(8, 0.05, pattern);
            const auto mask = full_grid(fs);
            range_angle map(mask, a, fs.wavelength_m(), 64);
            const auto y = observe(fs, a, mask, { { 45.0, map.azimuth_rad(40), 7.0 } });
            CPPUNIT_ASSERT_EQUAL(int(y.size()), map.n_observations());
            std::vector<float> out(size_t(map.map_size()));
            map.compute(y.data(), out.data());
            const auto peak = std::max_element(out.begin(), out.end()) - out.begin();
            CPPUNIT_ASSERT_EQUAL(long(40 * 64 + 9), long(peak));
            const double c = std::cos(map.azimuth_rad(40));
            const double want = pattern == element_pattern::cosine ? 10.0 * std::log10(std::pow(c * c, 2)) : 0.0;
            CPPUNIT_ASSERT_DOUBLES_EQUAL(want, out[size_t(peak)], 0.01);
        }
        const auto a = array_geometry::ula(8, 0.05);
        const auto sparse = pilot_mask::uniform(fs.n_symbols, fs.n_subcarriers, 128);
        range_angle map(sparse, a, fs.wavelength_m(), 64);
        const auto y = observe(fs, a, sparse, { { 45.0, map.azimuth_rad(40), 7.0 } });
        std::vector<float> out(size_t(map.map_size()));
        map.compute(y.data(), out.data());
        // Closed form: a pilot row's profile at the target's cell is Σ_{m in the row} w_m / Σ_m w_m
        // (periodic Hann w), the map the mean of its square over all N symbols.
        double sum_w = 0.0, want_power = 0.0;
        std::vector<double> row_w(size_t(fs.n_symbols), 0.0);
        for (int m = 0; m < fs.n_subcarriers; ++m)
            sum_w += 0.5 - 0.5 * std::cos(2.0 * M_PI * m / fs.n_subcarriers);
        for (const auto& p : sparse.positions())
            row_w[size_t(p.n)] += 0.5 - 0.5 * std::cos(2.0 * M_PI * p.m / fs.n_subcarriers);
        for (double w : row_w)
            want_power += std::pow(w / sum_w, 2) / fs.n_symbols;
        const double want = 10.0 * std::log10(want_power);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(want, out[size_t(40 * 64 + 9)], 0.05);
    }

    void two_targets_at_one_range_sit_on_their_rows()
    {
        // Two targets at 45 m, rows 20 and 44 (about 3.5 beamwidths of an 8-element λ/2 ULA
        // apart), at different speeds (their cross term averages out over the symbols): each
        // row's peak is at delay index 9 within 0.5 dB of its power, half the scene's (−3 dB;
        // the other target's sidelobe adds its power, under −13 dB), and between them the map
        // falls > 10 dB.
        const frame_settings fs;
        const auto a = array_geometry::ula(8, 0.05);
        const auto mask = full_grid(fs);
        range_angle map(mask, a, fs.wavelength_m(), 64);
        const auto y = observe(fs, a, mask, { { 45.0, map.azimuth_rad(20), 7.0 }, { 45.0, map.azimuth_rad(44), -5.0 } });
        std::vector<float> out(size_t(map.map_size()));
        map.compute(y.data(), out.data());
        for (int row : { 20, 44 }) {
            const float* r = out.data() + size_t(row) * 64;
            CPPUNIT_ASSERT_EQUAL(long(9), long(std::max_element(r, r + 64) - r));
            CPPUNIT_ASSERT_DOUBLES_EQUAL(10.0 * std::log10(0.5), r[9], 0.5);
        }
        CPPUNIT_ASSERT_LESS(-10.0f, out[size_t(32 * 64 + 9)]);
    }

    void bad_settings_are_refused_by_name()
    {
        const frame_settings fs;
        const auto a = array_geometry::ula(4, 0.05);
        const auto mask = pilot_mask::uniform(fs.n_symbols, fs.n_subcarriers, 32);
        assert_error([&] { range_angle(mask, a, fs.wavelength_m(), 1); }, "n_angles", "got 1");
        assert_error([&] { range_angle(mask, a, 0.0, 64); }, "wavelength_m", "> 0");
        assert_error([&] { range_angle(mask, a, fs.wavelength_m(), 64, "kaiser"); }, "window", "kaiser");
        const auto mimo = array_geometry::from_positions({ { 0, -0.025, 0 }, { 0, 0.025, 0 } },
                                                         { { 0, 0, 0 }, { 0, 0.1, 0 } });
        assert_error([&] { range_angle(mask, mimo, fs.wavelength_m(), 64); }, "2 transmit elements", "with one");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_range_angle);
