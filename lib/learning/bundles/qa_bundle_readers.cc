// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: bundle.json and the network settings refuse bad input with the path of
 * the field: unknown keys at every level, integers beyond their bounds, class names
 * that disagree with n_classes (and hence the weights), negative collision weights;
 * bundle_decoder refuses a batch holding a NaN or Inf frame, naming the frame. */
#include "qa/qa_files.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cstdlib>
#include <stdexcept>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;
using nlohmann::json;

namespace {
using gr::sems::qa::models_dir;

// A copy of a shipped bundle (mask and weights linked) whose bundle.json is edited by
// `edit`; returns the directory.
std::string edited_bundle(const std::string& name, const std::function<void(json&)>& edit)
{
    char tmpl[] = "/tmp/sems_qa_bundle_XXXXXX";
    const std::string dir = ::mkdtemp(tmpl);
    const std::string src = models_dir() + name + "/";
    json j = json::parse(std::ifstream(src + "bundle.json"));
    edit(j);
    std::ofstream(dir + "/bundle.json") << j.dump(1);
    CPPUNIT_ASSERT_EQUAL(0, ::symlink((src + "mask.json").c_str(), (dir + "/mask.json").c_str()));
    CPPUNIT_ASSERT_EQUAL(0, ::symlink((src + "decoder.pt").c_str(), (dir + "/decoder.pt").c_str()));
    return dir;
}

void load(const std::string& dir) { model_bundle::load(dir); }
} // namespace

class qa_bundle_readers : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_bundle_readers);
    CPPUNIT_TEST(shipped_bundles_load);
    CPPUNIT_TEST(class_names_agree_with_the_decoder);
    CPPUNIT_TEST(unknown_keys_at_every_level);
    CPPUNIT_TEST(integers_are_bounded);
    CPPUNIT_TEST(network_settings_are_strict);
    CPPUNIT_TEST(decoder_refuses_non_finite_frames);
    CPPUNIT_TEST(class_library_is_recorded);
    CPPUNIT_TEST_SUITE_END();

