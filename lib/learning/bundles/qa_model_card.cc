// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: model cards (model_card.json) read back what was written, field for field; a
 * malformed card is refused naming the file and the field; a card made from a shipped bundle
 * finds its frame preset, pilots and retrain command; every shipped bundle's card reads and
 * describes its bundle. */
#include "qa/qa_files.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/learning/bundles/model_card.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <unistd.h>

using namespace gr::sems;
using gr::sems::qa::assert_error;
using nlohmann::json;

namespace {
using gr::sems::qa::models_dir;

// A complete card of a classifier (made by hand: no decoder runs).
model_card classifier_card()
{
    model_card c = model_card::of_bundle(model_bundle::load(models_dir() + "classifier"));
    c.summary = "which target it is";
    c.test.measured_by = "sems_eval --model-card";
    c.test.command = "sems_eval --model-card models/classifier";
    c.test.frames = "frames 0..1999";
    c.test.scene = "the bundle's training scene";
    c.test.seed = 1;
    model_card::snr_figures a, b;
    a.snr_db = 0;
    a.frames = 2000;
    a.accuracy = 0.891;
    b.snr_db = 10;
    b.frames = 2000;
    b.accuracy = 0.9865;
    c.test.by_snr = { a, b };
    c.speed.snr_db = 10;
    c.speed.frames = 256;
    c.speed.repeats = 3;
    c.speed.decoder_fps = 30000;
    c.speed.anchor = "frame generator";
    c.speed.anchor_fps = 12000;
    return c;
}

// The card's JSON with one edit, read back.
void read_edited(const std::function<void(json&)>& edit)
{
    json j = classifier_card().to_json();
    edit(j);
    model_card::from_json(j, "card.json");
}
} // namespace

class qa_model_card : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_model_card);
    CPPUNIT_TEST(round_trip);
    CPPUNIT_TEST(malformed_cards_are_refused);
    CPPUNIT_TEST(facts_of_shipped_bundles);
    CPPUNIT_TEST(shipped_cards_read);
    CPPUNIT_TEST_SUITE_END();

