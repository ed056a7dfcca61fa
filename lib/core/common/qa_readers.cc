// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: every reader of the core formats (mask, scene, frame settings) and the
 * block parameters refuse bad input with the path of the field and the problem:
 * integers that would wrap, unknown keys at every level, sizes beyond the limits,
 * floats beyond the float range, and the former silent fixes. */
#include "core/common/json_object.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/blocks/target_channel.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <string>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {
const std::string mask_head = R"({"format": "sems.pilot_mask", "version": 1, )";
const std::string scene_head = R"({"format": "sems.scene", "version": 1, )";
std::string car(const std::string& extra = "")
{
    return R"({"class": "car", "range_m": 10, "velocity_mps": 12)" + extra + "}";
}
std::string fixed_scene(const std::string& targets, const std::string& extra = "")
{
    return scene_head + R"("targets": [)" + targets + "]" + extra + "}";
}
} // namespace

class qa_readers : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_readers);
    CPPUNIT_TEST(integers_never_wrap);
    CPPUNIT_TEST(mask_rejects_unknown_keys_and_sizes);
    CPPUNIT_TEST(scene_rejects_unknown_keys_at_every_level);
    CPPUNIT_TEST(scene_sizes_are_bounded);
    CPPUNIT_TEST(scene_micro_doppler_needs_its_amplitude);
    CPPUNIT_TEST(frame_settings_are_bounded);
    CPPUNIT_TEST(floats_are_range_checked);
    CPPUNIT_TEST(reader_object_allows_what_it_reads);
    CPPUNIT_TEST(channel_refuses_clutter_ratio_without_clutter);
    CPPUNIT_TEST(fuzz_findings);
    CPPUNIT_TEST_SUITE_END();

