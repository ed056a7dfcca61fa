// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: scenes — file round trip, random draws from the class table, validation. */
#include <gnuradio/sems/core/channel_model.h>
#include <gnuradio/sems/core/scene.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cstdio>
#include <string>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {
const std::string head = R"({"format": "sems.scene", "version": 1, )";
} // namespace

class qa_scene : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_scene);
    CPPUNIT_TEST(fixed_round_trip);
    CPPUNIT_TEST(random_round_trip);
    CPPUNIT_TEST(random_draws_follow_class_table);
    CPPUNIT_TEST(micro_doppler_off_means_no_md_paths);
    CPPUNIT_TEST(malformed_scenes_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    void fixed_round_trip()
    {
        const std::string text = head + R"("fading": "none", "target_of_interest": 1, "targets": [
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
        auto s = scene::parse(head + R"("random": {"classes": ["car", "drone"], "paths_per_target": 3,
            "excess_range_m": [5, 20]}, "clutter": {"csr_db": 0, "paths": 2, "range_m": [10, 100]}})");
        CPPUNIT_ASSERT(s.is_random());
        CPPUNIT_ASSERT_EQUAL(s.to_json().dump(), scene::parse(s.to_json_string()).to_json().dump());
        CPPUNIT_ASSERT_EQUAL(size_t(2), s.label_classes().size());
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

    void malformed_scenes_are_refused()
    {
        assert_error([] { scene::parse("{", "a.json"); }, "a.json: not valid JSON");
        assert_error([] { scene::parse(head + R"("targets": []})", "b.json"); }, "b.json: targets: a fixed scene needs");
        assert_error([] { scene::parse(head + R"("targets": [{"class": "tank", "range_m": 1, "velocity_mps": 1}]})",
                                       "c.json"); },
                     "unknown target class \"tank\"");
        assert_error([] { scene::parse(head + R"("targets": [{"class": "car", "range_m": -1, "velocity_mps": 1}]})",
                                       "d.json"); },
                     "d.json: targets[0].range_m: must be a finite number >= 0");
        assert_error([] { scene::parse(head + R"("targets": [{"class": "car", "range_m": 1}]})", "e.json"); },
                     "velocity_mps: missing");
        assert_error([] { scene::parse(head + R"("target_of_interest": 2, "targets": [{"class": "car", "range_m": 1, "velocity_mps": 1}]})",
                                       "f.json"); },
                     "target_of_interest: is 2 but the scene has 1 targets");
        assert_error([] { scene::parse(head + R"("random": {}, "targets": []})", "g.json"); }, "exactly one of");
        assert_error([] { scene::parse(head + R"("random": {"classes": []}})", "h.json"); }, "needs at least one class");
        assert_error([] { scene::parse(head + R"("random": {}, "fading": "rician"})", "i.json"); }, "fading");
        assert_error([] { scene::parse(head + R"("random": {}, "colour": 1})", "j.json"); }, "j.json: colour: unknown key");
        assert_error([] { scene::parse(head + R"("random": {}, "clutter": {"csr_db": "x"}})", "k.json"); },
                     "clutter.csr_db: expected a number");
        assert_error([] { scene::load("/nonexistent/scene.json"); }, "cannot open");
        // The frame decides what fits: a target beyond the unambiguous range is refused, not folded.
        assert_error([] { channel_model(frame_settings{}, scene::parse(head + R"("targets": [{"class": "car", "range_m": 400, "velocity_mps": 1}]})"), 0); },
                     "beyond the unambiguous range");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_scene);
