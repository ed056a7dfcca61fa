// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: frames as data — guard subcarriers, frame files, the field-by-field comparison,
 * and masks that keep off the guards. */
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <string>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;
using json = nlohmann::json;

namespace {
frame_settings guarded(int n, int m, std::vector<int> guards)
{
    frame_settings fs;
    fs.n_symbols = n;
    fs.n_subcarriers = m;
    fs.cp_len = 0;
    fs.guard_subcarriers = std::move(guards);
    fs.validate();
    return fs;
}
} // namespace

class qa_frames : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_frames);
    CPPUNIT_TEST(guards_read_and_write);
    CPPUNIT_TEST(bad_guards_are_refused);
    CPPUNIT_TEST(paper_frame_json_is_unchanged);
    CPPUNIT_TEST(first_difference_names_field_and_values);
    CPPUNIT_TEST(frame_files);
    CPPUNIT_TEST(mask_on_a_guard_is_refused);
    CPPUNIT_TEST(patterns_avoid_guards);
    CPPUNIT_TEST(presets_and_their_class_libraries);
    CPPUNIT_TEST_SUITE_END();

public:
    void guards_read_and_write()
    {
        const auto fs = frame_settings::from_json(
            json::parse(R"({"n_subcarriers": 16, "guard_subcarriers": [[0, 2], 8, [14, 15]]})"), "g.json");
        CPPUNIT_ASSERT((fs.guard_subcarriers == std::vector<int>{ 0, 1, 2, 8, 14, 15 }));
        CPPUNIT_ASSERT((fs.usable_subcarriers() == std::vector<int>{ 3, 4, 5, 6, 7, 9, 10, 11, 12, 13 }));
        CPPUNIT_ASSERT_EQUAL(32LL * 10, fs.usable_elements());
        CPPUNIT_ASSERT(fs.is_guard(8) && !fs.is_guard(9));
        // Runs of three or more are written as [first, last]; the round trip is exact.
        CPPUNIT_ASSERT_EQUAL(std::string(R"([[0,2],8,14,15])"), fs.to_json()["guard_subcarriers"].dump());
        CPPUNIT_ASSERT(frame_settings::from_json(fs.to_json(), "round trip") == fs);
    }

    void bad_guards_are_refused()
    {
        auto read = [](const std::string& text) { frame_settings::from_json(json::parse(text), "g.json"); };
        assert_error([&] { read(R"({"n_subcarriers": 16, "guard_subcarriers": [16]})"); },
                     "g.json: guard_subcarriers[0]", "must be in [0, 15]");
        assert_error([&] { read(R"({"n_subcarriers": 16, "guard_subcarriers": [-1]})"); }, "guard_subcarriers[0]");
        assert_error([&] { read(R"({"n_subcarriers": 16, "guard_subcarriers": [[0, 3], 2]})"); },
                     "guard_subcarriers[1]", "subcarrier 2 is listed twice");
        assert_error([&] { read(R"({"n_subcarriers": 16, "guard_subcarriers": [[5, 3]]})"); }, "first <= last");
        assert_error([&] { read(R"({"n_subcarriers": 16, "guard_subcarriers": [[1, 2, 3]]})"); }, "[first, last]");
        assert_error([&] { read(R"({"n_subcarriers": 16, "guard_subcarriers": 3})"); }, "expected a list");
        assert_error([&] { read(R"({"n_subcarriers": 4, "cp_len": 0, "guard_subcarriers": [[0, 3]]})"); },
                     "all 4 subcarriers are guards");
        frame_settings fs;
        fs.guard_subcarriers = { 5, 3 };
        assert_error([&] { fs.validate(); }, "ascending");
        fs.guard_subcarriers = { 3, 3 };
        assert_error([&] { fs.validate(); }, "subcarrier 3 is listed twice");
        fs.guard_subcarriers = { 64 };
        assert_error([&] { fs.validate(); }, "subcarrier 64 is outside [0, n_subcarriers - 1 = 63]");
    }

    void paper_frame_json_is_unchanged()
    {
        // A frame without guards writes exactly the six keys it always wrote (bundles stay byte-identical).
        const auto j = frame_settings{}.to_json();
        CPPUNIT_ASSERT_EQUAL(size_t(6), j.size());
        CPPUNIT_ASSERT(!j.contains("guard_subcarriers"));
    }

    void first_difference_names_field_and_values()
    {
        frame_settings a, b;
        CPPUNIT_ASSERT(!a.first_difference(b));
        CPPUNIT_ASSERT(a == b);
        b.symbol_interval_s = 1.25e-4;
        b.cp_len = 4;
        const auto d = a.first_difference(b);
        CPPUNIT_ASSERT(d);
        CPPUNIT_ASSERT_EQUAL(std::string("symbol_interval_s"), d->field); // the first differing field
        CPPUNIT_ASSERT_EQUAL(std::string("0.001"), d->first);
        CPPUNIT_ASSERT_EQUAL(std::string("0.000125"), d->second);
        CPPUNIT_ASSERT(a != b);
        assert_error([&] { a.require_same(b, "classifier_sink", "the bundle's frame", "the stream's frame"); },
                     "classifier_sink: frame field symbol_interval_s differs: the bundle's frame has 0.001, "
                     "the stream's frame has 0.000125");
        // Every field, guards included, is compared.
        frame_settings c;
        c.guard_subcarriers = { 0 };
        assert_error([&] { a.require_same(c, "x", "A", "B"); }, "guard_subcarriers differs: A has none, B has [0]");
        for (auto set : std::vector<void (*)(frame_settings&)>{
                 [](frame_settings& f) { f.n_symbols = 16; }, [](frame_settings& f) { f.n_subcarriers = 32; },
                 [](frame_settings& f) { f.bandwidth_hz = 20e6; }, [](frame_settings& f) { f.carrier_hz = 2.4e9; },
                 [](frame_settings& f) { f.cp_len = 8; } }) {
            frame_settings e;
            set(e);
            CPPUNIT_ASSERT(a.first_difference(e));
        }
        frame_settings f;
        f.bandwidth_hz = 20e6;
        CPPUNIT_ASSERT_EQUAL(std::string("30000000"), a.first_difference(f)->first);
        CPPUNIT_ASSERT_EQUAL(std::string("20000000"), a.first_difference(f)->second);
    }

    void frame_files()
    {
        const auto f = frame_file::from_json(json::parse(R"({"format": "sems.frame", "version": 1, "name": "t",
            "description": "test", "classes": "kinematic",
            "frame": {"n_symbols": 8, "n_subcarriers": 16, "bandwidth_hz": 2e7, "carrier_hz": 2.4e9,
                      "symbol_interval_s": 1e-4, "cp_len": 4, "guard_subcarriers": [0, [7, 9]]}})"),
                                             "t.json");
        CPPUNIT_ASSERT_EQUAL(std::string("kinematic"), f.classes);
        CPPUNIT_ASSERT_EQUAL(4, static_cast<int>(f.frame.guard_subcarriers.size()));
        CPPUNIT_ASSERT(frame_file::from_json(f.to_json(), "again").frame == f.frame);
        assert_error([] { frame_file::from_json(json::parse(R"({"format": "sems.frame", "version": 1})"), "m.json"); },
                     "m.json: frame: missing");
        assert_error([] { frame_file::from_json(json::parse(R"({"format": "sems.frame", "version": 1, "frame": {},
                                                            "colour": 1})"), "k.json"); },
                     "k.json: colour: unknown key");
        assert_error([] { frame_file::from_json(json::parse(R"({"format": "sems.frame", "version": 1,
                                                            "frame": {"bandwidth_hz": -1}})"), "b.json"); },
                     "b.json: frame", "bandwidth_hz");
        assert_error([] { frame_file::from_json(json::parse(R"({"format": "sems.classes", "version": 1})"), "c.json"); },
                     "c.json: format", "sems.frame");
        // The built-in paper frame is the defaults; an unknown name lists where it was looked for.
        CPPUNIT_ASSERT(frame_file::find("paper").frame == frame_settings{});
        CPPUNIT_ASSERT(frame_file::find("").frame == frame_settings{});
        assert_error([] { frame_file::find("no_such_frame"); }, "frame \"no_such_frame\"", "SEMS_FRAMES_PATH");
    }

    void mask_on_a_guard_is_refused()
    {
        const auto fs = guarded(4, 8, { 0, 4 });
        pilot_mask ok(4, 8, { { 0, 1 }, { 3, 7 } });
        ok.check_frame(fs, "pilot_mapper"); // no pilot on a guard
        pilot_mask bad(4, 8, { { 0, 1 }, { 2, 4 } });
        assert_error([&] { bad.check_frame(fs, "pilot_mapper"); },
                     "pilot_mapper: pilot 1 at [2, 4] is on guard subcarrier 4 of the frame");
    }

    void patterns_avoid_guards()
    {
        const auto fs = guarded(8, 16, { 0, 1, 8, 15 });
        for (const std::string p : { "uniform", "random", "doppler" }) {
            const auto m = pilot_mask::from_pattern(p, fs, 24, 7);
            CPPUNIT_ASSERT_EQUAL(24, m.size());
            for (const auto& pos : m.positions())
                CPPUNIT_ASSERT_MESSAGE(p + " put a pilot on guard " + std::to_string(pos.m), !fs.is_guard(pos.m));
            m.check_frame(fs, p);
            // Every usable element: still no guard.
            const auto all = pilot_mask::from_pattern(p, fs, static_cast<int>(fs.usable_elements()), 7);
            CPPUNIT_ASSERT_EQUAL(static_cast<int>(fs.usable_elements()), all.size());
            all.check_frame(fs, p);
            assert_error([&] { pilot_mask::from_pattern(p, fs, static_cast<int>(fs.usable_elements()) + 1, 7); },
                         "do not fit the N*(M - guards) = 8*12 = 96 usable resource elements");
        }
        // Without guards the frame overload is the plain pattern, position for position.
        frame_settings paper;
        for (const std::string p : { "uniform", "random", "doppler" })
            CPPUNIT_ASSERT(pilot_mask::from_pattern(p, paper, 32, 3) == pilot_mask::from_pattern(p, 32, 64, 32, 3));
    }

    void presets_and_their_class_libraries()
    {
        // Found by name from the source tree; each preset's library fits it, and a channel
        // model combining them builds and draws.
        const char* src = std::getenv("SEMS_SOURCE_DIR");
        CPPUNIT_ASSERT_MESSAGE("SEMS_SOURCE_DIR must point at the source tree", src != nullptr);
        for (const std::string name : { "paper", "sdr_2g4_20mhz", "wifi_5g_80mhz", "nr_30khz", "nr_sensing_120khz", "auto_77g" }) {
            const auto f = frame_file::find(name);
            CPPUNIT_ASSERT_EQUAL(name, f.name);
            CPPUNIT_ASSERT_MESSAGE(name, !f.classes.empty());
            const auto lib = class_library::find(f.classes);
            frame_settings small = f.frame;
            small.n_symbols = std::min(small.n_symbols, 4); // the draw only needs to run
            random_spec every;
            every.classes.clear(); // every class of the library
            channel_model cm(small, scene::random(every, std::nullopt, fading_kind::rayleigh, lib), 1);
            for (uint64_t k = 0; k < 8; ++k)
                CPPUNIT_ASSERT(!cm.draw(k).paths.empty());
            // Its array: neighbouring receive elements half the carrier's wavelength apart (no
            // grating lobe over the whole half space), and a scene of the two draws per element.
            CPPUNIT_ASSERT_MESSAGE(name, !f.array.empty());
            const auto a = array_geometry::find(f.array);
            double nearest = std::numeric_limits<double>::infinity();
            for (size_t i = 0; i < a.receive().size(); ++i)
                for (size_t k = i + 1; k < a.receive().size(); ++k) {
                    const auto& p = a.receive()[i];
                    const auto& q = a.receive()[k];
                    nearest = std::min(nearest, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
                }
            CPPUNIT_ASSERT_DOUBLES_EQUAL_MESSAGE(name + " / " + f.array, 0.5 * f.frame.wavelength_m(), nearest,
                                                 1e-5 * f.frame.wavelength_m());
            channel_model arrayed(small, scene::random(every, std::nullopt, fading_kind::rayleigh, lib).with_array(a), 1);
            CPPUNIT_ASSERT_EQUAL(a.n_receive() * a.n_transmit(), arrayed.n_elements());
            std::vector<gr_complex> h(static_cast<size_t>(small.n_symbols) * small.n_subcarriers);
            arrayed.factors(arrayed.draw(0), 0, arrayed.n_elements() - 1).fill(h.data());
        }
        // A preset is found by name from a scene too; an unknown name lists where it was looked for.
        CPPUNIT_ASSERT_EQUAL(12, scene::parse(R"({"format": "sems.scene", "version": 1, "array": "mimo3x4_77g",
            "targets": [{"class": "car", "range_m": 60, "velocity_mps": 8}]})").array()->n_receive() * 3);
        assert_error([] { scene::parse(R"({"format": "sems.scene", "version": 1, "array": "no_such_array",
            "targets": [{"class": "car", "range_m": 60, "velocity_mps": 8}]})", "s.json"); },
                     "s.json", "array \"no_such_array\": no such file (searched");
        // The paper's file is the built-in default.
        CPPUNIT_ASSERT(frame_file::load(std::string(src) + "/models/frames/paper.json").frame == frame_settings{});
        // A library that does not fit the frame is refused, naming the class and the limit:
        // the automotive car (40 m/s) beyond the paper frame's +-500 Hz at 3 GHz ...
        const auto automotive = class_library::find("automotive");
        random_spec car;
        car.classes = { static_cast<target_class>(automotive->id_of("car")) };
        assert_error([&] { channel_model(frame_settings{}, scene::random(car, std::nullopt, fading_kind::rayleigh, automotive), 1); },
                     "class car", "unambiguous");
        // ... and the urban car (1.5 km) beyond the automotive frame's 150 m.
        const auto urban = class_library::find("nr_urban");
        car.classes = { static_cast<target_class>(urban->id_of("car")) };
        assert_error([&] {
            channel_model(frame_file::find("auto_77g").frame,
                          scene::random(car, std::nullopt, fading_kind::rayleigh, urban), 1);
        },
                     "class car", "unambiguous range");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_frames);
