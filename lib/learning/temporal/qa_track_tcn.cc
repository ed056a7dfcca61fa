// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the temporal model of kind acf_tcn — its settings round-trip through JSON and bad
 * ones are refused by name, each frame's autocorrelation evidence is the closed form of a
 * tone, the streamed step is the batch forward frame by frame (tracks shorter than the
 * receptive field included), and a tiny seeded run writes a bundle that track_classifier
 * loads and steps with the trainer's answers. */
#include "learning/networks/task_decoder.h"
#include "learning/temporal/tcn_model.h"
#include "learning/temporal/track_data.h"
#include "learning/temporal/track_evidence.h"
#include "qa/qa_assert.h"
#include "qa/qa_files.h"
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <gnuradio/sems/learning/temporal/track_trainer.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <ATen/CPUGeneratorImpl.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>

using namespace gr::sems;

// Named, not anonymous: the unity build puts this file beside the other track tests.
namespace qa_track_tcn_detail {

nn::temporal_settings tcn_settings()
{
    nn::temporal_settings s;
    s.kind = "acf_tcn";
    return s;
}

// Every parameter drawn anew (biases too: the zero padding must differ from a zero input's
// output), so no term of the step can hide behind an initial zero.
void scramble(torch::nn::Module& m, double sd)
{
    torch::NoGradGuard ng;
    for (auto& p : m.parameters())
        p.normal_(0.0, sd);
}

// Evidence of B tracks (B x T x E, the last C values log-probabilities), zero past each
// track's end as the trainer gives it.
torch::Tensor padded_evidence(const std::vector<int64_t>& lengths, int64_t t, int64_t e, int64_t c)
{
    const int64_t b = static_cast<int64_t>(lengths.size());
    auto ev = torch::randn({ b, t, e });
    ev.slice(2, e - c, e).copy_(torch::log_softmax(ev.slice(2, e - c, e) * 3.0, -1));
    for (int64_t i = 0; i < b; ++i)
        ev[i].slice(0, lengths[static_cast<size_t>(i)], t).zero_();
    return ev;
}

// Steps each track through tcn_stepper for its length and compares every logit with the
// batch forward's, to float tolerance.
void check_streaming(const nn::temporal_settings& s, int64_t e, int64_t c, const std::vector<int64_t>& lengths)
{
    nn::tcn_model m(static_cast<int>(e), static_cast<int>(c), s);
    scramble(*m, 0.2);
    m->eval(); // dropout is for training only
    const int64_t t = *std::max_element(lengths.begin(), lengths.end());
    const auto ev = padded_evidence(lengths, t, e, c).contiguous();
    torch::Tensor whole;
    {
        torch::NoGradGuard ng;
        whole = m->forward(ev).contiguous();
    }
    CPPUNIT_ASSERT_EQUAL(int64_t(lengths.size()), whole.size(0));
    CPPUNIT_ASSERT_EQUAL(t, whole.size(1));
    CPPUNIT_ASSERT_EQUAL(c, whole.size(2));
    const nn::tcn_stepper stepper(*m);
    CPPUNIT_ASSERT_EQUAL(m->hidden_size(), stepper.state_size());
    CPPUNIT_ASSERT_EQUAL(s.receptive_field() * int(e) + 2 * s.channels + 1, m->hidden_size());
    std::vector<float> logits(static_cast<size_t>(c));
    double worst = 0.0;
    for (size_t i = 0; i < lengths.size(); ++i) {
        std::vector<float> state(static_cast<size_t>(stepper.state_size()), 0.0f);
        for (int64_t f = 0; f < lengths[i]; ++f) {
            stepper.step(state.data(), ev[int64_t(i)][f].data_ptr<float>(), logits.data());
            for (int64_t k = 0; k < c; ++k) {
                const double want = whole[int64_t(i)][f][k].item<float>();
                const double err = std::fabs(logits[size_t(k)] - want) / std::max(1.0, std::fabs(want));
                worst = std::max(worst, err);
            }
        }
    }
    CPPUNIT_ASSERT_MESSAGE("streamed logits differ from the batch forward's by " + std::to_string(worst), worst < 1e-5);
}

// Walking adults against children of the kinematic library, straight tracks.
scene adults_children()
{
    return scene::from_json(nlohmann::json::parse(R"({"format": "sems.scene", "version": 1, "classes": "kinematic",
        "random": {"classes": ["adult", "child"], "heading": "any", "tracks": {"frames": 8, "motion": "straight"}}})"),
                            "qa_track_tcn scene");
}

