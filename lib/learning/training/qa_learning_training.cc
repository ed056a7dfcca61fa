// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a tiny, seeded training run — beats chance on held-out frames, is
 * reproducible, and its bundle loads back into bundle_decoder with the same answers;
 * bad bundles give errors that name the file and the problem. */
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/training/trainer.h>
#include "learning/training/mask_settle_rule.h"
#include "learning/training/trainer_data.h"
#include "qa/qa_assert.h"
#include "qa/qa_files.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <unistd.h>

using namespace gr::sems;
using gr::sems::qa::assert_error;
namespace fsys = std::filesystem;

namespace {

std::string learning_dir(const std::string& name) { return qa::temp_dir("learning", name); }

// Tiny: pedestrian vs car, learned mask, seconds on two cores.
training_settings tiny(const std::string& out)
{
    training_settings s;
    s.task = task_kind::classify;
    random_spec r;
    r.classes = { target_class::pedestrian, target_class::car };
    s.scene_spec = scene::random(r);
    s.snr_min_db = s.snr_max_db = 20.0;
    s.frames = 1500;
    s.epochs = 4;
    s.decoder_epochs = 3;
    s.batch = 64;
    s.n_pilots = 16;
    s.threads = 1;
    s.seed = 7;
    s.eval_snr_db = { 20.0 };
    s.out_dir = out;
    s.verbose = false;
    return s;
}

struct trained {
    std::string dir;
    training_result result;
};
// One run shared by the tests of this suite.
const trained& shared_run()
{
    static std::unique_ptr<trained> t;
    if (!t) {
        t = std::make_unique<trained>();
        t->dir = learning_dir("tiny");
        t->result = train(tiny(t->dir), nullptr);
    }
    return *t;
}

void copy_bundle(const std::string& from, const std::string& to)
{
    fsys::remove_all(to);
    fsys::copy(from, to, fsys::copy_options::recursive);
}

std::string file_bytes(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    if (!f)
        throw std::runtime_error("qa: cannot read " + path);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

using qa::edit_json;
} // namespace

class qa_learning_training : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_learning_training);
    CPPUNIT_TEST(tiny_run_beats_chance);
    CPPUNIT_TEST(cold_start_mask_beats_random_mask);
    CPPUNIT_TEST(mask_settle_rule_counts_unchanged_epochs);
    CPPUNIT_TEST(settled_mask_gives_its_epochs_to_the_decoder);
    CPPUNIT_TEST(bundle_reproduces_trainer_answers);
    CPPUNIT_TEST(same_seed_same_mask_and_metrics);
    CPPUNIT_TEST(streamed_frames_are_the_held_frames);
    CPPUNIT_TEST(streamed_frames_train_the_same_bundle);
    CPPUNIT_TEST(bad_bundles_are_refused);
    CPPUNIT_TEST(bad_settings_are_refused);
    CPPUNIT_TEST(learned_pilot_power);
    CPPUNIT_TEST(trained_for_a_radio);
    CPPUNIT_TEST(pilot_phases_in_the_bundle);
    CPPUNIT_TEST_SUITE_END();

