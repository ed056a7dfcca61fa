// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems QA: a scene's link budget — each target's SNR per resource element is the radar
 * equation at its range and RCS, frame by frame, against a closed form written out here. */
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/link_budget.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <string>
#include <vector>

using namespace gr::sems;

namespace {

// The budget of the tests: a 2.4 GHz SDR-like radar (10 dBm, 6 dBi antennas, 5 dB noise
// figure, 2 dB of losses).
const std::string budget_json =
    R"("link_budget": {"tx_power_dbm": 10, "tx_gain_dbi": 6, "rx_gain_dbi": 6, "noise_figure_db": 5, "system_loss_db": 2})";

// SNR = P_t G_t G_r λ² σ / ((4π)³ R⁴ k T_0 F B L) in linear units, then dB.
double closed_form_snr_db(const frame_settings& fs, double range_m, double rcs_dbsm)
{
    const double pt = std::pow(10.0, (10.0 - 30.0) / 10.0), g = std::pow(10.0, 6.0 / 10.0);
    const double lambda = 3e8 / fs.carrier_hz, sigma = std::pow(10.0, rcs_dbsm / 10.0);
    const double f = std::pow(10.0, 5.0 / 10.0), l = std::pow(10.0, 2.0 / 10.0);
    const double snr = pt * g * g * lambda * lambda * sigma /
                       (std::pow(4 * M_PI, 3) * std::pow(range_m, 4) * 1.380649e-23 * 290.0 * f * fs.bandwidth_hz * l);
    return 10.0 * std::log10(snr);
}

scene budget_scene(const std::string& targets, const std::string& extra = "")
{
    return scene::parse(R"({"format": "sems.scene", "version": 1, "fading": "none", )" + budget_json + ", " + extra +
                            R"("targets": )" + targets + "}",
                        "budget.json");
}

// Mean |H|² over a noiseless frame, in dB: a point target's per-resource-element power.
double grid_power_db(const frame_settings& fs, channel_model& cm, uint64_t frame, frame_truth* truth = nullptr)
{
    const auto r = cm.draw(frame);
    std::vector<gr_complex> h(fs.grid_size());
    cm.factors(r, frame * fs.n_symbols).fill(h.data());
    double p = 0.0;
    for (const auto& x : h)
        p += std::norm(std::complex<double>(x));
    if (truth)
        *truth = r.truth;
    return 10.0 * std::log10(p / h.size());
}

} // namespace