// Tiny seeded acf_tcn settings on the shipped kinematic frame bundle (seconds of training).
track_training_settings tiny_settings(const std::string& dir, const scene& sc, int frames, int tracks, int channels)
{
    track_training_settings s;
    s.frame_bundle = qa::models_dir() + "classifier_kinematic";
    s.scene_spec = sc;
    s.scene_source = "qa_track_tcn scene";
    s.track_frames = frames;
    s.tracks = tracks;
    s.snr_min_db = s.snr_max_db = 20.0;
    s.threads = 1;
    s.eval_snr_db = { 20.0 };
    s.temporal = tcn_settings();
    s.temporal.channels = channels;
    s.out_dir = dir;
    s.verbose = false;
    return s;
}

struct tcn_run {
    std::string dir;
    track_training_result result;
};
// A tiny seeded acf_tcn run on the shipped kinematic frame bundle (seconds), shared by the tests.
const tcn_run& shared_tcn_run()
{
    static std::unique_ptr<tcn_run> r;
    if (!r) {
        r = std::make_unique<tcn_run>();
        r->dir = qa::temp_dir("track_tcn", "bundle");
        auto s = tiny_settings(r->dir, adults_children(), 8, 60, 16);
        s.epochs = 2;
        s.batch = 16;
        s.seed = 23;
        s.eval_frames = { 1, 8 };
        s.temporal.head = 8;
        s.loss_ramp = 1.0;
        r->result = train_track(s, nullptr);
    }
    return *r;
}

} // namespace qa_track_tcn_detail
using namespace qa_track_tcn_detail;

class qa_track_tcn : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_track_tcn);
    CPPUNIT_TEST(settings_round_trip);
    CPPUNIT_TEST(bad_settings_are_refused);
    CPPUNIT_TEST(acf_of_a_tone_is_its_closed_form);
    CPPUNIT_TEST(acf_picks_the_fullest_subcarrier);
    CPPUNIT_TEST(steps_are_the_batch_forward);
    CPPUNIT_TEST(forward_is_causal);
    CPPUNIT_TEST(trained_bundle_streams_the_trainer_answers);
    CPPUNIT_TEST(bad_tcn_bundles_are_refused);
    CPPUNIT_TEST(steep_ramp_on_short_tracks_trains_finite_weights);
    CPPUNIT_TEST_SUITE_END();

