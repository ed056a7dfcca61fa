// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: MIMO masks — the hand forms' assignments, the file's round trip and its refusals,
 * and what a receiver observes against the plane wave's closed form. */
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/channel/mimo_pilots.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <filesystem>
#include <map>
#include <set>
#include <unistd.h>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {

// The preset mimo2x4_3g: 4 receive elements 5 cm (λ/2 at 3 GHz) apart and 2 transmit elements
// 20 cm apart: an 8-element virtual ULA.
array_geometry mimo2x4() { return array_geometry::find("mimo2x4_3g"); }

} // namespace

class qa_mimo_mask : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_mimo_mask);
    CPPUNIT_TEST(time_division_gives_each_symbol_to_one_element_in_turn);
    CPPUNIT_TEST(frequency_division_gives_each_subcarrier_to_one_element_in_turn);
    CPPUNIT_TEST(same_pilots_share_each_pilots_energy);
    CPPUNIT_TEST(file_round_trip);
    CPPUNIT_TEST(bad_masks_are_refused_by_name);
    CPPUNIT_TEST(observations_follow_the_plane_wave_closed_form);
    CPPUNIT_TEST_SUITE_END();

public:
    void time_division_gives_each_symbol_to_one_element_in_turn()
    {
        const auto p = pilot_mask::from_pattern("staggered", 16, 32, 24);
        const auto m = mimo_mask::time_division(p, 3);
        std::map<int, int> of_symbol;
        for (int i = 0; i < p.size(); ++i) {
            const int n = p.positions()[size_t(i)].n, t = m.transmit()[size_t(i)];
            if (of_symbol.count(n))
                CPPUNIT_ASSERT_EQUAL(of_symbol[n], t);
            of_symbol[n] = t;
        }
        int rank = 0;
        for (const auto& [n, t] : of_symbol)
            CPPUNIT_ASSERT_EQUAL(rank++ % 3, t);
        for (int c : m.pilots_per_element())
            CPPUNIT_ASSERT(c > 0);
        // Pilots on fewer symbols than elements: one element would send nothing.
        const pilot_mask one_symbol(8, 8, { { 3, 1 }, { 3, 5 } });
        assert_error([&] { mimo_mask::time_division(one_symbol, 2); }, "time division", "1 symbols");
    }

    void frequency_division_gives_each_subcarrier_to_one_element_in_turn()
    {
        const pilot_mask p(8, 8, { { 0, 1 }, { 0, 4 }, { 2, 1 }, { 5, 6 } });
        const auto m = mimo_mask::frequency_division(p, 2);
        // Subcarriers 1, 4, 6 in order → elements 0, 1, 0.
        CPPUNIT_ASSERT((m.transmit() == std::vector<int>{ 0, 1, 0, 0 }));
        CPPUNIT_ASSERT((m.pilots_per_element() == std::vector<int>{ 3, 1 }));
    }

    void same_pilots_share_each_pilots_energy()
    {
        const auto p = pilot_mask::from_pattern("uniform", 8, 16, 8);
        const auto m = mimo_mask::same_pilots(p, 4);
        double e = 0.0;
        for (int j = 0; j < 4; ++j) {
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.5, m.amplitude(3, j), 1e-15);
            e += m.amplitude(3, j) * m.amplitude(3, j);
        }
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, e, 1e-15); // every form: one unit of energy per pilot
        const auto t = mimo_mask::time_division(p, 2);
        CPPUNIT_ASSERT_EQUAL(1.0, t.amplitude(0, t.transmit()[0]));
        CPPUNIT_ASSERT_EQUAL(0.0, t.amplitude(0, 1 - t.transmit()[0]));
    }

    void file_round_trip()
    {
        const auto m = mimo_mask(pilot_mask::from_pattern("random", 8, 16, 10, 7), 3,
                                 { 0, 2, 1, mimo_mask::every_element, 0, 0, 1, 2, 2, 1 });
        const auto path = std::filesystem::temp_directory_path() / ("qa_mimo_mask_" + std::to_string(::getpid()) + ".json");
        m.save(path.string());
        const auto back = mimo_mask::load(path.string());
        std::filesystem::remove(path);
        CPPUNIT_ASSERT(back == m);
        CPPUNIT_ASSERT_EQUAL(std::string(mimo_mask::format_name), m.to_json()["format"].get<std::string>());
        // A file may list its pilots in any order: transmit[i] is the element of pilots[i] as listed.
        const auto listed = mimo_mask::parse(R"({"format": "sems.mimo_mask", "version": 1, "n_transmit": 2,
            "transmit": [1, 0, -1],
            "mask": {"format": "sems.pilot_mask", "version": 1, "n_symbols": 4, "n_subcarriers": 4,
                     "pilots": [[3, 0], [0, 2], [1, 1]]}})");
        CPPUNIT_ASSERT((listed.transmit() == std::vector<int>{ 0, -1, 1 })); // (0,2) (1,1) (3,0)
    }

    void bad_masks_are_refused_by_name()
    {
        const auto p = pilot_mask::from_pattern("uniform", 8, 16, 4);
        assert_error([&] { mimo_mask(p, 2, { 0, 1, 2, 0 }, "m.json"); }, "m.json: transmit[2]", "got 2");
        assert_error([&] { mimo_mask(p, 2, { 0, 1, -2, 0 }, "m.json"); }, "transmit[2]", "got -2");
        assert_error([&] { mimo_mask(p, 2, { 0, 1 }, "m.json"); }, "transmit", "2 entries for the mask's 4 pilots");
        assert_error([&] { mimo_mask(p, 0, { 0, 0, 0, 0 }, "m.json"); }, "n_transmit", "got 0");
        const pilot_mask unequal(8, 16, p.positions(), gr_complex(1.0f, 0.0f), { { "kind", "explicit" } }, "pilot mask",
                                 { 0.5, 1.5, 1.0, 1.0 });
        assert_error([&] { mimo_mask(unequal, 2, { 0, 1, 0, 1 }, "m.json"); }, "mask.power", "equal energies");
        auto j = mimo_mask::same_pilots(p, 2).to_json();
        j["transmit"][1] = 5;
        assert_error([&] { mimo_mask::from_json(j, "f.json"); }, "f.json: transmit[1]", "got 5");
        j = mimo_mask::same_pilots(p, 2).to_json();
        j["transmitt"] = 1;
        assert_error([&] { mimo_mask::from_json(j, "f.json"); }, "transmitt", "unknown");
        // The scene's array and the mask must agree on N_t.
        frame_settings fs;
        const auto a = mimo2x4();
        target_spec t;
        t.cls = target_class::car;
        t.range_m = 60.0;
        channel_model cm(fs, scene::fixed({ t }, std::nullopt, 0, fading_kind::none).with_array(a), 1);
        const auto three = mimo_mask::same_pilots(pilot_mask::from_pattern("uniform", fs.n_symbols, fs.n_subcarriers, 8), 3);
        assert_error([&] { mimo_pilots(cm, cm.draw(0), 0, three); }, "2 transmit elements", "the MIMO mask 3");
        const auto small = mimo_mask::same_pilots(pilot_mask::from_pattern("uniform", 8, 16, 8), 2);
        assert_error([&] { mimo_pilots(cm, cm.draw(0), 0, small); }, "mimo_pilots", "8");
    }

    void observations_follow_the_plane_wave_closed_form()
    {
        frame_settings fs;
        const auto a = mimo2x4();
        const double az = 0.4;
        target_spec t;
        t.cls = target_class::car;
        t.range_m = 75.0;
        t.velocity_mps = 8.0;
        t.azimuth_rad = az;
        channel_model cm(fs, scene::fixed({ t }, std::nullopt, 0, fading_kind::none).with_array(a), 3);
        const auto r = cm.draw(0);
        const auto p = pilot_mask::from_pattern("staggered", fs.n_symbols, fs.n_subcarriers, 16);
        const auto u = direction_vector(az, 0.0);
        // The emulator's element delay is exact: element offset o turns pilot i by
        // exp(j2π f_i u·o/c) at its own frequency f_i = f_c + m_i Δf (carrier phase and delay).
        const double c = speed_of_light_mps;
        std::vector<double> f;
        for (const auto& q : p.positions())
            f.push_back(fs.carrier_hz + q.m * fs.subcarrier_spacing_hz());
        // Time division: pilot i from element j_i; y[k,i]/y[0,i] = exp(j2π u·(p_k − p_0)/λ) (the
        // transmit element's phase cancels), and y[0,i] of element 1 over element 0's channel
        // at the same resource element carries exp(j2π u·(q_1 − q_0)/λ).
        const auto td = mimo_mask::time_division(p, 2);
        const auto y = mimo_pilots(cm, r, 0, td);
        CPPUNIT_ASSERT_EQUAL(size_t(4 * 16), y.size());
        const auto flat = p.flat_indices();
        std::vector<std::vector<gr_complex>> h(8, std::vector<gr_complex>(size_t(fs.grid_size())));
        for (int v = 0; v < 8; ++v)
            cm.factors(r, 0, v).fill(h[size_t(v)].data());
        const auto& rx = a.receive();
        const auto& tx = a.transmit();
        const auto sp = mimo_mask::same_pilots(p, 2);
        const auto ys = mimo_pilots(cm, r, 0, sp);
        for (int i = 0; i < 16; ++i) {
            const int j = td.transmit()[size_t(i)];
            for (int k = 1; k < 4; ++k) {
                const std::complex<double> ratio =
                    std::complex<double>(y[size_t(k) * 16 + i]) / std::complex<double>(y[size_t(i)]);
                const std::complex<double> closed =
                    std::exp(std::complex<double>(0.0, 2.0 * M_PI * f[size_t(i)] * u[1] * (rx[k][1] - rx[0][1]) / c));
                CPPUNIT_ASSERT(std::abs(ratio - closed) < 1e-5);
            }
            const std::complex<double> other = std::complex<double>(h[size_t(1 - j)][size_t(flat[size_t(i)])]) /
                                               std::complex<double>(y[size_t(i)]);
            const double dq = (1 - j) == 1 ? tx[1][1] - tx[0][1] : tx[0][1] - tx[1][1];
            const std::complex<double> closed_tx = std::exp(std::complex<double>(0.0, 2.0 * M_PI * f[size_t(i)] * u[1] * dq / c));
            CPPUNIT_ASSERT(std::abs(other - closed_tx) < 1e-5);
            // Same pilots: every element at 1/sqrt(2), the transmit array factor over element 0's channel.
            const std::complex<double> h0(h[0][size_t(flat[size_t(i)])]);
            const std::complex<double> factor =
                (1.0 + std::exp(std::complex<double>(0.0, 2.0 * M_PI * f[size_t(i)] * u[1] * (tx[1][1] - tx[0][1]) / c))) /
                std::sqrt(2.0);
            CPPUNIT_ASSERT(std::abs(std::complex<double>(ys[size_t(i)]) - h0 * factor) < 1e-5 * std::abs(h0) + 1e-7);
        }
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_mimo_mask);