class qa_link_budget : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_link_budget);
    CPPUNIT_TEST(snr_against_range_is_the_radar_equation);
    CPPUNIT_TEST(a_moving_target_follows_r_to_the_fourth);
    CPPUNIT_TEST(random_targets_draw_their_class_rcs);
    CPPUNIT_TEST(clutter_keeps_its_ratio_to_the_targets);
    CPPUNIT_TEST(round_trip);
    CPPUNIT_TEST(bad_budgets_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    // From 1 m to the frame's far end and over 60 dB of RCS: the grid's power and the truth's
    // link SNR equal the closed form (asked within 0.1 dB; they agree to rounding).
    void snr_against_range_is_the_radar_equation()
    {
        const frame_settings fs;
        for (double range : { 1.0, 7.5, 40.0, 150.0, 300.0 })
            for (double rcs : { -30.0, 0.0, 30.0 }) {
                channel_model cm(fs,
                                 budget_scene(R"([{"class": "car", "range_m": )" + std::to_string(range) +
                                              R"(, "velocity_mps": 3, "rcs_dbsm": )" + std::to_string(rcs) + "}]"),
                                 1);
                frame_truth truth;
                const double got = grid_power_db(fs, cm, 0, &truth), want = closed_form_snr_db(fs, range, rcs);
                const std::string at = "at " + std::to_string(range) + " m, " + std::to_string(rcs) + " dBsm";
                CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE(at, want, got, 0.1);
                CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE(at, want, got, 1e-5);
                CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE(at, want, truth.link_snr_db, 1e-9);
            }
        // Without a budget: unit power and no link SNR (the paper's scenes are unchanged).
        channel_model plain(fs, scene::parse(R"({"format": "sems.scene", "version": 1, "fading": "none",
            "targets": [{"class": "car", "range_m": 40, "velocity_mps": 3}]})"), 1);
        frame_truth truth;
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, grid_power_db(fs, plain, 0, &truth), 1e-5);
        CPPUNIT_ASSERT(std::isnan(truth.link_snr_db));
    }

    // A receding target on a track: frame by frame its SNR falls as R⁻⁴ of its range then.
    void a_moving_target_follows_r_to_the_fourth()
    {
        const frame_settings fs;
        channel_model cm(fs,
                         budget_scene(R"([{"class": "car", "range_m": 10, "velocity_mps": -15, "rcs_dbsm": 10}])",
                                      R"("track": {"range_m": [5, 200]}, )"),
                         3);
        double first = 0.0;
        for (uint64_t f = 0; f < 200; f += 20) {
            frame_truth truth;
            const double got = grid_power_db(fs, cm, f, &truth);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(closed_form_snr_db(fs, truth.range_m, 10.0), got, 1e-5);
            if (f == 0)
                first = got;
            else // 40 dB per decade of range, from the first frame's
                CPPUNIT_ASSERT_DOUBLES_EQUAL(first - 40.0 * std::log10(truth.range_m / 10.0), got, 1e-5);
        }
        CPPUNIT_ASSERT(first - grid_power_db(fs, cm, 180) > 30.0); // it went from 10 m to past 50 m
    }

    // A random scene's targets draw their RCS uniformly in dB from their class's interval.
    void random_targets_draw_their_class_rcs()
    {
        const auto lib = class_library::from_json(nlohmann::json::parse(R"({"format": "sems.classes", "version": 1,
            "name": "rcs", "classes": [{"name": "small", "range_m": [2, 100], "speed_mps": [0, 5], "rcs_dbsm": [-20, -10]},
                                       {"name": "big", "range_m": [2, 100], "speed_mps": [0, 5], "rcs_dbsm": 15}]})"),
                                                  "rcs.json");
        random_spec r;
        r.classes.clear();
        const frame_settings fs;
        channel_model cm(fs, scene::random(r, std::nullopt, fading_kind::none, lib).with_budget(link_budget{}), 5);
        double lo = 1e9, hi = -1e9;
        for (uint64_t f = 0; f < 500; ++f) {
            const auto truth = cm.draw(f).truth;
            const double rcs = truth.link_snr_db - link_budget{}.snr_db(fs, truth.range_m, 0.0);
            if (truth.class_name == "big") {
                CPPUNIT_ASSERT_DOUBLES_EQUAL(15.0, rcs, 1e-9);
            } else {
                CPPUNIT_ASSERT(rcs >= -20.0 - 1e-9 && rcs <= -10.0 + 1e-9);
                lo = std::min(lo, rcs);
                hi = std::max(hi, rcs);
            }
        }
        CPPUNIT_ASSERT(lo < -19.0 && hi > -11.0);
    }

    // Clutter keeps its meaning: csr times the targets' power, whatever their range.
    void clutter_keeps_its_ratio_to_the_targets()
    {
        const frame_settings fs;
        for (double range : { 3.0, 120.0 }) {
            channel_model cm(fs,
                             budget_scene(R"([{"class": "car", "range_m": )" + std::to_string(range) +
                                              R"(, "velocity_mps": 3, "rcs_dbsm": 5}])",
                                          R"("clutter": {"csr_db": 7, "paths": 3}, )"),
                             2);
            const auto r = cm.draw(0);
            CPPUNIT_ASSERT_EQUAL(size_t(4), r.paths.size());
            const double clutter = r.paths[1].mean_power + r.paths[2].mean_power + r.paths[3].mean_power;
            CPPUNIT_ASSERT_DOUBLES_EQUAL(7.0, 10.0 * std::log10(clutter / r.paths[0].mean_power), 1e-9);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(closed_form_snr_db(fs, range, 5.0), 10.0 * std::log10(r.paths[0].mean_power), 1e-9);
        }
    }

    void round_trip()
    {
        const auto s = budget_scene(R"([{"class": "car", "range_m": 40, "velocity_mps": 3, "rcs_dbsm": 12.5}])");
        const auto again = scene::from_json(s.to_json(), "again");
        CPPUNIT_ASSERT(again.budget() && *again.budget() == *s.budget());
        CPPUNIT_ASSERT_EQUAL(12.5, again.targets()[0].rcs_dbsm);
        CPPUNIT_ASSERT_EQUAL(s.to_json().dump(), again.to_json().dump());
        CPPUNIT_ASSERT_EQUAL(6.0, s.budget()->rx_gain_dbi);
        CPPUNIT_ASSERT_EQUAL(290.0, s.budget()->noise_temperature_k); // a default
    }

    void bad_budgets_are_refused()
    {
        const std::string car = R"([{"class": "car", "range_m": 40, "velocity_mps": 3, "rcs_dbsm": 10}])";
        qa::assert_error([] { budget_scene(R"([{"class": "car", "range_m": 40, "velocity_mps": 3}])"); },
                         "budget.json: targets[0].rcs_dbsm", "missing");
        qa::assert_error([] { budget_scene(R"([{"class": "car", "range_m": 0.5, "velocity_mps": 3, "rcs_dbsm": 1}])"); },
                         "targets[0].range_m", "too near");
        qa::assert_error([] { budget_scene(R"([{"class": "car", "range_m": 9, "velocity_mps": 3, "rcs_dbsm": 1, "power": 2}])"); },
                         "targets[0].power", "rcs_dbsm, not power");
        qa::assert_error([&] { budget_scene(car, R"("track": {"range_m": [0, 100]}, )"); }, "track.range_m", "1.0");
        auto with_budget = [&](const std::string& b) {
            return [b, car] {
                scene::parse(R"({"format": "sems.scene", "version": 1, "link_budget": )" + b + R"(, "targets": )" + car + "}",
                             "b.json");
            };
        };
        qa::assert_error(with_budget(R"({"noise_figure_db": -1})"), "b.json: link_budget.noise_figure_db", ">= 0");
        qa::assert_error(with_budget(R"({"system_loss_db": -3})"), "link_budget.system_loss_db", ">= 0");
        qa::assert_error(with_budget(R"({"noise_temperature_k": 0})"), "link_budget.noise_temperature_k", "> 0");
        qa::assert_error(with_budget(R"({"tx_power_dbm": "high"})"), "link_budget.tx_power_dbm", "");
        qa::assert_error(with_budget(R"({"bandwidth_hz": 1e6})"), "link_budget.bandwidth_hz", "unknown key");
        // A budget whose strongest target would not fit a frame of floats is refused by the model.
        qa::assert_error([] {
            channel_model(frame_settings{}, scene::parse(R"({"format": "sems.scene", "version": 1,
                "link_budget": {"tx_power_dbm": 150, "tx_gain_dbi": 100, "rx_gain_dbi": 100},
                "targets": [{"class": "car", "range_m": 1, "velocity_mps": 0, "rcs_dbsm": 100}]})"), 1);
        },
                         "scene target 0", "beyond the 300");
        const auto strong = [](const std::string& clutter) { // 260 dB of target, and 60 dB of clutter above it
            return scene::parse(R"({"format": "sems.scene", "version": 1,
                "link_budget": {"tx_power_dbm": 100, "tx_gain_dbi": 50, "rx_gain_dbi": 50}, )" + clutter + R"(
                "targets": [{"class": "car", "range_m": 1, "velocity_mps": 0, "rcs_dbsm": 20}]})");
        };
        channel_model(frame_settings{}, strong(""), 1); // 260 dB alone fits
        qa::assert_error([&] { channel_model(frame_settings{}, strong(R"("clutter": {"csr_db": 60, "ranges_m": [10]},)"), 1); },
                         "scene target 0", "clutter above it included");
        // A random scene needs every class's RCS and ranges from 1 m: the paper's classes have
        // an RCS but start at 0 m.
        qa::assert_error([] { scene::random(random_spec{}).with_budget(link_budget{}); }, "class \"pedestrian\"", "as near as");
        const auto no_rcs = class_library::from_json(nlohmann::json::parse(R"({"format": "sems.classes", "version": 1,
            "name": "x", "classes": [{"name": "rock", "range_m": [5, 50], "speed_mps": 0}]})"), "x.json");
        random_spec r;
        r.classes.clear();
        qa::assert_error([&] { scene::random(r, std::nullopt, fading_kind::none, no_rcs).with_budget(link_budget{}); },
                         "class \"rock\"", "no rcs_dbsm");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_link_budget);