public:
    void shipped_bundles_load()
    {
        for (const char* name : { "classifier", "delay_single", "delay_multipath" })
            load(edited_bundle(name, [](json&) {}));
    }

    void class_names_agree_with_the_decoder()
    {
        // More names than classes, no n_classes: the sink used to read past the probabilities.
        auto d = edited_bundle("classifier", [](json& j) {
            j["class_names"].push_back("tank");
            j["decoder"]["settings"].erase("n_classes");
        });
        assert_error([&] { load(d); }, d + "/bundle.json: class_names: has 4 names but the decoder has 3 classes",
                     "by default");
        // Fewer names than classes: the answers were silently wrong.
        d = edited_bundle("classifier", [](json& j) { j["class_names"] = { "car", "drone" }; });
        assert_error([&] { load(d); }, "class_names: has 2 names but the decoder has 3 classes (decoder.settings.n_classes)");
        // n_classes that disagrees with the weights is refused when the weights are read
        // (bundle_decoder checks every tensor's shape); the names keep to n_classes here.
        d = edited_bundle("classifier", [](json& j) { j["class_names"] = { "car", "car", "drone" }; });
        assert_error([&] { load(d); }, "class_names[1]: \"car\" is listed twice");
        d = edited_bundle("classifier", [](json& j) { j["class_names"] = { "car", "", "drone" }; });
        assert_error([&] { load(d); }, "class_names[1]: is empty");
        d = edited_bundle("classifier", [](json& j) { j["class_names"] = { "car", 3, "drone" }; });
        assert_error([&] { load(d); }, "class_names[1]: expected a string");
        d = edited_bundle("delay_single", [](json& j) { j["class_names"] = { "car", "drone" }; });
        assert_error([&] { load(d); }, "class_names: a delay model has no classes");
    }

    void unknown_keys_at_every_level()
    {
        auto d = edited_bundle("classifier", [](json& j) { j["weight_file"] = "other.pt"; });
        assert_error([&] { load(d); }, d + "/bundle.json: weight_file: unknown key");
        d = edited_bundle("classifier", [](json& j) { j["decoder"]["setings"] = json::object(); });
        assert_error([&] { load(d); }, "bundle.json: decoder.setings: unknown key");
        d = edited_bundle("classifier", [](json& j) { j["decoder"]["settings"]["widht"] = 3; });
        assert_error([&] { load(d); }, "bundle.json: decoder.settings: widht: unknown key");
        d = edited_bundle("delay_single", [](json& j) { j["decoder"]["settings"]["windw"] = 3; });
        assert_error([&] { load(d); }, "bundle.json: decoder.settings: windw: unknown key");
        d = edited_bundle("classifier", [](json& j) { j["frame"]["n_symbol"] = 32; });
        assert_error([&] { load(d); }, "bundle.json: frame: n_symbol: unknown key");
        d = edited_bundle("classifier", [](json& j) { j["decoder"] = 3; });
        assert_error([&] { load(d); }, "bundle.json: decoder: expected a JSON object");
    }

    void integers_are_bounded()
    {
        auto d = edited_bundle("classifier", [](json& j) { j["n_pilots"] = 4294967328ULL; });
        assert_error([&] { load(d); }, "bundle.json: n_pilots: must be in [1, 4194304]");
        d = edited_bundle("classifier", [](json& j) {
            j["decoder"]["settings"]["n_classes"] = 2000;
        });
        assert_error([&] { load(d); }, "decoder.settings: n_classes: must be in [2, 1024], got 2000");
        d = edited_bundle("classifier", [](json& j) { j["decoder"]["settings"]["width"] = 4294967312ULL; });
        assert_error([&] { load(d); }, "decoder.settings: width: must be in [1, 1000000]");
        d = edited_bundle("classifier", [](json& j) { j["frame"]["n_subcarriers"] = 4294967360ULL; });
        assert_error([&] { load(d); }, "bundle.json: frame: n_subcarriers: must be in [1, 65536]");
        json names = json::array();
        for (int i = 0; i < 1025; ++i)
            names.push_back("c" + std::to_string(i));
        d = edited_bundle("classifier", [&](json& j) { j["class_names"] = names; });
        assert_error([&] { load(d); }, "class_names: must have 2 to 1024 entries, got 1025");
    }

    void network_settings_are_strict()
    {
        assert_error([] { nn::encoder_settings::from_json(json{ { "collision_weight", -1.0 } }, "enc"); },
                     "enc: collision_weight: must be >= 0");
        assert_error([] { nn::encoder_settings::from_json(json{ { "embeding", 4 } }, "enc"); },
                     "enc: embeding: unknown key", "embedding");
        assert_error([] { nn::encoder_settings::from_json(json{ { "factorized", 1 } }, "enc"); },
                     "enc: factorized: expected true or false");
        assert_error([] { nn::classifier_settings::from_json(json{ { "depth", -1 } }, "cls"); },
                     "cls: depth: must be in [0, 1000000], got -1");
        assert_error([] { nn::delay_settings::from_json(json{ { "q", 18446744073709551615ULL } }, "dl"); },
                     "dl: q: must be in [2, 1000000]");
        assert_error([] { nn::reconstruction_settings::from_json(json{ { "hiden", 3 } }, "rec"); },
                     "rec: hiden: unknown key");
        assert_error([] { nn::reconstruction_settings::from_json(json::array(), "rec"); }, "rec: settings: expected a JSON object");
        assert_error([] { nn::classifier_settings::from_json(json{ { "chirp_bins", 4 } }, "cls"); },
                     "cls: chirp_bins: must be 0 (off) or odd");
        assert_error([] { nn::classifier_settings::from_json(json{ { "chirp_sweep_bins", 0.0 } }, "cls"); },
                     "cls: chirp_sweep_bins: must be finite and > 0");
        assert_error([] { nn::classifier_settings::from_json(json{ { "chirp_min_pilots", 0 } }, "cls"); },
                     "cls: chirp_min_pilots: must be in [1, 1000000], got 0");
        // A bundle written before the tone fit existed reads as without it (legacy value), and
        // one written before chirp_min_pilots as counting every observed subcarrier.
        CPPUNIT_ASSERT_EQUAL(0, nn::classifier_settings::from_json(json::object(), "cls").chirp_bins);
        CPPUNIT_ASSERT_EQUAL(1, nn::classifier_settings::from_json(json{ { "chirp_bins", 9 } }, "cls").chirp_min_pilots);
        // Round trips: what to_json writes reads back.
        nn::classifier_settings cls;
        CPPUNIT_ASSERT_EQUAL(9, cls.chirp_bins);
        CPPUNIT_ASSERT_EQUAL(3, cls.chirp_min_pilots);
        CPPUNIT_ASSERT(nn::classifier_settings::from_json(cls.to_json(), "c").to_json() == cls.to_json());
        nn::encoder_settings e;
        CPPUNIT_ASSERT(nn::encoder_settings::from_json(e.to_json(), "e").to_json() == e.to_json());
        nn::delay_settings ds;
        CPPUNIT_ASSERT(nn::delay_settings::from_json(ds.to_json(), "d").to_json() == ds.to_json());
    }

    void decoder_refuses_non_finite_frames()
    {
        // The rule of bundle_decoder.h: a NaN or Inf anywhere in a frame (either part, any
        // pilot) refuses the batch, naming the method, the frame and the pilot; the same
        // batch without that value decodes.
        const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
        bundle_decoder cls(model_bundle::load(models_dir() + "classifier"), 1);
        bundle_decoder del(model_bundle::load(models_dir() + "delay_single"), 1);
        for (const bundle_decoder* d : { &cls, &del }) {
            const int np = d->n_pilots();
            std::vector<gr_complex> obs(size_t(4) * np, gr_complex(0.5f, -0.25f));
            const bool is_cls = d == &cls;
            auto decode = [&] {
                if (is_cls)
                    return d->classify(obs.data(), 4).size();
                return d->estimate_delay_index(obs.data(), 4).size();
            };
            const std::string method = is_cls ? "bundle_decoder::classify: " : "bundle_decoder::estimate_delay: ";
            CPPUNIT_ASSERT_EQUAL(size_t(is_cls ? 4 * 3 : 4), decode()); // finite: answered
            obs[size_t(2) * np + 5] = gr_complex(0.0f, nan);
            assert_error(decode, method + "frame 2 of the batch of 4 holds a non-finite observation (pilot 5)");
            obs[size_t(0) * np + np - 1] = gr_complex(-inf, 0.0f); // the first bad frame is named
            assert_error(decode, method + "frame 0 of the batch of 4", "(pilot " + std::to_string(np - 1) + ")");
            obs[size_t(0) * np + np - 1] = obs[size_t(2) * np + 5] = gr_complex(0.5f, -0.25f);
            CPPUNIT_ASSERT_EQUAL(size_t(is_cls ? 4 * 3 : 4), decode());
        }
        std::vector<gr_complex> one(cls.n_pilots(), gr_complex(inf, inf));
        assert_error([&] { cls.features(one.data(), 1); }, "bundle_decoder::features: frame 0 of the batch of 1");
        assert_error([&] { del.estimate_delay(one.data(), 1); }, "bundle_decoder::estimate_delay: frame 0");
    }

    void class_library_is_recorded()
    {
        // The shipped bundles predate the key: the paper's table.
        auto b = model_bundle::load(edited_bundle("classifier", [](json&) {}));
        CPPUNIT_ASSERT(b.library && b.library->same_classes(*class_library::paper()));
        b.check_library(*class_library::paper(), "qa");
        // A bundle records its library in full and reads it back.
        const auto kin = class_library::find("kinematic");
        auto d = edited_bundle("classifier", [&](json& j) {
            j["class_library"] = kin->to_json();
            j["class_names"] = { "adult", "car", "quadcopter" }; // a subset, in label order
        });
        b = model_bundle::load(d);
        CPPUNIT_ASSERT_EQUAL(kin->name(), b.library->name());
        CPPUNIT_ASSERT(b.library->same_classes(*kin));
        CPPUNIT_ASSERT_EQUAL(kin->to_json().dump(), b.to_json()["class_library"].dump());
        b.check_library(*kin, "qa");
        // Frames of another library are refused, naming both and how they differ.
        try {
            b.check_library(*class_library::paper(), "qa");
            CPPUNIT_FAIL("a bundle of the kinematic library accepted the paper's frames");
        } catch (const std::runtime_error& e) {
            const std::string what = e.what();
            for (const std::string& needle : std::vector<std::string>{ "qa: the bundle " + d, "class library \"kinematic\"",
                                              "class library \"paper\"", kin->difference(*class_library::paper()) })
                CPPUNIT_ASSERT_MESSAGE("message \"" + what + "\" lacks \"" + needle + "\"",
                                       what.find(needle) != std::string::npos);
        }
        // Class names outside the recorded library, a library on a delay model, a bad library.
        d = edited_bundle("classifier", [&](json& j) { j["class_library"] = kin->to_json(); });
        assert_error([&] { load(d); },
                     d + "/bundle.json: class_names: \"pedestrian\" is not a class of its class_library \"kinematic\"");
        d = edited_bundle("delay_single", [&](json& j) { j["class_library"] = kin->to_json(); });
        assert_error([&] { load(d); }, "bundle.json: class_library: a delay model has no classes");
        d = edited_bundle("classifier", [&](json& j) { j["class_library"] = { { "format", "sems.classes" } }; });
        assert_error([&] { load(d); }, "bundle.json: class_library");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_bundle_readers);
