// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: scenes — file round trip, random draws from the class table (both headings),
 * validation. */
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/scene.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>
#include <string>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {
const std::string scene_json_head = R"({"format": "sems.scene", "version": 1, )";
} // namespace

class qa_scene : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_scene);
    CPPUNIT_TEST(fixed_round_trip);
    CPPUNIT_TEST(random_round_trip);
    CPPUNIT_TEST(random_draws_follow_class_table);
    CPPUNIT_TEST(micro_doppler_off_means_no_md_paths);
    CPPUNIT_TEST(any_heading_draws_speed_times_cos_uniform_angle);
    CPPUNIT_TEST(malformed_scenes_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    void fixed_round_trip()
    {
        const std::string text = scene_json_head + R"("fading": "none", "target_of_interest": 1, "targets": [
            {"class": "car", "range_m": 80, "velocity_mps": 15},
            {"class": "drone", "range_m": 50, "velocity_mps": 7, "power": 2,
             "micro_doppler": {"rate_hz": 100, "amplitude_m": 0.01, "phase_rad": 0.5},
             "paths": [{"excess_range_m": 0, "power": 1}, {"excess_range_m": 12, "power": 0.3}]}],
            "clutter": {"csr_db": 10, "ranges_m": [20, 40]}})";
        auto s = scene::parse(text, "fixed.json");
        CPPUNIT_ASSERT(!s.is_random());
        CPPUNIT_ASSERT_EQUAL(1, s.target_of_interest());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.01, s.targets()[1].md->amplitude_m, 1e-15);
        const std::string path = "qa_scene_roundtrip.json";
        s.save(path);
        auto back = scene::load(path);
        std::remove(path.c_str());
        CPPUNIT_ASSERT_EQUAL(s.to_json().dump(), back.to_json().dump());
        channel_model cm(frame_settings{}, back, 1);
        auto r = cm.draw(3);
        CPPUNIT_ASSERT_EQUAL(std::string("drone"), r.truth.class_name);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(50.0, r.truth.range_m, 0.0);
        CPPUNIT_ASSERT_EQUAL(5, r.truth.n_paths); // 1 + 2 target paths, 2 clutter
        CPPUNIT_ASSERT_EQUAL(uint64_t(3), r.truth.frame);
    }

    void random_round_trip()
    {
        auto s = scene::parse(scene_json_head + R"("random": {"classes": ["car", "drone"], "paths_per_target": 3,
            "excess_range_m": [5, 20]}, "clutter": {"csr_db": 0, "paths": 2, "range_m": [10, 100]}})");
        CPPUNIT_ASSERT(s.is_random());
        CPPUNIT_ASSERT_EQUAL(s.to_json().dump(), scene::parse(s.to_json_string()).to_json().dump());
        CPPUNIT_ASSERT_EQUAL(size_t(2), s.label_classes().size());
        // The heading: written always, "approaching" by default, "any" read back.
        CPPUNIT_ASSERT_EQUAL(std::string("approaching"), s.to_json()["random"]["heading"].get<std::string>());
        auto any = scene::parse(scene_json_head + R"("random": {"heading": "any"}})");
        CPPUNIT_ASSERT(any.random_settings()->heading == heading_kind::any);
        CPPUNIT_ASSERT_EQUAL(any.to_json().dump(), scene::parse(any.to_json_string()).to_json().dump());
    }

    void random_draws_follow_class_table()
    {
        channel_model cm(frame_settings{}, scene::random(random_spec{}), 5);
        const frame_settings fs;
        int counts[3] = { 0, 0, 0 };
        for (int f = 0; f < 3000; ++f) {
            auto r = cm.draw(f);
            const auto& spec = class_info(r.truth.class_id);
            counts[r.truth.class_id]++;
            CPPUNIT_ASSERT(r.truth.range_m >= spec.range_min_m && r.truth.range_m <= spec.range_max_m);
            CPPUNIT_ASSERT(r.truth.velocity_mps >= spec.speed_min_mps && r.truth.velocity_mps <= spec.speed_max_mps);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(r.truth.delay_s * fs.bandwidth_hz, r.truth.delay_index, 1e-9);
            const auto& p = r.paths[0];
            if (spec.has_micro_doppler()) {
                CPPUNIT_ASSERT(p.md_rate_hz >= spec.md_rate_min_hz && p.md_rate_hz <= spec.md_rate_max_hz);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(spec.md_amplitude_m, p.md_amplitude_m, 0.0);
            } else {
                CPPUNIT_ASSERT_EQUAL(0.0, p.md_rate_hz);
            }
        }
        for (int c : counts) // uniform over 3 classes: 1000 ± 3·26
            CPPUNIT_ASSERT(c > 900 && c < 1100);
    }

    void micro_doppler_off_means_no_md_paths()
    {
        random_spec spec;
        spec.micro_doppler = false;
        channel_model cm(frame_settings{}, scene::random(spec), 6);
        for (int f = 0; f < 200; ++f)
            for (const auto& p : cm.draw(f).paths)
                CPPUNIT_ASSERT_EQUAL(0.0, p.md_rate_hz);
    }

    void any_heading_draws_speed_times_cos_uniform_angle()
    {
        // Cars: speed s ~ U[10, 20], radial velocity v = s·cos θ with θ ~ U[0, 2π).
        random_spec spec;
        spec.classes = { target_class::car };
        spec.heading = heading_kind::any;
        channel_model cm(frame_settings{}, scene::random(spec), 8);
        const int n = 20000;
        std::vector<double> v(n);
        for (int f = 0; f < n; ++f)
            v[f] = cm.draw(f).truth.velocity_mps;
        // Both signs, and never faster than the class allows.
        const double positive = std::count_if(v.begin(), v.end(), [](double x) { return x > 0; }) / double(n);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.5, positive, 0.015); // sd 0.0035
        for (double x : v)
            CPPUNIT_ASSERT(std::fabs(x) <= 20.0);
        // Moments: E[v] = 0, E[v²] = E[s²]/2 = (20³ - 10³)/(3·10)/2 = 116.67 (sd 0.076 and 0.69).
        double m1 = 0, m2 = 0;
        for (double x : v) {
            m1 += x / n;
            m2 += x * x / n;
        }
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, m1, 0.35);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(7000.0 / 60.0, m2, 3.0);
        // Kolmogorov–Smirnov against F(x) = E_s[P(cos θ <= x/s)] = E_s[1 - acos(clamp(x/s))/π].
        std::sort(v.begin(), v.end());
        auto cdf = [](double x) {
            const int k = 2000;
            double sum = 0;
            for (int i = 0; i < k; ++i) {
                const double s = 10.0 + 10.0 * (i + 0.5) / k;
                sum += 1.0 - std::acos(std::clamp(x / s, -1.0, 1.0)) / M_PI;
            }
            return sum / k;
        };
        double d = 0;
        for (int i = 0; i < n; i += 7) { // every 7th order statistic: enough for the sup
            const double f = cdf(v[i]);
            d = std::max({ d, std::fabs(f - double(i) / n), std::fabs(f - double(i + 1) / n) });
        }
        CPPUNIT_ASSERT_MESSAGE("KS distance " + std::to_string(d), d < 1.63 / std::sqrt(double(n))); // 1 % level
        // Approaching (the default): the same frames' speeds, all positive.
        spec.heading = heading_kind::approaching;
        channel_model ap(frame_settings{}, scene::random(spec), 8);
        for (int f = 0; f < 2000; ++f) {
            const double x = ap.draw(f).truth.velocity_mps;
            CPPUNIT_ASSERT(x >= 10.0 && x <= 20.0);
        }
        CPPUNIT_ASSERT(heading_from_name("any") == heading_kind::any);
        CPPUNIT_ASSERT_EQUAL(std::string("approaching"), heading_name(heading_kind::approaching));
        assert_error([] { heading_from_name("sideways"); }, "unknown heading \"sideways\"", "approaching, any");
    }

    void malformed_scenes_are_refused()
    {
        assert_error([] { scene::parse(scene_json_head + R"("random": {"heading": "north"}})", "l.json"); },
                     "l.json: random.heading", "north");
        assert_error([] { scene::parse("{", "a.json"); }, "a.json: not valid JSON");
        assert_error([] { scene::parse(scene_json_head + R"("targets": []})", "b.json"); }, "b.json: targets: a fixed scene needs");
        assert_error([] { scene::parse(scene_json_head + R"("targets": [{"class": "tank", "range_m": 1, "velocity_mps": 1}]})",
                                       "c.json"); },
                     "unknown target class \"tank\"");
        assert_error([] { scene::parse(scene_json_head + R"("targets": [{"class": "car", "range_m": -1, "velocity_mps": 1}]})",
                                       "d.json"); },
                     "d.json: targets[0].range_m: must be a finite number >= 0");
        assert_error([] { scene::parse(scene_json_head + R"("targets": [{"class": "car", "range_m": 1}]})", "e.json"); },
                     "velocity_mps: missing");
        assert_error([] { scene::parse(scene_json_head + R"("target_of_interest": 2, "targets": [{"class": "car", "range_m": 1, "velocity_mps": 1}]})",
                                       "f.json"); },
                     "target_of_interest: is 2 but the scene has 1 targets");
        assert_error([] { scene::parse(scene_json_head + R"("random": {}, "targets": []})", "g.json"); }, "exactly one of");
        assert_error([] { scene::parse(scene_json_head + R"("random": {"classes": []}})", "h.json"); }, "needs at least one class");
        assert_error([] { scene::parse(scene_json_head + R"("random": {}, "fading": "rician"})", "i.json"); }, "fading");
        assert_error([] { scene::parse(scene_json_head + R"("random": {}, "colour": 1})", "j.json"); }, "j.json: colour: unknown key");
        assert_error([] { scene::parse(scene_json_head + R"("random": {}, "clutter": {"csr_db": "x"}})", "k.json"); },
                     "clutter.csr_db: expected a number");
        assert_error([] { scene::load("/nonexistent/scene.json"); }, "cannot open");
        // The frame decides what fits: a target beyond the unambiguous range is refused, not folded.
        assert_error([] { channel_model(frame_settings{}, scene::parse(scene_json_head + R"("targets": [{"class": "car", "range_m": 400, "velocity_mps": 1}]})"), 0); },
                     "beyond the unambiguous range");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_scene);
