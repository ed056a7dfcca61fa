// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: super-frame masks — F = 1 is the ordinary mask file bit for bit, F sets round-trip
 * with their energies and phases, a frame picks set f mod F, and every mismatch (count, F,
 * grid, symbol, size) is refused naming both values. */
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/frame/super_frame_mask.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {
const std::string small_mask_head = R"({"format": "sems.pilot_mask", "version": 1, "n_symbols": 4, "n_subcarriers": 8, )";

std::string file_text(const std::string& path)
{
    std::ifstream in(path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}
} // namespace

class qa_super_frame_mask : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_super_frame_mask);
    CPPUNIT_TEST(one_frame_is_the_ordinary_mask);
    CPPUNIT_TEST(sets_round_trip);
    CPPUNIT_TEST(frames_pick_their_set);
    CPPUNIT_TEST(repeated_mask);
    CPPUNIT_TEST(mismatches_are_refused_naming_both_values);
    CPPUNIT_TEST(bad_files_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    // Every shipped bundle's mask reads as F = 1 and writes back the same JSON as the mask reader.
    void one_frame_is_the_ordinary_mask()
    {
        const char* src = std::getenv("SEMS_SOURCE_DIR");
        CPPUNIT_ASSERT_MESSAGE("SEMS_SOURCE_DIR must point at the source tree", src != nullptr);
        for (const char* bundle : { "classifier", "classifier_kinematic", "delay_single", "classifier_sdr_2g4" }) {
            const std::string path = std::string(src) + "/models/" + bundle + "/mask.json";
            const auto one = pilot_mask::load(path);
            const auto sf = super_frame_mask::load(path);
            CPPUNIT_ASSERT_EQUAL(1, sf.n_frames());
            CPPUNIT_ASSERT(sf.set(0) == one);
            CPPUNIT_ASSERT(&sf.for_frame(12345) == &sf.set(0));
            CPPUNIT_ASSERT_EQUAL(one.to_json().dump(), sf.to_json().dump());
            // and a file written from it is the mask reader's file, byte for byte
            const std::string a = "qa_sfm_one_a.json", b = "qa_sfm_one_b.json";
            one.save(a);
            sf.save(b);
            CPPUNIT_ASSERT_EQUAL(file_text(a), file_text(b));
            std::remove(a.c_str());
            std::remove(b.c_str());
        }
        const super_frame_mask wrapped(pilot_mask::doppler(4, 8, 8));
        CPPUNIT_ASSERT_EQUAL(pilot_mask::doppler(4, 8, 8).to_json().dump(), wrapped.to_json().dump());
    }

    void sets_round_trip()
    {
        std::vector<pilot_mask> sets;
        sets.push_back(pilot_mask::doppler(4, 8, 6));
        sets.push_back(pilot_mask::random(4, 8, 6, 7).with_phases("newman"));
        sets.push_back(pilot_mask(4, 8, { { 0, 1 }, { 0, 2 }, { 1, 3 }, { 2, 4 }, { 3, 5 }, { 3, 7 } },
                                  gr_complex(1, 0), { { "kind", "explicit" } }, "set 2",
                                  { 0.5, 1.5, 1.0, 1.0, 0.5, 1.5 }));
        const super_frame_mask sf(sets, { { "kind", "learned" }, { "note", "test" } });
        CPPUNIT_ASSERT_EQUAL(3, sf.n_frames());
        CPPUNIT_ASSERT_EQUAL(6, sf.pilots_per_frame());
        const std::string path = "qa_sfm_sets.json";
        sf.save(path);
        const auto back = super_frame_mask::load(path);
        std::remove(path.c_str());
        CPPUNIT_ASSERT(back == sf);
        CPPUNIT_ASSERT_EQUAL(sf.to_json().dump(), back.to_json().dump());
        CPPUNIT_ASSERT_EQUAL(std::string("learned"), back.origin()["kind"].get<std::string>());
        CPPUNIT_ASSERT_EQUAL(std::string("newman"), back.set(1).phase_sequence());
        CPPUNIT_ASSERT(!back.set(2).equal_power());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.5, back.set(2).power()[1], 0.0);
        CPPUNIT_ASSERT_EQUAL(3, back.to_json()["n_frames"].get<int>());
        CPPUNIT_ASSERT(!back.to_json().contains("pilots")); // the sets hold them
    }

    void frames_pick_their_set()
    {
        std::vector<pilot_mask> sets;
        for (int f = 0; f < 5; ++f)
            sets.push_back(pilot_mask::random(4, 8, 3, 100 + f));
        const super_frame_mask sf(sets);
        for (uint64_t frame : { 0ULL, 1ULL, 4ULL, 5ULL, 9ULL, 1000001ULL, ~0ULL })
            CPPUNIT_ASSERT(sf.for_frame(frame) == sets[frame % 5]);
        CPPUNIT_ASSERT_THROW(sf.set(5), std::out_of_range);
    }

    void repeated_mask()
    {
        const auto m = pilot_mask::staggered(4, 8, 8);
        const auto sf = super_frame_mask::repeated(m, 4);
        CPPUNIT_ASSERT_EQUAL(4, sf.n_frames());
        for (int f = 0; f < 4; ++f)
            CPPUNIT_ASSERT(sf.set(f) == m);
        CPPUNIT_ASSERT_EQUAL(std::string("repeated"), sf.origin()["kind"].get<std::string>());
        assert_error([&] { super_frame_mask::repeated(m, 0); }, "frames", "got 0");
        assert_error([&] { super_frame_mask::repeated(m, limits::max_super_frames + 1); }, "frames",
                     std::to_string(limits::max_super_frames));
    }

    void mismatches_are_refused_naming_both_values()
    {
        assert_error([] { super_frame_mask({ pilot_mask::doppler(4, 8, 4), pilot_mask::doppler(4, 8, 5) }); },
                     "frames[1]", "has 5 pilots but frames[0] has 4");
        assert_error([] { super_frame_mask({ pilot_mask::doppler(4, 8, 4), pilot_mask::doppler(8, 8, 4) }); },
                     "frames[1]", "8 x 8 grid but frames[0] is 4 x 8");
        assert_error(
            [] {
                super_frame_mask({ pilot_mask::doppler(4, 8, 1),
                                   pilot_mask(4, 8, { { 0, 0 } }, gr_complex(0, 1)) });
            },
            "frames[1]", "pilot symbol");
        const super_frame_mask sf({ pilot_mask::doppler(4, 8, 4), pilot_mask::burst(4, 8, 4) });
        assert_error([&] { sf.check_shape(4, 4, "decoder", "the bundle"); }, "F = 2",
                     "the bundle expects F = 4");
        assert_error([&] { sf.check_shape(2, 6, "decoder", "the bundle"); }, "has 4 pilots per frame",
                     "expects 6");
        sf.check_shape(2, 4, "decoder", "the bundle"); // the same shape passes
        frame_settings fs;
        fs.n_symbols = 4;
        fs.n_subcarriers = 8;
        fs.guard_subcarriers = { 7 };
        const super_frame_mask guarded({ pilot_mask::doppler(4, 8, 4), pilot_mask(4, 8, { { 0, 7 }, { 1, 1 }, { 2, 2 }, { 3, 3 } }) });
        assert_error([&] { guarded.check_frame(fs, "mapper"); }, "super-frame set 1", "guard subcarrier 7");
    }

    void bad_files_are_refused()
    {
        // Sets of one super-frame share their pilot symbol: both values are named.
        assert_error([] { super_frame_mask({ pilot_mask(4, 8, { { 0, 0 } }), pilot_mask(4, 8, { { 1, 1 } }, gr_complex(0.0f, 1.0f)) }, {}, "sf"); },
                     "frames[1]", "has the pilot symbol (0,1) but frames[0] has (1,0)");
        const std::string two = R"("frames": [{"pilots": [[0, 0], [1, 1]]}, {"pilots": [[2, 2], [3, 3]]}]})";
        super_frame_mask::parse(small_mask_head + two, "ok.json"); // well formed
        assert_error([&] { pilot_mask::parse(small_mask_head + two, "sf.json"); }, "sf.json", "super_frame_mask");
        assert_error([] { super_frame_mask::parse(small_mask_head + R"("frames": []})", "sf.json"); }, "sf.json: frames",
                     "got 0");
        assert_error([] { super_frame_mask::parse(small_mask_head + R"("frames": {"pilots": []}})", "sf.json"); },
                     "sf.json: frames", "a list");
        assert_error(
            [] {
                super_frame_mask::parse(small_mask_head + R"("n_frames": 3, "frames": [{"pilots": [[0, 0]]}, {"pilots": [[1, 1]]}]})",
                                        "sf.json");
            },
            "n_frames", "declares 3 frames but the list has 2");
        assert_error(
            [] {
                super_frame_mask::parse(small_mask_head + R"("frames": [{"pilots": [[0, 0]]}, {"pilots": [[9, 1]]}]})", "sf.json");
            },
            "sf.json (frames[1])", "outside the 4 x 8 grid");
        assert_error(
            [] {
                super_frame_mask::parse(
                    small_mask_head + R"("frames": [{"pilots": [[0, 0]]}, {"pilots": [[1, 1]], "n_symbols": 4}]})", "sf.json");
            },
            "frames[1].n_symbols", "belongs to the file");
        assert_error(
            [] {
                super_frame_mask::parse(small_mask_head + R"("frames": [{"pilots": [[0, 0]]}, {"pilots": [[1, 1], [2, 2]]}]})",
                                        "sf.json");
            },
            "has 2 pilots but frames[0] has 1");
        assert_error(
            [] {
                super_frame_mask::parse(small_mask_head + R"("frames": [{"pilots": [[0, 0]]}, {"pilots": [[1, 1]], "powr": [1]}]})",
                                        "sf.json");
            },
            "frames[1]", "powr");
        assert_error([] { super_frame_mask::parse(small_mask_head + R"("frames": [[0, 0]]})", "sf.json"); }, "frames[0]",
                     "JSON object");
        assert_error([] { super_frame_mask::parse(small_mask_head + R"("frames": [{"pilots": [[0, 0]]}], "pilots": [[1, 1]]})",
                                                  "sf.json"); },
                     "sf.json: pilots", "unknown key");
        std::string many = small_mask_head + R"("frames": [)";
        for (int f = 0; f <= limits::max_super_frames; ++f)
            many += std::string(f ? ", " : "") + R"({"pilots": [[0, 0]]})";
        assert_error([&] { super_frame_mask::parse(many + "]}", "sf.json"); }, "frames",
                     std::to_string(limits::max_super_frames));
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_super_frame_mask);