public:
    void tiny_run_beats_chance()
    {
        const auto& r = shared_run().result;
        const double acc = r.bundle.metrics.at("test").at("accuracy").get<double>();
        CPPUNIT_ASSERT_EQUAL(150, r.n_test);
        // Chance is 0.5 for two balanced classes.
        CPPUNIT_ASSERT_MESSAGE("held-out accuracy " + std::to_string(acc), acc >= 0.8);
        CPPUNIT_ASSERT_EQUAL(16, r.bundle.mask.size());
        CPPUNIT_ASSERT_EQUAL(std::string("learned"), r.bundle.mask.origin().at("kind").get<std::string>());
    }

    void cold_start_mask_beats_random_mask()
    {
        // All three classes at 5 dB with 16 pilots: the default learner (Gumbel top-k from
        // zero scores, spectral decoder) against the same decoder, seed and number of
        // epochs on a random mask, scored on the same held-out frames.
        auto s = tiny("");
        s.scene_spec = scene::random(random_spec{});
        s.snr_min_db = s.snr_max_db = 5.0;
        s.eval_snr_db = {};
        const auto learned = train(s, nullptr);
        s.mask_pattern = "random";
        s.epochs = s.epochs + s.decoder_epochs;
        const auto rnd = train(s, nullptr);
        const double a = learned.bundle.metrics.at("test").at("accuracy").get<double>();
        const double r = rnd.bundle.metrics.at("test").at("accuracy").get<double>();
        CPPUNIT_ASSERT_EQUAL(std::string("random"), rnd.bundle.mask.origin().at("kind").get<std::string>());
        CPPUNIT_ASSERT_EQUAL(std::string("learned"), learned.bundle.mask.origin().at("kind").get<std::string>());
        // Chance is 1/3; measured 0.92 against 0.59 (150 test frames, sd <= 0.04 each).
        CPPUNIT_ASSERT_MESSAGE("learned " + std::to_string(a) + " vs random " + std::to_string(r),
                               a >= 0.8 && a >= r + 0.15);
        // The learned mask found slow-time structure: one subcarrier carries many pilots.
        std::vector<int> per_subcarrier(64, 0);
        for (const auto& p : learned.bundle.mask.positions())
            per_subcarrier[p.m]++;
        CPPUNIT_ASSERT(*std::max_element(per_subcarrier.begin(), per_subcarrier.end()) >= 8);
        // bundle.json records the learner and the decoder.
        CPPUNIT_ASSERT_EQUAL(std::string("gumbel_topk"),
                             learned.bundle.training.at("encoder").at("kind").get<std::string>());
        CPPUNIT_ASSERT_EQUAL(0, learned.bundle.training.at("encoder").at("soft_epochs").get<int>());
        CPPUNIT_ASSERT_EQUAL(std::string("classifier_spectral"), learned.bundle.decoder.at("kind").get<std::string>());
    }

    void mask_settle_rule_counts_unchanged_epochs()
    {
        const std::vector<int64_t> a{ 3, 1, 2 }, a_reordered{ 2, 3, 1 }, b{ 1, 2, 4 };
        mask_settle_rule two(2);
        CPPUNIT_ASSERT(!two.settled_after(a)); // the first mask has nothing to equal
        CPPUNIT_ASSERT(!two.settled_after(a_reordered));
        CPPUNIT_ASSERT_EQUAL(1, two.unchanged());
        CPPUNIT_ASSERT(!two.settled_after(b)); // a change starts the count again
        CPPUNIT_ASSERT_EQUAL(0, two.unchanged());
        CPPUNIT_ASSERT(!two.settled_after(b));
        CPPUNIT_ASSERT(two.settled_after(b));
        mask_settle_rule never(0);
        for (int i = 0; i < 5; ++i)
            CPPUNIT_ASSERT(!never.settled_after(a));
        CPPUNIT_ASSERT_EQUAL(4, never.unchanged());
    }

    // The budget holds whether phase 1 stops early or not: its unused epochs go to phase 2
    // (patience large enough that phase 2 runs them all), and the mask records how many
    // epochs learned it.
    void settled_mask_gives_its_epochs_to_the_decoder()
    {
        auto s = tiny("");
        s.epochs = 8;
        s.decoder_epochs = 2;
        s.patience = 100;
        // Every cell a pilot: the mask cannot change, so it settles after 1 + settle epochs
        // whatever the scores do (a tiny run's partial masks keep moving for many epochs).
        s.n_pilots = s.frame.grid_size();
        s.frames = 300;
        for (const int settle : { 0, 1 }) {
            s.mask_settle_epochs = settle;
            const auto r = train(s, nullptr);
            int mask_epochs = 0, decoder_epochs = 0;
            for (const auto& e : r.history)
                (e.at("phase") == "mask" ? mask_epochs : decoder_epochs)++;
            const std::string what = "settle " + std::to_string(settle) + ": " + std::to_string(mask_epochs) +
                                     " mask + " + std::to_string(decoder_epochs) + " decoder epochs";
            CPPUNIT_ASSERT_EQUAL_MESSAGE(what, 10, mask_epochs + decoder_epochs);
            CPPUNIT_ASSERT_EQUAL_MESSAGE(what, mask_epochs, r.bundle.mask.origin().at("mask_epochs_run").get<int>());
            CPPUNIT_ASSERT_EQUAL(settle, r.bundle.training.at("mask_settle_epochs").get<int>());
            CPPUNIT_ASSERT_EQUAL_MESSAGE(what, settle == 0 ? 8 : 2, mask_epochs);
        }
        s.mask_settle_epochs = -1;
        CPPUNIT_ASSERT_THROW(s.validate(), std::invalid_argument);
    }

    void bundle_reproduces_trainer_answers()
    {
        const auto& t = shared_run();
        const auto b = model_bundle::load(t.dir);
        CPPUNIT_ASSERT(b.mask == t.result.bundle.mask);
        CPPUNIT_ASSERT_EQUAL(size_t(2), b.class_names.size());
        bundle_decoder dec(b, 1);
        const auto probs = dec.classify(t.result.test_obs.data(), t.result.n_test);
        CPPUNIT_ASSERT_EQUAL(t.result.test_probs.size(), probs.size());
        for (size_t i = 0; i < probs.size(); ++i)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(t.result.test_probs[i], probs[i], 1e-5);
        // Features: 16 per frame, finite.
        const auto f = dec.features(t.result.test_obs.data(), 3);
        CPPUNIT_ASSERT_EQUAL(size_t(3 * dec.feature_size()), f.size());
        // A classifier bundle refuses delay estimation.
        assert_error([&] { dec.estimate_delay(t.result.test_obs.data(), 1); }, "classify");
    }

    void same_seed_same_mask_and_metrics()
    {
        const auto& t = shared_run();
        auto s = tiny("");
        const auto again = train(s, nullptr);
        CPPUNIT_ASSERT_MESSAGE(again.bundle.mask.to_json_string() + "\n vs \n" + t.result.bundle.mask.to_json_string() +
                                   "\n" + again.history.dump() + "\n" + t.result.history.dump(),
                               again.bundle.mask == t.result.bundle.mask);
        CPPUNIT_ASSERT_EQUAL(t.result.bundle.metrics.at("test").dump(), again.bundle.metrics.at("test").dump());
    }

    // The data set's training frames held and streamed: the same bits for every frame in any
    // order, and for any grid positions of the first frames (the template bank's pilots), on
    // a library of moving scatterers (walkers, rotors, wheels) at any heading; the same labels,
    // delays, validation and test frames.
    void streamed_frames_are_the_held_frames()
    {
        auto s = tiny("");
        s.frames = 300;
        random_spec spec;
        spec.classes.clear();
        spec.heading = heading_kind::any;
        const scene sc = scene::random(spec, std::nullopt, fading_kind::rayleigh, class_library::find("kinematic"));
        s.training_data = "hold";
        const auto held = training::make_data(s, sc);
        s.training_data = "stream";
        const auto streamed = training::make_data(s, sc);
        CPPUNIT_ASSERT(streamed.train.streamed() && !held.train.streamed() && !streamed.train.h.defined());
        CPPUNIT_ASSERT_EQUAL(int64_t(240), streamed.train.size());
        CPPUNIT_ASSERT_EQUAL(held.train.held_bytes(), streamed.train.held_bytes());
        const auto idx = torch::randperm(held.train.size(), torch::kLong);
        const int threads = at::get_num_threads();
        at::set_num_threads(2); // the frames are computed on LibTorch's threads
        CPPUNIT_ASSERT(torch::equal(held.train.frames(idx), streamed.train.frames(idx)));
        at::set_num_threads(threads);
        CPPUNIT_ASSERT(torch::equal(held.train.label, streamed.train.label));
        CPPUNIT_ASSERT(torch::equal(held.train.delay, streamed.train.delay));
        CPPUNIT_ASSERT(torch::equal(held.val.h, streamed.val.h) && torch::equal(held.test.h, streamed.test.h));
        CPPUNIT_ASSERT(torch::equal(held.test.label, streamed.test.label));
        const int64_t grid = s.frame.n_symbols * s.frame.n_subcarriers;
        const auto flat = torch::tensor({ int64_t(0), int64_t(5), int64_t(77), grid - 1 }, torch::kLong);
        CPPUNIT_ASSERT(torch::equal(held.train.pilots(200, flat), streamed.train.pilots(200, flat)));
        CPPUNIT_ASSERT_THROW(streamed.train.frames(torch::tensor({ int64_t(240) }, torch::kLong)), std::logic_error);
    }

    // Streamed training frames are the held ones bit for bit: the same mask, epochs, decoder
    // weights and test metrics.
    void streamed_frames_train_the_same_bundle()
    {
        const auto& t = shared_run();
        const auto dir = learning_dir("streamed");
        auto s = tiny(dir);
        s.training_data = "stream";
        const auto r = train(s, nullptr);
        CPPUNIT_ASSERT(r.bundle.mask == t.result.bundle.mask);
        CPPUNIT_ASSERT_EQUAL(t.result.bundle.metrics.at("test").dump(), r.bundle.metrics.at("test").dump());
        auto untimed = [](nlohmann::json h) { // the epochs' losses and scores, not their times
            for (auto& e : h)
                for (const char* k : { "seconds", "cpu_seconds", "train_frames_per_s" })
                    e.erase(k);
            return h.dump();
        };
        CPPUNIT_ASSERT_EQUAL(untimed(t.result.history), untimed(r.history));
        CPPUNIT_ASSERT_EQUAL(file_bytes(t.dir + "/decoder.pt"), file_bytes(dir + "/decoder.pt"));
        CPPUNIT_ASSERT(!r.bundle.training.contains("training_data")); // where frames live is not a setting of the bundle
        s.training_data = "disk";
        assert_error([&] { train(s, nullptr); }, "training_data", "disk");
        fsys::remove_all(dir);
    }

    void bad_bundles_are_refused()
    {
        const auto& t = shared_run();
        assert_error([] { model_bundle::load("/nonexistent/sems/bundle"); }, "/nonexistent/sems/bundle",
                     "does not exist");

        const auto d = learning_dir("bad");
        copy_bundle(t.dir, d);
        fsys::remove(d + "/bundle.json");
        assert_error([&] { model_bundle::load(d); }, "bundle.json", "cannot open");

        copy_bundle(t.dir, d);
        edit_json(d + "/bundle.json", [](nlohmann::json& j) { j["task"] = "delay"; });
        assert_error([&] { model_bundle::load(d); }, "bundle.json", "task");
        edit_json(d + "/bundle.json", [](nlohmann::json& j) { j["task"] = "juggle"; });
        assert_error([&] { model_bundle::load(d); }, "bundle.json", "juggle");

        copy_bundle(t.dir, d);
        const auto good = model_bundle::load(d);
        assert_error([&] { good.check_compatible(good.frame, 16, task_kind::delay, "delay sink"); }, "delay sink",
                     "\"classify\" model");
        assert_error([&] { good.check_compatible(good.frame, 32, task_kind::classify, "classifier sink"); },
                     "N_p = 16");
        frame_settings other = good.frame;
        other.n_symbols = 16;
        assert_error([&] { good.check_compatible(other, 16, task_kind::classify, "classifier sink"); }, "frame");

        std::ofstream(d + "/decoder.pt", std::ios::trunc) << "not a torch archive";
        assert_error([&] { bundle_decoder dec(model_bundle::load(d), 1); }, "decoder.pt", "corrupt");
        fsys::remove(d + "/decoder.pt");
        assert_error([&] { bundle_decoder dec(model_bundle::load(d), 1); }, "decoder.pt", "missing");

        // Weights of another architecture.
        copy_bundle(t.dir, d);
        edit_json(d + "/bundle.json", [](nlohmann::json& j) { j["decoder"]["settings"]["width"] = 4; });
        assert_error([&] { bundle_decoder dec(model_bundle::load(d), 1); }, "decoder.pt");

        // Mask that does not match bundle.json: fewer pilots, another frame.
        copy_bundle(t.dir, d);
        edit_json(d + "/mask.json", [](nlohmann::json& j) {
            j["pilots"].erase(j["pilots"].begin());
            if (j.contains("n_pilots"))
                j["n_pilots"] = j["pilots"].size(); // a valid mask, just not this bundle's
        });
        assert_error([&] { model_bundle::load(d); }, "mask.json", "n_pilots = 16");
        copy_bundle(t.dir, d);
        edit_json(d + "/mask.json", [](nlohmann::json& j) { j["n_symbols"] = 64; });
        assert_error([&] { model_bundle::load(d); }, "mask.json", "does not match bundle.json");
        fsys::remove(d + "/mask.json");
        assert_error([&] { model_bundle::load(d); }, "mask.json");
        fsys::remove_all(d);
    }

    void bad_settings_are_refused()
    {
        auto s = tiny("");
        s.objective = "fun";
        assert_error([&] { train(s, nullptr); }, "objective");
        s = tiny("");
        s.snr_min_db = 30;
        s.snr_max_db = 10;
        assert_error([&] { train(s, nullptr); }, "snr");
        s = tiny("");
        s.n_pilots = 5000;
        assert_error([&] { train(s, nullptr); }, "pilots");
        s = tiny("");
        s.scene_spec = scene::random(random_spec{ { target_class::car } });
        assert_error([&] { train(s, nullptr); }, "at least two classes");
        s = tiny("");
        s.encoder.kind = "dice";
        assert_error([&] { train(s, nullptr); }, "encoder kind", "dice");
        s = tiny("");
        s.classifier.architecture = "transformer";
        assert_error([&] { train(s, nullptr); }, "architecture", "transformer");
        s = tiny("");
        s.classifier.mti = "median";
        assert_error([&] { train(s, nullptr); }, "mti", "median");
        s = tiny("");
        s.classifier.doppler_bins = 8;
        assert_error([&] { train(s, nullptr); }, "doppler_bins");
        s = tiny("");
        s.pilot_power = "shouting";
        assert_error([&] { train(s, nullptr); }, "pilot_power", "shouting");
        s = tiny("");
        s.pilot_power = "learned";
        s.mask_pattern = "uniform";
        assert_error([&] { train(s, nullptr); }, "pilot_power \"learned\" needs a learned mask");
        s = tiny("");
        s.pilot_power = "learned";
        s.pilot_power_floor = 1.0;
        assert_error([&] { train(s, nullptr); }, "pilot_power_floor must be in [0, 1)");
        s = tiny("");
        s.pilot_phases = "chirp";
        assert_error([&] { train(s, nullptr); }, "pilot_phases must be \"zero\" or \"newman\"", "chirp");
    }

    // A tiny run that learns the pilots' energies: they share the total of equal power
    // (mean 1), differ, respect the floor, and the bundle records and repeats the setting.
    void learned_pilot_power()
    {
        const auto dir = learning_dir("power");
        auto s = tiny(dir);
        s.frames = 600;
        s.epochs = 2;
        s.decoder_epochs = 1;
        s.pilot_power = "learned";
        s.pilot_power_floor = 0.2;
        const auto r = train(s, nullptr);
        const auto& mk = r.bundle.mask;
        CPPUNIT_ASSERT_EQUAL(16, mk.size());
        CPPUNIT_ASSERT(!mk.equal_power());
        double sum = 0.0, lo = 1e300, hi = -1e300;
        for (double p : mk.power()) {
            sum += p;
            lo = std::min(lo, p);
            hi = std::max(hi, p);
        }
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, sum / mk.size(), 1e-12);
        CPPUNIT_ASSERT_MESSAGE("energies from " + std::to_string(lo) + " to " + std::to_string(hi), hi - lo > 1e-3);
        CPPUNIT_ASSERT_MESSAGE("smallest energy " + std::to_string(lo), lo >= 0.2 - 1e-9);
        // mask.json carries the energies; bundle.json the setting; --from repeats it.
        const auto loaded = model_bundle::load(dir);
        CPPUNIT_ASSERT(loaded.mask == mk);
        CPPUNIT_ASSERT_EQUAL(std::string("learned"), loaded.training.at("pilot_power").get<std::string>());
        const auto again = training_settings::from_bundle(loaded);
        CPPUNIT_ASSERT_EQUAL(std::string("learned"), again.pilot_power);
        CPPUNIT_ASSERT_EQUAL(0.2, again.pilot_power_floor);
        // Equal power is recorded too, and a record without the key (older bundles) reads as equal.
        const auto& plain = shared_run().result.bundle;
        CPPUNIT_ASSERT(plain.mask.equal_power());
        CPPUNIT_ASSERT_EQUAL(std::string("equal"), plain.training.at("pilot_power").get<std::string>());
        auto old = model_bundle::load(shared_run().dir);
        old.training.erase("pilot_power");
        CPPUNIT_ASSERT_EQUAL(std::string("equal"), training_settings::from_bundle(old).pilot_power);
        fsys::remove_all(dir);
    }

    // The shared run again with Newman phases: the decoder sees Y/s_k, so the training, the
    // pilots and the test metrics are those of the run without phases; only the bundle's
    // mask gains the phases, and bundle.json records the setting for --from.
    void pilot_phases_in_the_bundle()
    {
        const auto& t = shared_run();
        const auto dir = learning_dir("phases");
        auto s = tiny(dir);
        s.pilot_phases = "newman";
        const auto r = train(s, nullptr);
        const auto& mk = r.bundle.mask;
        CPPUNIT_ASSERT_EQUAL(std::string("newman"), mk.phase_sequence());
        CPPUNIT_ASSERT(!mk.zero_phases());
        CPPUNIT_ASSERT(mk.with_phases("zero") == t.result.bundle.mask);
        CPPUNIT_ASSERT(mk == t.result.bundle.mask.with_phases("newman"));
        CPPUNIT_ASSERT_EQUAL(t.result.bundle.metrics.at("test").dump(), r.bundle.metrics.at("test").dump());
        const auto loaded = model_bundle::load(dir);
        CPPUNIT_ASSERT(loaded.mask == mk);
        CPPUNIT_ASSERT_EQUAL(std::string("newman"), loaded.training.at("pilot_phases").get<std::string>());
        CPPUNIT_ASSERT_EQUAL(std::string("newman"), training_settings::from_bundle(loaded).pilot_phases);
        // Without the setting the record has no key, and reads back as "as the mask has them".
        CPPUNIT_ASSERT(!t.result.bundle.training.contains("pilot_phases"));
        CPPUNIT_ASSERT(training_settings::from_bundle(model_bundle::load(t.dir)).pilot_phases.empty());
        fsys::remove_all(dir);
    }

    // A radio file: the ideal one trains bit for bit as without it (the trainer's own
    // H + noise); a monostatic radio with strong phase noise changes every observation, is
    // recorded in bundle.json and read back by --from; what training cannot draw is refused.
    void trained_for_a_radio()
    {
        const auto& t = shared_run();
        const auto dir = learning_dir("radio");
        auto s = tiny(dir);
        s.radio = front_end_settings{};
        s.radio_source = "ideal.json";
        auto r = train(s, nullptr);
        CPPUNIT_ASSERT_EQUAL(t.result.bundle.metrics.at("test").dump(), r.bundle.metrics.at("test").dump());
        CPPUNIT_ASSERT(t.result.bundle.mask == r.bundle.mask);

        front_end_settings radio;
        radio.leakage_db = 40.0;
        radio.phase_noise_dbc_hz = -70.0;
        radio.adc_enob = 8.0;
        s.radio = radio;
        s.radio_source = "a harsh radio";
        r = train(s, nullptr);
        CPPUNIT_ASSERT(t.result.bundle.metrics.at("test").dump() != r.bundle.metrics.at("test").dump());
        const auto loaded = model_bundle::load(dir);
        CPPUNIT_ASSERT_EQUAL(radio.to_json().dump(), loaded.training.at("radio").dump());
        CPPUNIT_ASSERT_EQUAL(std::string("a harsh radio"), loaded.training.at("radio_source").get<std::string>());
        const auto again = training_settings::from_bundle(loaded);
        CPPUNIT_ASSERT(again.radio && *again.radio == radio);
        // Trained for the ideal radio: no key, and none read back.
        CPPUNIT_ASSERT(!t.result.bundle.training.contains("radio"));
        CPPUNIT_ASSERT(!training_settings::from_bundle(model_bundle::load(t.dir)).radio);

        auto bad = tiny(dir);
        bad.radio = radio;
        bad.radio->sfo_ppm = 3.0;
        assert_error([&] { train(bad, nullptr); }, "sfo_ppm", "3");
        bad.radio->sfo_ppm = 0.0;
        bad.pilot_power = "learned";
        assert_error([&] { train(bad, nullptr); }, "pilot_power", "radio");
        bad.pilot_power = "equal";
        bad.radio->adc_enob = 0.5;
        assert_error([&] { train(bad, nullptr); }, "adc_enob", "0.5");
        fsys::remove_all(dir);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_learning_training);