public:
    void round_trip()
    {
        const auto c = classifier_card();
        char tmpl[] = "/tmp/sems_qa_card_XXXXXX";
        const std::string dir = ::mkdtemp(tmpl);
        c.save(dir);
        const auto back = model_card::load(dir);
        CPPUNIT_ASSERT_EQUAL(c.to_json().dump(), back.to_json().dump());
        CPPUNIT_ASSERT_EQUAL(std::string("classifier"), back.bundle);
        CPPUNIT_ASSERT_EQUAL(std::string("paper"), back.frame_preset);
        CPPUNIT_ASSERT(back.frame == frame_settings{});
        CPPUNIT_ASSERT_EQUAL(0.9865, *back.cited().accuracy);
        CPPUNIT_ASSERT(!back.cited().mae_index);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(2.5, back.speed.ratio(), 1e-12);
        // A delay card with a frame that is no preset keeps the frame's settings.
        model_card d = model_card::of_bundle(model_bundle::load(models_dir() + "delay_single"));
        d.frame_preset.clear();
        d.frame.n_symbols = 16;
        d.test = c.test;
        for (auto& f : d.test.by_snr) {
            f.accuracy.reset();
            f.mae_index = 0.188;
            f.mae_m = 0.94;
            f.median_abs_error_index = 0.017;
        }
        d.speed = c.speed;
        const auto dback = model_card::from_json(d.to_json(), "delay card");
        CPPUNIT_ASSERT_EQUAL(d.to_json().dump(), dback.to_json().dump());
        CPPUNIT_ASSERT_EQUAL(16, dback.frame.n_symbols);
        CPPUNIT_ASSERT(dback.frame_preset.empty());
        CPPUNIT_ASSERT_EQUAL(0.188, *dback.cited().mae_index);
        std::filesystem::remove_all(dir);
    }

    void malformed_cards_are_refused()
    {
        read_edited([](json&) {}); // the unedited card reads
        assert_error([] { read_edited([](json& j) { j["format"] = "sems.model_bundle"; }); }, "card.json", "format");
        assert_error([] { read_edited([](json& j) { j.erase("summary"); }); }, "card.json: summary: missing");
        assert_error([] { read_edited([](json& j) { j["test"]["by_snr"][1]["accuracy"] = 98.65; }); },
                     "card.json: test.by_snr[1].accuracy: must be in [0, 1]");
        assert_error([] { read_edited([](json& j) { j["test"]["by_snr"][0]["mae_index"] = 0.2; }); },
                     "test.by_snr[0].mae_index", "does not belong to a classifier");
        assert_error([] { read_edited([](json& j) { j["cite_snr_db"] = 20; }); }, "card.json: cite_snr_db",
                     "no test.by_snr entry at 20");
        assert_error([] { read_edited([](json& j) { j["test"]["by_snr"][1]["snr_db"] = 0; }); },
                     "test.by_snr[1].snr_db", "listed twice");
        assert_error([] { read_edited([](json& j) { j["speed"]["anchor_fps"] = 0; }); }, "speed.anchor_fps");
        assert_error([] { read_edited([](json& j) { j["test"]["sede"] = 1; }); }, "test.sede: unknown key");
        assert_error([] { read_edited([](json& j) { j["frame"] = "no_such_frame"; }); }, "card.json: frame",
                     "no_such_frame");
        assert_error([] { read_edited([](json& j) { j["test"]["command"] = ""; }); }, "test.command: is empty");
        assert_error([] { model_card::load("/nonexistent/model_card.json"); }, "/nonexistent/model_card.json",
                     "cannot open");
    }

    void facts_of_shipped_bundles()
    {
        const auto d = model_card::of_bundle(model_bundle::load(models_dir() + "delay_single"));
        CPPUNIT_ASSERT(d.task == task_kind::delay);
        CPPUNIT_ASSERT_EQUAL(32, d.n_pilots);
        CPPUNIT_ASSERT_EQUAL(std::string("models/masks/one_symbol_random32.json"), d.mask);
        CPPUNIT_ASSERT_EQUAL(std::string("newman"), d.pilot_phases);
        CPPUNIT_ASSERT(d.classes.empty());
        CPPUNIT_ASSERT_EQUAL(std::string("training.command_line"), d.retrain_recorded);
        CPPUNIT_ASSERT(d.retrain_command.find("sems_train --from ") == 0);
        const auto s = model_card::of_bundle(model_bundle::load(models_dir() + "classifier_sdr_2g4"));
        CPPUNIT_ASSERT_EQUAL(std::string("sdr_2g4_20mhz"), s.frame_preset);
        CPPUNIT_ASSERT_EQUAL(std::string("learned"), s.mask);
        CPPUNIT_ASSERT_EQUAL(std::string("kinematic"), s.class_library);
        const auto t = model_card::of_bundle(model_bundle::load(models_dir() + "classifier_kinematic_track"));
        CPPUNIT_ASSERT_EQUAL(std::string("track.training.command_line"), t.retrain_recorded);
        CPPUNIT_ASSERT(t.retrain_command.empty()); // sems_train --from would retrain its frame classifier only
    }

    // Every shipped bundle has a card that this reader accepts and that describes that bundle
    // (models/README.md is generated from them).
    void shipped_cards_read()
    {
        int cards = 0;
        for (const auto& entry : std::filesystem::directory_iterator(models_dir())) {
            if (!std::filesystem::exists(entry.path() / "bundle.json"))
                continue;
            const auto b = model_bundle::load(entry.path().string());
            const auto c = model_card::load(entry.path().string());
            const std::string name = entry.path().filename().string();
            CPPUNIT_ASSERT_EQUAL(name, c.bundle);
            CPPUNIT_ASSERT_MESSAGE(name, c.task == b.task && c.n_pilots == b.mask.size() && c.frame == b.frame);
            CPPUNIT_ASSERT_MESSAGE(name, c.classes == b.class_names);
            CPPUNIT_ASSERT_EQUAL(name + ": " + c.test.measured_by, name + ": sems_eval --model-card");
            c.cited(); // the figure to cite is one of the measured ones
            ++cards;
        }
        CPPUNIT_ASSERT(cards >= 10);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_model_card);