public:
    void integers_never_wrap()
    {
        // 4294967328 = 2^32 + 32 used to load as 32.
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 4294967328, "n_subcarriers": 8, "pilots": [[0, 0]]})", "w.json"); },
                     "w.json: n_symbols: must be in [1, 65536]", "got 4294967328");
        // [4294967296, 5] used to load as [0, 5].
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 4, "n_subcarriers": 8, "pilots": [[4294967296, 5]]})", "p.json"); },
                     "p.json: pilots[0]: position [4294967296, 5] is outside the 4 x 8 grid");
        // Beyond int64: nlohmann reads it as unsigned; get<long long>() would give -1.
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 4, "n_subcarriers": 8, "pilots": [[18446744073709551615, 5]]})", "u.json"); },
                     "u.json: pilots[0]", "out of range");
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": -4294967295, "n_subcarriers": 8, "pilots": [[0, 0]]})", "n.json"); },
                     "n.json: n_symbols: must be in [1, 65536]");
        assert_error([] { scene::parse(scene_head + R"("random": {"targets": 4294967297}})", "s.json"); },
                     "s.json: random.targets: must be in [1, 256]", "4294967297");
        assert_error([] { scene::parse(fixed_scene(car(), R"(, "target_of_interest": 4294967296)"), "t.json"); },
                     "t.json: target_of_interest: must be in [0, 255]");
        assert_error([] { scene::parse(scene_head + R"("random": {}, "clutter": {"csr_db": 1, "paths": 4294967300}})", "c.json"); },
                     "c.json: clutter.paths: must be in [1, 4096]");
        assert_error([] { frame_settings::from_json(nlohmann::json::parse(R"({"n_symbols": 4294967328})"), "f.json"); },
                     "f.json: n_symbols: must be in [1, 65536]");
        assert_error([] { frame_settings::from_json(nlohmann::json::parse(R"({"cp_len": 9223372036854775808})"), "f.json"); },
                     "f.json: cp_len");
        // The version of any format, too.
        assert_error([] { pilot_mask::parse(R"({"format": "sems.pilot_mask", "version": 18446744073709551617})", "v.json"); },
                     "v.json: version");
    }

    void mask_rejects_unknown_keys_and_sizes()
    {
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 4, "n_subcarriers": 8, "pilots": [[0, 0]], "pilot_symbl": [1, 0]})", "k.json"); },
                     "k.json: pilot_symbl: unknown key", "pilot_symbol");
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 65536, "n_subcarriers": 65536, "pilots": [[0, 0]]})", "g.json"); },
                     "g.json: n_symbols * n_subcarriers", "exceeds the limit of 4194304");
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 1, "n_subcarriers": 2, "pilots": [[0, 0], [0, 1], [0, 0]]})", "l.json"); },
                     "l.json: pilots: lists 3 pilots, more than the N*M = 2 cells");
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 2, "n_subcarriers": 2, "pilots": [[0, 0]], "n_pilots": 18446744073709551615})", "np.json"); },
                     "np.json: n_pilots", "out of range");
        assert_error([] { pilot_mask::parse(R"([1, 2])", "a.json"); }, "a.json", "expected a JSON object");
        assert_error([] { pilot_mask::uniform(65536, 65536, 4); }, "exceeds the limit");
        // origin is free-form provenance: any content is kept.
        const auto m = pilot_mask::parse(mask_head + R"("n_symbols": 2, "n_subcarriers": 2, "pilots": [[0, 0]], "origin": {"kind": "x", "note": 1}})");
        CPPUNIT_ASSERT_EQUAL(1, m.size());
    }

    void scene_rejects_unknown_keys_at_every_level()
    {
        // The issue's example: a typo in a target was ignored.
        assert_error([] { scene::parse(fixed_scene(car(R"(, "powr": 1)")), "t.json"); },
                     "t.json: targets[0].powr: unknown key", "power");
        assert_error([] { scene::parse(fixed_scene(car() + "," + car(R"(, "micro_doppler": {"rate_hz": 1, "amplitude_m": 0.1, "phse_rad": 0})")), "m.json"); },
                     "m.json: targets[1].micro_doppler.phse_rad: unknown key");
        assert_error([] { scene::parse(fixed_scene(car(R"(, "paths": [{"excess_range_m": 0}, {"excess_range_m": 3, "pwr": 0.5}])")), "p.json"); },
                     "p.json: targets[0].paths[1].pwr: unknown key");
        assert_error([] { scene::parse(fixed_scene(car(), R"(, "clutter": {"csr_db": 3, "pahts": 2})"), "c.json"); },
                     "c.json: clutter.pahts: unknown key");
        assert_error([] { scene::parse(scene_head + R"("random": {"classes": ["car"], "target": 2}})", "r.json"); },
                     "r.json: random.target: unknown key", "targets");
        assert_error([] { scene::parse(scene_head + R"("random": {}, "colour": 1})", "j.json"); }, "j.json: colour: unknown key");
        // Wrong shapes name their path too.
        assert_error([] { scene::parse(fixed_scene(car(R"(, "micro_doppler": 3)")), "s.json"); },
                     "s.json: targets[0].micro_doppler: expected a JSON object");
        assert_error([] { scene::parse(fixed_scene(car(R"(, "paths": [1])")), "s.json"); },
                     "s.json: targets[0].paths[0]: expected a JSON object");
        assert_error([] { scene::parse(scene_head + R"("random": {}, "target_of_interest": 0})", "toi.json"); },
                     "toi.json: target_of_interest: applies to fixed scenes only");
        assert_error([] { scene::parse(fixed_scene(car(), R"(, "clutter": {"csr_db": 3, "ranges_m": [1, 2], "paths": 2})"), "both.json"); },
                     "both.json: clutter", "not both");
        // A scene written by to_json() reads back (the writer and the reader agree on every key).
        random_spec r;
        const auto s1 = scene::random(r, clutter_spec{});
        CPPUNIT_ASSERT(scene::parse(s1.to_json_string()).to_json() == s1.to_json());
        target_spec t;
        t.md = micro_doppler{ 10.0, 0.01, 0.5 };
        t.paths.push_back({ 5.0, 0.5 });
        clutter_spec c;
        c.ranges_m = { 3.0, 4.0 };
        const auto s2 = scene::fixed({ t, t }, c, 1);
        CPPUNIT_ASSERT(scene::parse(s2.to_json_string()).to_json() == s2.to_json());
    }

    void scene_sizes_are_bounded()
    {
        // The issue's example: 2e9 targets parsed, then a frame allocated without limit.
        assert_error([] { scene::parse(scene_head + R"("random": {"targets": 2000000000}})", "big.json"); },
                     "big.json: random.targets: must be in [1, 256], got 2000000000");
        assert_error([] { scene::parse(scene_head + R"("random": {"paths_per_target": 100000}})", "big.json"); },
                     "random.paths_per_target: must be in [1, 256]");
        std::string many;
        for (int i = 0; i < 257; ++i)
            many += (i ? "," : "") + car();
        assert_error([&] { scene::parse(fixed_scene(many), "many.json"); }, "many.json: targets: must have 0 to 256 entries, got 257");
        std::string paths = R"({"excess_range_m": 0})";
        for (int i = 0; i < 256; ++i)
            paths += R"(, {"excess_range_m": 1})";
        assert_error([&] { scene::parse(fixed_scene(car(R"(, "paths": [)" + paths + "]")), "paths.json"); },
                     "paths.json: targets[0].paths: must have 1 to 256 entries, got 257");
        std::string ranges = "0";
        for (int i = 0; i < 4096; ++i)
            ranges += ", 1";
        assert_error([&] { scene::parse(fixed_scene(car(), R"(, "clutter": {"csr_db": 1, "ranges_m": [)" + ranges + "]}"), "cl.json"); },
                     "cl.json: clutter.ranges_m: must have 1 to 4096 entries, got 4097");
        // The same bounds hold for scenes built in code.
        random_spec r;
        r.n_targets = 1000;
        assert_error([&] { scene::random(r); }, "random.targets: must be in [1, 256]");
        clutter_spec c;
        c.n_paths = 5000;
        assert_error([&] { scene::random(random_spec{}, c); }, "clutter.paths: must be in [1, 4096]");
        target_spec t;
        t.paths.assign(300, path_spec{});
        assert_error([&] { scene::fixed({ t }); }, "targets[0].paths", "limit of 256");
    }

    void scene_micro_doppler_needs_its_amplitude()
    {
        // Formerly the class table's amplitude was used silently: a scene that models
        // micro-Doppler now states its size, and the message gives the table's value.
        assert_error([] { scene::parse(fixed_scene(R"({"class": "drone", "range_m": 10, "velocity_mps": 1, "micro_doppler": {"rate_hz": 100}})"), "md.json"); },
                     "md.json: targets[0].micro_doppler.amplitude_m: missing", "\"drone\"");
        assert_error([] { scene::parse(fixed_scene(car(R"(, "micro_doppler": {"amplitude_m": 0.1})")), "md.json"); },
                     "md.json: targets[0].micro_doppler.rate_hz: missing");
    }

    void frame_settings_are_bounded()
    {
        assert_error([] { frame_settings::from_json(nlohmann::json::parse(R"({"n_symbol": 4})"), "f.json"); },
                     "f.json: n_symbol: unknown key", "n_symbols");
        assert_error([] { frame_settings::from_json(nlohmann::json::parse(R"({"n_symbols": 4096, "n_subcarriers": 4096})"), "f.json"); },
                     "f.json", "grid N*M = 16777216 exceeds the limit of 4194304");
        frame_settings fs;
        fs.n_symbols = 1 << 17;
        fs.n_subcarriers = 1 << 16;
        assert_error([&] { fs.validate(); }, "n_symbols must be in [1, 65536]");
        // grid_size() of an unvalidated struct throws instead of overflowing.
        assert_error([&] { (void)fs.grid_size(); }, "grid N*M = 8589934592 is out of range");
        fs.n_symbols = limits::max_symbols;
        fs.n_subcarriers = 64;
        CPPUNIT_ASSERT_EQUAL(limits::max_symbols * 64, fs.grid_size());
    }

    void floats_are_range_checked()
    {
        // A double beyond the float range was cast to float (undefined behaviour).
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 2, "n_subcarriers": 2, "pilots": [[0, 0]], "pilot_symbol": [1e39, 0]})", "f.json"); },
                     "f.json: pilot_symbol[0]: must be a finite number within the float range");
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 2, "n_subcarriers": 2, "pilots": [[0, 0]], "pilot_symbol": [0, -1e300]})", "f.json"); },
                     "f.json: pilot_symbol[1]");
        // A tiny value rounds to 0 as IEEE does, and a zero pilot symbol is refused.
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 2, "n_subcarriers": 2, "pilots": [[0, 0]], "pilot_symbol": [1e-50, 0]})", "z.json"); },
                     "z.json: pilot_symbol: must be finite and non-zero");
        CPPUNIT_ASSERT_EQUAL(3.0f, json_read::to_float(3.0, "x", "s"));
    }

    void reader_object_allows_what_it_reads()
    {
        // A key read through the reader is known automatically: new fields need no list.
        const auto j = nlohmann::json::parse(R"({"a": 1, "b": {"c": 2.5, "d": true}, "e": "x"})");
        json_read::object_reader r(j, "src");
        CPPUNIT_ASSERT_EQUAL(1, r.int_required("a", 0, 1));
        auto rb = r.object("b");
        CPPUNIT_ASSERT_EQUAL(2.5, rb.number("c"));
        assert_error([&] { rb.finish(); }, "src: b.d: unknown key (known here: c)");
        CPPUNIT_ASSERT(rb.boolean_or("d", false));
        rb.finish();
        assert_error([&] { r.finish(); }, "src: e: unknown key");
        CPPUNIT_ASSERT_EQUAL(std::string("x"), r.string_or("e", ""));
        r.finish();
        assert_error([&] { r.integer("a", 2, 5); }, "src: a: must be in [2, 5], got 1");
        assert_error([&] { r.number_in("a", 0, 3, 4); }, "src: a: must be in [3, 4], got 1");
        assert_error([&] { r.require("zz"); }, "src: zz: missing");
    }

    void channel_refuses_clutter_ratio_without_clutter()
    {
        // clutter_csr_db was dropped silently when clutter_paths is 0.
        assert_error([] { target_channel::make("", {}, 1, 1, true, "approaching", 0, 10.0); },
                     "clutter_csr_db = 10", "clutter_paths = 0");
        assert_error([] { target_channel::make("", {}, 1, 1, true, "approaching", 5000, 10.0); }, "clutter.paths: must be in [1, 4096]");
        assert_error([] { target_channel::make("", {}, 300); }, "random.targets: must be in [1, 256]");
        assert_error([] { target_channel::make("", {}, 1, 1, true, "approaching", 0, 0.0, 10.0, 0, 70000, 64); }, "n_symbols must be in [1, 65536]");
        CPPUNIT_ASSERT(target_channel::make("", {}, 1, 1, true, "approaching", 2, 10.0) != nullptr);
    }

    // Regression tests of what the fuzzers found (fuzz/corpus keeps the inputs too).
    void fuzz_findings()
    {
        // fuzz_mask: a number beyond double made nlohmann throw out_of_range, which escaped
        // as an exception that is not std::invalid_argument and named no file.
        assert_error([] { pilot_mask::parse(mask_head + R"("n_symbols": 32, "n_subcarriers": 61e394, "pilots": [[0, 0]]})", "o.json"); },
                     "o.json: not valid JSON", "number overflow");
        assert_error([] { scene::parse(scene_head + R"("random": {"path_power_decay_db": -1e400}})", "o.json"); },
                     "o.json: not valid JSON");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_readers);
