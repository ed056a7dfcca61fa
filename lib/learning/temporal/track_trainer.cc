// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: training a decision over a track (see track_trainer.h). */
#include <gnuradio/sems/learning/temporal/track_trainer.h>
#include "learning/networks/task_decoder.h"
#include "learning/temporal/temporal_model.h"
#include "learning/temporal/track_evidence.h"
#include "learning/temporal/super_frame_learner.h"
#include "learning/temporal/track_data.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <ATen/CPUGeneratorImpl.h>
#include <stdexcept>

namespace gr {
namespace sems {

// Named, not anonymous: the unity build puts this file beside others with helpers of their own.
namespace track_trainer_detail {
[[noreturn]] void bad(const std::string& field, const std::string& problem)
{
    throw std::invalid_argument("track training: " + field + ": " + problem);
}

// The tracks' splits: 8:1:1 of `tracks`, by track index.
struct splits {
    int64_t train, val, test;
    explicit splits(int64_t tracks) : train(tracks * 8 / 10), val(tracks / 10), test(tracks - train - tracks / 10) {}
};

// The scene the tracks come from: the settings', or the frame bundle's training scene followed
// over tracks of K frames with gains new every frame.
scene track_scene(const track_training_settings& s, const model_bundle& frame)
{
    if (s.scene_spec) {
        if (!s.scene_spec->is_random() || !s.scene_spec->random_settings()->tracks)
            bad("scene", s.scene_source + " draws a new target every frame: give it random.tracks");
        return *s.scene_spec;
    }
    if (!frame.training.contains("scene"))
        bad("scene", "the frame bundle " + frame.directory + " records no training scene: give one");
    const auto sc = scene::from_json(frame.training.at("scene"), frame.directory + ": training.scene");
    if (!sc.is_random())
        bad("scene", "the frame bundle " + frame.directory + " was trained on a fixed scene: give a tracked one");
    auto r = *sc.random_settings();
    track_draw_spec t;
    t.frames_min = t.frames_max = s.track_frames;
    r.tracks = t;
    return scene::random(r, sc.clutter(), sc.fading(), sc.library_ptr());
}

// The temporal model's evidence of every frame of `obs` (count x K x N_p x 2) inside its
// track (`length`), as count x K x E (zero past a track's end).
torch::Tensor evidence_of(const temporal::track_evidence& evidence,
                          const torch::Tensor& obs,
                          const torch::Tensor& length,
                          const torch::Tensor& set)
{
    const int64_t e = evidence.size();
    const int64_t count = obs.size(0), k = obs.size(1), np = obs.size(2);
    auto valid = (torch::arange(k, torch::kLong).view({ 1, k }) < length.view({ count, 1 })).flatten();
    auto rows = valid.nonzero().flatten();
    auto flat = obs.reshape({ count * k, np, 2 }).index_select(0, rows).contiguous();
    auto sets = set.reshape({ count * k }).index_select(0, rows).to(torch::kInt).contiguous();
    const int* ps = sets.data_ptr<int>();
    auto out = torch::zeros({ count * k, e }, torch::kFloat);
    constexpr int64_t step = 4096;
    const auto* p = reinterpret_cast<const gr_complex*>(flat.data_ptr<float>());
    std::vector<float> ev;
    auto part = torch::empty({ 0 });
    for (int64_t a = 0; a < rows.size(0); a += step) {
        const int64_t b = std::min(rows.size(0), a + step);
        ev = evidence(p + a * np, static_cast<int>(b - a), ps + a);
        out.index_copy_(0, rows.slice(0, a, b), torch::from_blob(ev.data(), { b - a, e }, torch::kFloat).clone());
    }
    return out.view({ count, k, e });
}

// 1 where frame t of a track is inside it: count x K.
torch::Tensor valid_frames(const torch::Tensor& length, int64_t k)
{
    return torch::arange(k, torch::kLong).view({ 1, k }) < length.view({ -1, 1 });
}

// Accuracy and macro-F1 of predictions `pred` against `label` (both long, n), C classes.
std::pair<double, double> scores(const torch::Tensor& pred, const torch::Tensor& label, int64_t c)
{
    const int64_t n = label.size(0);
    if (n == 0)
        return { 0.0, 0.0 };
    auto pp = pred.accessor<int64_t, 1>();
    auto pl = label.accessor<int64_t, 1>();
    std::vector<double> tp(c, 0.0), fp(c, 0.0), fn(c, 0.0);
    double correct = 0.0;
    for (int64_t i = 0; i < n; ++i) {
        if (pp[i] == pl[i]) {
            ++correct;
            ++tp[pl[i]];
        } else {
            ++fp[pp[i]];
            ++fn[pl[i]];
        }
    }
    double f1 = 0.0;
    int present = 0;
    for (int64_t j = 0; j < c; ++j) {
        if (tp[j] + fn[j] == 0.0)
            continue; // a class absent from the test tracks does not count
        ++present;
        const double d = 2 * tp[j] + fp[j] + fn[j];
        f1 += d > 0.0 ? 2 * tp[j] / d : 0.0;
    }
    return { correct / n, present ? f1 / present : 0.0 };
}
} // namespace track_trainer_detail
using namespace track_trainer_detail;

void track_training_settings::validate() const
{
    if (frame_bundle.empty())
        bad("frame_bundle", "give the per-frame classifier bundle the decision builds on");
    if (track_frames < 1 || track_frames > limits::max_track_frames)
        bad("track_frames", "must be in [1, " + std::to_string(limits::max_track_frames) + "], got " +
                                std::to_string(track_frames));
    if (tracks < 10)
        bad("tracks", "must be at least 10 (split 8:1:1), got " + std::to_string(tracks));
    if (!(std::isfinite(snr_min_db) && std::isfinite(snr_max_db) && snr_min_db <= snr_max_db))
        bad("snr", "need finite snr_min_db <= snr_max_db, got [" + std::to_string(snr_min_db) + ", " +
                       std::to_string(snr_max_db) + "]");
    if (epochs < 1)
        bad("epochs", "must be >= 1");
    if (batch < 1)
        bad("batch", "must be >= 1");
    if (!(lr > 0.0 && std::isfinite(lr)))
        bad("lr", "must be a finite number > 0");
    if (!(acf_tcn_lr > 0.0 && std::isfinite(acf_tcn_lr)))
        bad("acf_tcn_lr", "must be a finite number > 0");
    if (!(loss_ramp >= 0.0 && loss_ramp <= 16.0))
        bad("loss_ramp", "must be in [0, 16], got " + std::to_string(loss_ramp));
    if (!(weight_decay >= 0.0 && std::isfinite(weight_decay)))
        bad("weight_decay", "must be a finite number >= 0");
    if (!(temporal.dropout >= 0.0 && temporal.dropout < 1.0))
        bad("temporal.dropout", "must be in [0, 1)");
    if (patience < 1)
        bad("patience", "must be >= 1");
    for (double x : eval_snr_db)
        if (std::isnan(x))
            bad("eval_snr_db", "NaN");
    for (int f : eval_frames)
        if (f < 1 || f > track_frames)
            bad("eval_frames", std::to_string(f) + " frames is outside the training tracks' [1, " +
                                   std::to_string(track_frames) + "]");
    if (temporal.hidden < 1)
        bad("temporal.hidden", "must be >= 1");
    temporal.validate("track training: temporal");
    if (super_frames < 1 || super_frames > limits::max_super_frames)
        bad("super_frames", "must be in [1, " + std::to_string(limits::max_super_frames) + "], got " +
                                std::to_string(super_frames));
    if (super_frames > 1) {
        if (out_dir.empty())
            bad("out_dir", "a super-frame of " + std::to_string(super_frames) +
                               " sets is learned with its frame decoder, which is written there: give one");
        if (mask_epochs < 1)
            bad("mask_epochs", "must be >= 1");
        if (mask_tracks < 1 || mask_tracks > tracks * 8 / 10)
            bad("mask_tracks", "must be in [1, " + std::to_string(tracks * 8 / 10) + "] (the training tracks), got " +
                                   std::to_string(mask_tracks));
        if (!(mask_lr > 0.0 && std::isfinite(mask_lr)))
            bad("mask_lr", "must be a finite number > 0");
        if (!(mask_encoder_lr > 0.0 && std::isfinite(mask_encoder_lr)))
            bad("mask_encoder_lr", "must be a finite number > 0");
        if (mask_start != "frame" && mask_start != "random")
            bad("mask_start", "must be \"frame\" or \"random\", got \"" + mask_start + "\"");
    }
}

nlohmann::json track_training_settings::to_json() const
{
    nlohmann::json j = { { "frame_bundle", frame_bundle },
                         { "scene_source", scene_source },
                         { "track_frames", track_frames },
                         { "tracks", tracks },
                         { "split", "8:1:1" },
                         { "snr_min_db", snr_min_db },
                         { "snr_max_db", snr_max_db },
                         { "epochs", epochs },
                         { "batch", batch },
                         { "lr", lr },
                         { "weight_decay", weight_decay },
                         { "patience", patience },
                         { "seed", seed },
                         { "threads", threads },
                         { "eval_snr_db", eval_snr_db },
                         { "eval_frames", eval_frames },
                         { "super_frames", super_frames },
                         { "mask_epochs", mask_epochs },
                         { "mask_tracks", mask_tracks },
                         { "mask_lr", mask_lr },
                         { "mask_encoder_lr", mask_encoder_lr },
                         { "mask_start", mask_start },
                         { "command_line", command_line } };
    // The keys a gru_fusion run without a ramp always wrote, and the others where they apply
    // (a record of such a run, and a cache keyed on it, stays as it was).
    if (temporal.kind == "acf_tcn")
        j["acf_tcn_lr"] = acf_tcn_lr;
    if (loss_ramp != 0.0)
        j["loss_ramp"] = loss_ramp;
    return j;
}

track_training_result train_track(const track_training_settings& s, std::ostream* log)
{
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    s.validate();
    if (s.threads > 0)
        at::set_num_threads(s.threads);
    torch::manual_seed(s.seed);
    auto frame = model_bundle::load(s.frame_bundle);
    if (frame.task != task_kind::classify)
        bad("frame_bundle", frame.directory + " is a \"" + task_name(frame.task) + "\" bundle, not a classifier");
    if (!frame.track.is_null())
        bad("frame_bundle", frame.directory + " is already a track bundle: give its per-frame bundle");
    const scene sc = track_scene(s, frame);
    frame.check_library(sc.library(), "track training");
    const splits sp(s.tracks);
    auto say = [&](const std::string& line) {
        if (log && s.verbose)
            *log << line << std::endl;
    };
    // A super-frame: its F sets and the frame decoder learned with them first, written into
    // out_dir as the frame half of the track bundle (the frame bundle itself stays as it is).
    nlohmann::json super_frame_history;
    if (s.super_frames > 1) {
        if (frame.super_frames() > 1)
            bad("frame_bundle", frame.directory + "'s mask already spans " + std::to_string(frame.super_frames()) +
                                    " frames: give a bundle of one frame's mask to learn a super-frame from");
        namespace fsys = std::filesystem;
        std::error_code ec;
        if (fsys::equivalent(s.out_dir, frame.directory, ec))
            bad("out_dir", s.out_dir + " is the frame bundle's own directory: write the track bundle elsewhere");
        const int64_t val_tracks = std::min<int64_t>(sp.val, 400);
        auto learned = temporal::learn_super_frame(frame, sc, s, sp.train, val_tracks, say);
        super_frame_history = learned.history;
        frame.super_frame = learned.masks;
        frame.mask = learned.masks.set(0);
        frame.weights_name = model_bundle::weights_file;
        frame.save(s.out_dir);
        nn::save_module(learned.decoder, (fsys::path(s.out_dir) / frame.weights_name).string());
        frame.directory = s.out_dir;
    }
    bundle_decoder frames(frame, s.threads);
    const temporal::track_evidence evidence(frames, s.temporal); // as the track classifier reads it
    const int64_t c = static_cast<int64_t>(frame.class_names.size());
    const int64_t e = evidence.size(); // the model's inputs, then C log-probabilities
    const int64_t k = s.track_frames;
    const super_frame_mask masks = frame.super_frame ? *frame.super_frame : super_frame_mask(frame.mask);

    // The tracks: train, validation and test, each track from (seed, index) alone.
    auto draw = [&](int64_t first, int64_t count) {
        return temporal::draw_tracks(frame.frame, sc, masks, s.seed, first, count, s.track_frames, frame.class_names);
    };
    const auto td0 = clock::now();
    const auto train = draw(0, sp.train), val = draw(sp.train, sp.val), test = draw(sp.train + sp.val, sp.test);
    say("tracks: " + std::to_string(sp.train) + " train, " + std::to_string(sp.val) + " validation, " +
        std::to_string(sp.test) + " test, " + std::to_string(k) + " frames each at most (" +
        std::to_string(std::chrono::duration<double>(clock::now() - td0).count()) + " s to draw)");

    const auto model = nn::make_temporal_model(static_cast<int>(e), static_cast<int>(c), s.temporal);
    const double lr = s.temporal.kind == "acf_tcn" ? s.acf_tcn_lr : s.lr;
    torch::optim::AdamW opt(model->parameters(), torch::optim::AdamWOptions(lr).weight_decay(s.weight_decay));
    auto gen = at::detail::createCPUGenerator(s.seed ^ 0x747261636b6e6f69ULL);
    const auto val_obs = temporal::observe_tracks(val, masks, s.snr_min_db, s.snr_max_db, gen);
    const auto val_ev = evidence_of(evidence, val_obs, val.length, val.set);
    const auto val_valid = valid_frames(val.length, k);

    // Mean accuracy of the decision after every frame of every track (the validation score).
    auto mean_accuracy = [&](const torch::Tensor& ev, const torch::Tensor& label, const torch::Tensor& valid) {
        torch::NoGradGuard ng;
        model->eval();
        auto pred = model->forward(ev).argmax(-1);
        auto ok = (pred == label.view({ -1, 1 })) & valid;
        return ok.sum().item<double>() / valid.sum().item<double>();
    };

    // The log of the loss's weight of the decision after t = 1..K frames, γ·log(t/K) (loss_ramp
    // > 0 only): a batch's weights are taken relative to its largest, so tracks far shorter than
    // K with a steep ramp cannot underflow every weight to 0 (and the loss to 0/0).
    const auto log_ramp = (s.loss_ramp * torch::log(torch::arange(1, k + 1, torch::kDouble) / double(k)))
                              .to(torch::kFloat)
                              .view({ 1, k });
    track_training_result result;
    result.history = nlohmann::json::array();
    double best = -1.0;
    int since_best = 0;
    std::vector<torch::Tensor> best_state;
    for (int epoch = 1; epoch <= s.epochs; ++epoch) {
        const auto te = clock::now();
        // New noise each epoch, then the frame decoder once over every training frame.
        const auto obs = temporal::observe_tracks(train, masks, s.snr_min_db, s.snr_max_db, gen);
        const auto ev = evidence_of(evidence, obs, train.length, train.set);
        const auto valid = valid_frames(train.length, k);
        model->train();
        auto order = torch::randperm(sp.train, gen, torch::kLong);
        double loss_sum = 0.0;
        int64_t steps = 0;
        for (int64_t a = 0; a < sp.train; a += s.batch) {
            auto idx = order.slice(0, a, std::min<int64_t>(sp.train, a + s.batch));
            auto logits = model->forward(ev.index_select(0, idx));
            auto v = valid.index_select(0, idx).flatten();
            auto lbl = train.label.index_select(0, idx).view({ -1, 1 }).expand({ idx.size(0), k }).flatten();
            auto rows = v.nonzero().flatten();
            torch::Tensor loss;
            if (s.loss_ramp == 0.0) {
                loss = torch::nn::functional::cross_entropy(logits.reshape({ -1, c }).index_select(0, rows),
                                                            lbl.index_select(0, rows));
            } else { // the decision after t frames weighs (t/K)^ramp
                auto ce = torch::nn::functional::cross_entropy(
                    logits.reshape({ -1, c }).index_select(0, rows), lbl.index_select(0, rows),
                    torch::nn::functional::CrossEntropyFuncOptions().reduction(torch::kNone));
                auto lw = log_ramp.expand({ idx.size(0), k }).flatten().index_select(0, rows);
                auto w = (lw - lw.max()).exp(); // the largest is 1
                loss = (ce * w).sum() / w.sum();
            }
            opt.zero_grad();
            loss.backward();
            opt.step();
            loss_sum += loss.item<double>();
            ++steps;
        }
        const double acc = mean_accuracy(val_ev, val.label, val_valid);
        const double secs = std::chrono::duration<double>(clock::now() - te).count();
        result.history.push_back({ { "epoch", epoch }, { "loss", loss_sum / std::max<int64_t>(1, steps) },
                                   { "val_mean_accuracy", acc }, { "seconds", secs } });
        std::ostringstream line;
        line << "epoch " << epoch << "/" << s.epochs << ": loss " << std::setprecision(4) << loss_sum / std::max<int64_t>(1, steps)
             << ", validation accuracy over every frame of the tracks " << acc << " (" << std::setprecision(3) << secs
             << " s)";
        say(line.str());
        if (acc > best) {
            best = acc;
            since_best = 0;
            best_state.clear();
            for (const auto& p : model->parameters())
                best_state.push_back(p.detach().clone());
        } else if (++since_best >= s.patience) {
            say("early stop: no better validation for " + std::to_string(s.patience) + " epochs");
            break;
        }
    }
    {
        torch::NoGradGuard ng;
        auto params = model->parameters();
        for (size_t i = 0; i < params.size(); ++i)
            params[i].copy_(best_state[i]);
    }
    model->eval();
    // The leading frames over which the fusion decides better on the validation tracks are
    // left to it (temporal_settings::fusion_frames).
    {
        torch::NoGradGuard ng;
        auto learned = model->forward(val_ev).argmax(-1);
        auto fused = val_ev.slice(2, e - c, e).cumsum(1).argmax(-1);
        auto truth = val.label.view({ -1, 1 });
        auto n = val_valid.sum(0).to(torch::kDouble).clamp_min(1.0);
        auto learned_acc = ((learned == truth) & val_valid).sum(0).to(torch::kDouble) / n;
        auto fused_acc = ((fused == truth) & val_valid).sum(0).to(torch::kDouble) / n;
        int lead = 0;
        while (lead < k && learned_acc[lead].item<double>() < fused_acc[lead].item<double>())
            ++lead;
        model->set_fusion_frames(lead);
        say("the fusion decides the first " + std::to_string(lead) +
            " frame(s) of a track (better than the " + (s.temporal.kind == "gru_fusion" ? "GRU" : "convolutions") +
            " there on the validation tracks)");
    }

    // The test tracks at each SNR: the decision after t frames, and the fusion of independent
    // frames on the very same frames, over the tracks that last t frames.
    nlohmann::json by_snr = nlohmann::json::array();
    for (size_t i = 0; i < s.eval_snr_db.size(); ++i) {
        const double snr = s.eval_snr_db[i];
        auto g = at::detail::createCPUGenerator(s.seed * 1000003ULL + 17 + i);
        const auto obs = temporal::observe_tracks(test, masks, snr, snr, g);
        const auto ev = evidence_of(evidence, obs, test.length, test.set);
        torch::Tensor pred, fused;
        {
            torch::NoGradGuard ng;
            pred = model->decide(model->forward(ev), ev);
            fused = ev.slice(2, e - c, e).cumsum(1).argmax(-1);
        }
        nlohmann::json rows = nlohmann::json::array();
        std::ostringstream line;
        line << "test at " << snr << " dB:";
        for (int t : s.eval_frames) {
            auto keep = (test.length >= t).nonzero().flatten();
            auto label = test.label.index_select(0, keep);
            const auto a = scores(pred.select(1, t - 1).index_select(0, keep).contiguous(), label, c);
            const auto f = scores(fused.select(1, t - 1).index_select(0, keep).contiguous(), label, c);
            rows.push_back({ { "frames", t },
                             { "tracks", keep.size(0) },
                             { "accuracy", a.first },
                             { "macro_f1", a.second },
                             { "fusion_accuracy", f.first },
                             { "fusion_macro_f1", f.second } });
            line << " " << t << " frames " << std::setprecision(3) << a.first << " (fusion " << f.first << ")";
        }
        say(line.str());
        // Confusion after the longest observation time scored, for both (rows: truth).
        const int t_max = *std::max_element(s.eval_frames.begin(), s.eval_frames.end());
        auto keep = (test.length >= t_max).nonzero().flatten();
        auto confusion = [&](const torch::Tensor& p) {
            std::vector<std::vector<int64_t>> m(c, std::vector<int64_t>(c, 0));
            auto pp = p.select(1, t_max - 1).index_select(0, keep).contiguous();
            auto ll = test.label.index_select(0, keep).contiguous();
            for (int64_t j = 0; j < keep.size(0); ++j)
                ++m[ll[j].item<int64_t>()][pp[j].item<int64_t>()];
            return m;
        };
        by_snr.push_back({ { "snr_db", snr },
                           { "by_frames", rows },
                           { "confusion_frames", t_max },
                           { "confusion", confusion(pred) },
                           { "fusion_confusion", confusion(fused) } });
    }
    result.metrics = { { "test_tracks", sp.test }, { "by_snr", by_snr } };

    // The track bundle: the frame bundle's files and the track record.
    result.bundle = frame;
    auto training = s.to_json();
    training["history"] = result.history;
    training["scene"] = sc.to_json();
    if (s.super_frames > 1)
        training["super_frame_history"] = super_frame_history;
    result.bundle.track = { { "frames", s.track_frames },
                            { "temporal", model->describe() },
                            { "weights_file", track_classifier::weights_file },
                            { "training", training },
                            { "metrics", result.metrics } };
    if (!s.out_dir.empty()) {
        namespace fsys = std::filesystem;
        std::error_code ec;
        if (s.super_frames == 1 && fsys::equivalent(s.out_dir, frame.directory, ec))
            bad("out_dir", s.out_dir + " is the frame bundle's own directory: write the track bundle elsewhere");
        result.bundle.save(s.out_dir);
        if (s.super_frames == 1) // a super-frame's decoder is already there
            fsys::copy_file(frame.weights_path(), fsys::path(s.out_dir) / frame.weights_name,
                            fsys::copy_options::overwrite_existing, ec);
        if (ec)
            bad("out_dir", "cannot copy " + frame.weights_path() + " into " + s.out_dir + " (" + ec.message() + ")");
        nn::save_module(model, (fsys::path(s.out_dir) / track_classifier::weights_file).string());
        result.bundle.directory = s.out_dir;
        say("wrote " + s.out_dir);
    }
    result.seconds = std::chrono::duration<double>(clock::now() - t0).count();
    return result;
}

} // namespace sems
} // namespace gr