public:
    void settings_round_trip()
    {
        // gru_fusion writes the keys it always wrote, and reads them back.
        const nn::temporal_settings gru;
        const auto g = gru.to_json();
        CPPUNIT_ASSERT_EQUAL(size_t(5), g.size());
        for (const char* k : { "kind", "hidden", "doppler_profile", "dropout", "fusion_frames" })
            CPPUNIT_ASSERT_MESSAGE(k, g.contains(k));
        CPPUNIT_ASSERT(nn::temporal_settings::from_json(g, "qa").to_json() == g);
        // acf_tcn: its own keys, every value back as it was.
        auto s = tcn_settings();
        s.channels = 24;
        s.kernel = 3;
        s.dilations = { 1, 3, 9, 2 };
        s.head = 7;
        s.dropout = 0.1;
        s.fusion_frames = 2;
        const auto j = s.to_json();
        CPPUNIT_ASSERT(!j.contains("hidden") && !j.contains("doppler_profile"));
        const auto back = nn::temporal_settings::from_json(j, "qa");
        CPPUNIT_ASSERT_EQUAL(std::string("acf_tcn"), back.kind);
        CPPUNIT_ASSERT_EQUAL(24, back.channels);
        CPPUNIT_ASSERT_EQUAL(3, back.kernel);
        CPPUNIT_ASSERT(back.dilations == std::vector<int>({ 1, 3, 9, 2 }));
        CPPUNIT_ASSERT_EQUAL(7, back.head);
        CPPUNIT_ASSERT_EQUAL(0.1, back.dropout);
        CPPUNIT_ASSERT_EQUAL(2, back.fusion_frames);
        CPPUNIT_ASSERT(back.to_json() == j);
        CPPUNIT_ASSERT_EQUAL(1 + 2 * 15, back.receptive_field());
        // The study's defaults: 64 channels, 5 taps, dilations 1, 2, 4 (29 frames), a head of 64.
        const auto d = nn::temporal_settings::from_json({ { "kind", "acf_tcn" } }, "qa");
        CPPUNIT_ASSERT_EQUAL(64, d.channels);
        CPPUNIT_ASSERT_EQUAL(5, d.kernel);
        CPPUNIT_ASSERT(d.dilations == std::vector<int>({ 1, 2, 4 }));
        CPPUNIT_ASSERT_EQUAL(64, d.head);
        CPPUNIT_ASSERT_EQUAL(29, d.receptive_field());
        CPPUNIT_ASSERT_EQUAL(nn::temporal_settings{}.dropout, d.dropout);
    }

    void bad_settings_are_refused()
    {
        using json = nlohmann::json;
        auto read = [](const json& j) { return [j] { nn::temporal_settings::from_json(j, "my.json"); }; };
        qa::assert_error(read({ { "kind", "lstm" } }), "my.json: kind", "known: gru_fusion, acf_tcn");
        qa::assert_error(read({ { "kind", "acf_tcn" }, { "channels", 0 } }), "my.json: channels", "got 0");
        qa::assert_error(read({ { "kind", "acf_tcn" }, { "kernel", 65 } }), "my.json: kernel", "64");
        qa::assert_error(read({ { "kind", "acf_tcn" }, { "head", -1 } }), "my.json: head");
        qa::assert_error(read(json::parse(R"({"kind": "acf_tcn", "dilations": []})")), "my.json: dilations", "1 to 16");
        qa::assert_error(read(json::parse(R"({"kind": "acf_tcn", "dilations": [1, 0]})")), "my.json: dilations[1]",
                         "got 0");
        qa::assert_error(read(json::parse(R"({"kind": "acf_tcn", "dilations": 2})")), "my.json: dilations", "list");
        qa::assert_error(read(json::parse(R"({"kind": "acf_tcn", "kernel": 64, "dilations": [64, 2]})")),
                         "my.json: dilations", "receptive field");
        qa::assert_error(read({ { "kind", "acf_tcn" }, { "dropout", 1.0 } }), "my.json: dropout");
        // A key of the other kind is unknown, both ways.
        qa::assert_error(read({ { "kind", "acf_tcn" }, { "hidden", 8 } }), "my.json: hidden", "unknown key");
        qa::assert_error(read({ { "channels", 8 } }), "my.json: channels", "unknown key");
        // The trainer checks its settings the same way, before it loads anything.
        track_training_settings t;
        t.frame_bundle = "x";
        t.temporal = tcn_settings();
        t.temporal.kernel = 0;
        qa::assert_error([&] { t.validate(); }, "temporal: kernel");
        t.temporal = tcn_settings();
        t.acf_tcn_lr = 0.0;
        qa::assert_error([&] { t.validate(); }, "acf_tcn_lr");
        t.acf_tcn_lr = 1e-3;
        t.loss_ramp = -1.0;
        qa::assert_error([&] { t.validate(); }, "loss_ramp");
        // Built directly, a model of an unknown kind is refused too.
        auto unknown = tcn_settings();
        unknown.kind = "lstm";
        qa::assert_error([&] { nn::make_temporal_model(10, 2, unknown); }, "lstm", "known");
    }

    // A tone e^{j2πfn} (times any complex gain) on the subcarrier: over pilots at symbols S,
    // r_k = e^{j2πfk} · |{n ∈ S: n + k ∈ S}| / |S|, 0 where no pair spans k.
    void acf_of_a_tone_is_its_closed_form()
    {
        const int n_sym = 16, n_sub = 8, sub = 3;
        const std::vector<int> symbols{ 0, 1, 2, 5, 9, 15 };
        std::vector<pilot_position> pos;
        for (int n : symbols)
            pos.push_back({ n, sub });
        pos.push_back({ 4, 6 }); // other subcarriers: fewer pilots, not read
        pos.push_back({ 7, 6 });
        pos.push_back({ 2, 0 });
        const pilot_mask mask(n_sym, n_sub, pos);
        const temporal::acf_plan plan(mask, "qa mask");
        CPPUNIT_ASSERT_EQUAL(sub, plan.subcarrier());
        CPPUNIT_ASSERT_EQUAL(2 * (n_sym - 1), plan.size());
        const double f = 0.137;
        const std::complex<double> gain(-2.5, 1.25);
        std::vector<gr_complex> obs;
        for (const auto& p : mask.positions()) // mask order
            obs.push_back(p.m == sub ? gr_complex(gain * std::polar(1.0, 2.0 * M_PI * f * p.n))
                                     : gr_complex(7.0f, -3.0f));
        std::vector<float> out(static_cast<size_t>(plan.size()));
        plan.compute(obs.data(), out.data());
        for (int k = 1; k < n_sym; ++k) {
            int pairs = 0;
            for (int a : symbols)
                pairs += std::count(symbols.begin(), symbols.end(), a + k) > 0;
            const auto want = std::polar(1.0, 2.0 * M_PI * f * k) * double(pairs) / double(symbols.size());
            CPPUNIT_ASSERT_DOUBLES_EQUAL(want.real(), out[size_t(k - 1)], 1e-6);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(want.imag(), out[size_t(n_sym - 1 + k - 1)], 1e-6);
        }
        CPPUNIT_ASSERT_EQUAL(0.0f, out[size_t(11 - 1)]); // no pair 11 symbols apart
        // A frame of zeros has no shape: all zero, not NaN.
        std::vector<gr_complex> zeros(obs.size(), gr_complex(0.0f, 0.0f));
        plan.compute(zeros.data(), out.data());
        for (float x : out)
            CPPUNIT_ASSERT_EQUAL(0.0f, x);
    }

    void acf_picks_the_fullest_subcarrier()
    {
        // Two subcarriers with three pilots each: the lower one, whatever the mask order.
        const pilot_mask tie(8, 8, { { 0, 5 }, { 1, 5 }, { 3, 5 }, { 2, 2 }, { 4, 2 }, { 6, 2 }, { 7, 0 } });
        CPPUNIT_ASSERT_EQUAL(2, temporal::acf_plan(tie, "tie").subcarrier());
        // No subcarrier with two pilots: refused, naming the mask.
        const pilot_mask spread(8, 8, { { 0, 1 }, { 1, 2 }, { 2, 3 } });
        qa::assert_error([&] { temporal::acf_plan(spread, "my_mask.json"); }, "my_mask.json", "two pilots");
    }

    void steps_are_the_batch_forward()
    {
        torch::manual_seed(31);
        // The default network (receptive field 29 frames): a long track, one just past the
        // field, and tracks shorter than it, down to one frame.
        check_streaming(tcn_settings(), 14, 4, { 45, 30, 29, 12, 3, 1 });
        // Another shape: an even kernel, uneven dilations, one channel count.
        auto s = tcn_settings();
        s.channels = 5;
        s.kernel = 2;
        s.dilations = { 3, 1, 5, 2 };
        s.head = 6;
        check_streaming(s, 7, 3, { 20, 12, 11, 2 });
        auto one = tcn_settings(); // one tap: no memory but the running mean and maximum
        one.kernel = 1;
        one.dilations = { 1 };
        check_streaming(one, 5, 2, { 9, 4 });
    }

    // The decision after t frames does not move when later frames change.
    void forward_is_causal()
    {
        torch::manual_seed(32);
        nn::tcn_model m(10, 3, tcn_settings());
        scramble(*m, 0.2);
        m->eval();
        auto a = padded_evidence({ 40 }, 40, 10, 3);
        auto b = a.clone();
        b.slice(1, 25, 40).normal_();
        torch::NoGradGuard ng;
        const auto la = m->forward(a), lb = m->forward(b);
        CPPUNIT_ASSERT(torch::equal(la.slice(1, 0, 25), lb.slice(1, 0, 25)));
        CPPUNIT_ASSERT(!torch::equal(la.slice(1, 25, 40), lb.slice(1, 25, 40)));
    }

    // The written bundle loads with track_classifier, whose evidence is the pilots'
    // autocorrelation and the frame decoder's log-probabilities, and whose steps give the
    // trained model's forward frame by frame; the fusion beside it is that of the frames.
    // Tracks of one frame, K = 1024 and a ramp of 16: every weight (t/K)^16 = 2^-160 is 0 in a
    // float, so a loss of Σ ce·w / Σ w would be 0/0 and train NaN weights; the ramp's weights are
    // taken relative to a batch's largest, and the trained bundle decides finitely.
    void steep_ramp_on_short_tracks_trains_finite_weights()
    {
        const std::string dir = qa::temp_dir("track_tcn", "steep_ramp");
        const auto one_frame = scene::from_json(nlohmann::json::parse(R"({"format": "sems.scene", "version": 1,
            "classes": "kinematic", "random": {"classes": ["adult", "child"], "tracks": {"frames": 1}}})"),
                                                "qa_track_tcn one-frame scene");
        auto s = tiny_settings(dir, one_frame, 1024, 20, 8);
        s.epochs = 1;
        s.batch = 8;
        s.seed = 29;
        s.eval_frames = { 1 };
        s.temporal.head = 4;
        s.loss_ramp = 16.0;
        const auto r = train_track(s, nullptr);
        CPPUNIT_ASSERT(std::isfinite(r.history.at(0).at("loss").get<double>()));
        const track_classifier tc(model_bundle::load(dir), 1);
        const auto tracks = temporal::draw_tracks(tc.bundle().frame, *s.scene_spec, tc.bundle().mask, 3, 0, 2, 1,
                                                  tc.bundle().class_names);
        auto gen = at::detail::createCPUGenerator(7);
        const auto obs = temporal::observe_tracks(tracks, tc.bundle().mask, 20.0, 20.0, gen).contiguous();
        for (int64_t i = 0; i < 2; ++i) {
            auto fr = obs[i].slice(0, 0, 1).contiguous();
            const auto ev = tc.evidence(reinterpret_cast<const gr_complex*>(fr.data_ptr<float>()), 1);
            auto st = tc.begin();
            std::vector<float> p(size_t(tc.n_classes()));
            tc.step(st, ev.data(), p.data());
            for (float x : p)
                CPPUNIT_ASSERT(std::isfinite(x));
        }
    }

    void trained_bundle_streams_the_trainer_answers()
    {
        const auto& run = shared_tcn_run();
        const auto b = model_bundle::load(run.dir);
        CPPUNIT_ASSERT(track_classifier::is_track_bundle(b));
        CPPUNIT_ASSERT_EQUAL(std::string("acf_tcn"), b.track.at("temporal").at("kind").get<std::string>());
        CPPUNIT_ASSERT_EQUAL(1e-3, b.track.at("training").at("acf_tcn_lr").get<double>());
        CPPUNIT_ASSERT_EQUAL(1.0, b.track.at("training").at("loss_ramp").get<double>());
        CPPUNIT_ASSERT_EQUAL(size_t(2), b.track.at("training").at("history").size());
        track_classifier tc(b, 1);
        const int c = tc.n_classes(), e = tc.evidence_size(), np = tc.n_pilots();
        CPPUNIT_ASSERT_EQUAL(6, c); // the frame bundle's classes
        CPPUNIT_ASSERT_EQUAL(2 * (b.frame.n_symbols - 1) + c, e);
        CPPUNIT_ASSERT_EQUAL(std::string("acf_tcn"), tc.settings().kind);
        CPPUNIT_ASSERT_EQUAL(16, tc.settings().channels);

        const auto tracks = temporal::draw_tracks(b.frame, adults_children(), b.mask, 91, 0, 3, 8, b.class_names);
        auto gen = at::detail::createCPUGenerator(5);
        const auto obs = temporal::observe_tracks(tracks, b.mask, 10.0, 10.0, gen).contiguous();
        const auto model = nn::make_temporal_model(e, c, tc.settings());
        nn::load_module(model, run.dir + "/" + track_classifier::weights_file);
        model->eval();
        const bundle_decoder frames(b, 1);
        const temporal::acf_plan plan(b.mask, "qa");
        for (int64_t i = 0; i < 3; ++i) {
            const int64_t len = tracks.length[i].item<int64_t>();
            auto fr = obs[i].slice(0, 0, len).contiguous();
            const auto* y = reinterpret_cast<const gr_complex*>(fr.data_ptr<float>());
            const auto ev = tc.evidence(y, static_cast<int>(len));
            CPPUNIT_ASSERT_EQUAL(size_t(len * e), ev.size());
            // Its parts: the autocorrelation, then the frame decoder's log-probabilities.
            const auto fe = frames.evidence(y, static_cast<int>(len));
            std::vector<float> acf(static_cast<size_t>(plan.size()));
            for (int64_t f = 0; f < len; ++f) {
                plan.compute(y + f * np, acf.data());
                for (int k = 0; k < plan.size(); ++k)
                    CPPUNIT_ASSERT_EQUAL(acf[size_t(k)], ev[size_t(f * e + k)]);
                const int fs = frames.evidence_size();
                for (int k = 0; k < c; ++k)
                    CPPUNIT_ASSERT_EQUAL(fe[size_t(f * fs + fs - c + k)], ev[size_t(f * e + e - c + k)]);
            }
            torch::Tensor want;
            {
                torch::NoGradGuard ng;
                want = torch::softmax(
                    model->forward(torch::from_blob(const_cast<float*>(ev.data()), { 1, len, e }).clone()), -1)[0];
            }
            auto st = tc.begin();
            CPPUNIT_ASSERT_EQUAL(size_t(29 * e + 2 * 16 + 1), st.hidden.size());
            std::vector<double> sum(static_cast<size_t>(c), 0.0);
            std::vector<float> p(static_cast<size_t>(c)), q(static_cast<size_t>(c));
            for (int64_t f = 0; f < len; ++f) {
                tc.step(st, ev.data() + f * e, p.data(), q.data());
                CPPUNIT_ASSERT_EQUAL(uint64_t(f + 1), st.frames);
                double top = -std::numeric_limits<double>::infinity();
                for (int k = 0; k < c; ++k) {
                    sum[size_t(k)] += ev[size_t(f * e + e - c + k)];
                    top = std::max(top, sum[size_t(k)]);
                }
                double z = 0.0;
                for (int k = 0; k < c; ++k)
                    z += std::exp(sum[size_t(k)] - top);
                for (int k = 0; k < c; ++k) {
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(std::exp(sum[size_t(k)] - top) / z, q[size_t(k)], 1e-5);
                    if (f < tc.settings().fusion_frames) // the fusion decides the first frames
                        CPPUNIT_ASSERT_EQUAL(q[size_t(k)], p[size_t(k)]);
                    else
                        CPPUNIT_ASSERT_DOUBLES_EQUAL(want[f][k].item<float>(), p[size_t(k)], 1e-5);
                }
            }
        }
        // A frame with a NaN is refused as the frame decoder refuses it.
        std::vector<gr_complex> bad(static_cast<size_t>(np), gr_complex(1.0f, 0.0f));
        bad[3] = gr_complex(std::nanf(""), 0.0f);
        qa::assert_error([&] { tc.evidence(bad.data(), 1); }, "non-finite", "pilot 3");
        // A GRU's state is not this model's.
        auto st = tc.begin();
        st.hidden.resize(64);
        std::vector<float> zero(static_cast<size_t>(e), 0.0f), p(static_cast<size_t>(c));
        qa::assert_error([&] { tc.step(st, zero.data(), p.data()); }, "state of another model");
    }

    void bad_tcn_bundles_are_refused()
    {
        namespace fsys = std::filesystem;
        const auto& run = shared_tcn_run();
        const std::string dir = qa::temp_dir("track_tcn", "bad");
        auto broken = [&](const std::function<void(nlohmann::json&)>& f) {
            fsys::remove_all(dir);
            fsys::copy(run.dir, dir, fsys::copy_options::recursive);
            qa::edit_json(dir + "/bundle.json", f);
            return model_bundle::load(dir);
        };
        auto kind = [](const char* k) {
            return [k](nlohmann::json& j) {
                j["track"]["temporal"]["kind"] = k;
                j["track"]["temporal"]["settings"]["kind"] = k;
            };
        };
        qa::assert_error([&] { track_classifier(broken(kind("lstm"))); }, "bundle.json",
                         "unknown temporal model \"lstm\"");
        // Its settings read as a GRU's: a key of acf_tcn is unknown there.
        qa::assert_error([&] { track_classifier(broken(kind("gru_fusion"))); }, "bundle.json", "channels");
        // Weights of another shape: the weights file is named.
        auto wider = [](nlohmann::json& j) { j["track"]["temporal"]["settings"]["channels"] = 17; };
        qa::assert_error([&] { track_classifier(broken(wider)); }, "temporal.pt");
        fsys::remove_all(dir);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_track_tcn);
