// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 8: decisions over a track. Accuracy and macro-F1 against observation
 * time (frames of a track) and SNR on the kinematic library (any heading, Rayleigh gains new
 * every frame), every method on the same test tracks:
 *   - SemS-track: the SemS frame bundle (learned mask) under the temporal decoder;
 *   - the SemS decoder on the hand patterns (Doppler, staggered; burst below N pilots) under
 *     the same temporal decoder, trained the same way;
 *   - the fusion of independent frames (the product of per-frame posteriors) of each of those
 *     frame bundles, and of MSE-DL's;
 *   - the feature SVM over the track (the Doppler-spectrum moments of the Doppler pattern's
 *     pilots, their mean and standard deviation over the frames given);
 *   - the Perfect-CSI spectrogram CNN (the whole noiseless grid of every frame).
 * Per-track decisions go beside the scores (exp8_predictions.csv, exp8_truth.csv), for the
 * paired statistics of apps/figures/plot_tracks.py. */
#include "eval.h"
#include "spectrogram_cnn.h"
#include <gnuradio/sems/baselines/doppler_features.h>
#include <gnuradio/sems/baselines/feature_svm.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <gnuradio/sems/learning/temporal/track_trainer.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <sstream>
#include <thread>

namespace sems_eval {

namespace {

namespace fsys = std::filesystem;

// The recognition scene of experiment 7, each target followed over `frames` frames.
scene tracked_scene(const scene& sc, int frames)
{
    auto r = *sc.random_settings();
    track_draw_spec t;
    t.frames_min = t.frames_max = frames;
    r.tracks = t;
    return scene::random(r, sc.clutter(), sc.fading(), sc.library_ptr());
}

// Visits tracks 0 .. count - 1 of `tsc`, each drawn alone from (seed, index) by c.threads
// workers (one channel model each): visit(i, len, class id, grids, noise) gets the track's
// first len <= frames noiseless grids (len x N x M) and unit-variance noise of the same shape,
// drawn from (seed, i) too, so a track is the same whichever worker draws it (with_noise
// false: no noise is drawn and visit gets nullptr). Only one track per worker is in memory.
template <typename Visit>
void for_each_track(const config& c, const scene& tsc, int count, int frames, uint64_t seed, bool with_noise, Visit visit)
{
    const size_t grid = c.fs.grid_size();
    const int workers = std::max(1, std::min(c.threads, count));
    std::vector<std::thread> pool;
    for (int w = 0; w < workers; ++w)
        pool.emplace_back([&, w] {
            channel_model cm(c.fs, tsc, seed);
            frame_realization r;
            std::vector<gr_complex> h(size_t(frames) * grid), noise(with_noise ? size_t(frames) * grid : 0);
            for (int i = w; i < count; i += workers) {
                const int len = std::min(frames, cm.begin_track(static_cast<uint64_t>(i)));
                std::mt19937_64 g(seed * 0x9e3779b97f4a7c15ULL + uint64_t(i) * 0xbf58476d1ce4e5b9ULL + 1);
                std::normal_distribution<float> half(0.0f, std::sqrt(0.5f));
                int label = -1;
                for (int f = 0; f < len; ++f) {
                    cm.draw(static_cast<uint64_t>(f), r);
                    if (f == 0)
                        label = r.truth.class_id;
                    cm.factors(r, 0).fill(h.data() + size_t(f) * grid); // the track's own clock
                }
                if (with_noise)
                    for (size_t k = 0; k < size_t(len) * grid; ++k)
                        noise[k] = gr_complex(half(g), half(g));
                visit(i, len, label, h.data(), with_noise ? noise.data() : nullptr);
            }
        });
    for (auto& th : pool)
        th.join();
}

// The test tracks: their noiseless grids and unit-variance noise kept (the same noise at every
// SNR and for every method, as test_set).
struct track_grids {
    int count = 0, frames = 0;
    test_set grids;             // count * frames grids (track-major); zero past a track's end
    std::vector<int> length;    // frames of each track, 1..frames
    std::vector<int> label;     // class id in the scene's library
    const gr_complex* h(int track) const { return grids.h.data() + size_t(track) * frames * grids.fs.grid_size(); }
};

track_grids draw_track_grids(const config& c, const scene& tsc, int count, int frames, uint64_t seed)
{
    track_grids t;
    t.count = count;
    t.frames = frames;
    t.grids.fs = c.fs;
    t.grids.count = count * frames;
    const size_t grid = c.fs.grid_size(), n = size_t(count) * frames * grid;
    t.grids.h.assign(n, gr_complex(0.0f, 0.0f));
    t.grids.w.assign(n, gr_complex(0.0f, 0.0f));
    t.length.assign(count, 0);
    t.label.assign(count, -1);
    for_each_track(c, tsc, count, frames, seed, true,
                   [&](int i, int len, int label, const gr_complex* h, const gr_complex* w) {
                       t.length[i] = len;
                       t.label[i] = label;
                       const size_t at = size_t(i) * frames * grid;
                       std::copy(h, h + size_t(len) * grid, t.grids.h.begin() + at);
                       std::copy(w, w + size_t(len) * grid, t.grids.w.begin() + at);
                   });
    return t;
}

// A method's decisions: count x eval frames, the class id after t frames (-1: track shorter).
using answers = std::vector<int>;

const std::vector<std::string> score_header{ "experiment", "scenario", "method", "mask", "n_pilots", "snr_db",
                                             "frames", "accuracy", "macro_f1", "n_tracks", "seed", "train_seed",
                                             "us_per_frame", "train_seconds", "model" };
const std::vector<std::string> prediction_header{ "method", "n_pilots", "snr_db", "train_seed", "frames", "predicted" };

class track_scorer
{
public:
    track_scorer(const config& c, const track_grids& tests, const scene& sc, uint64_t test_seed, std::ostream& log)
        : d_c(c), d_tests(tests), d_sc(sc), d_test_seed(test_seed), d_log(log),
          d_scores(c.out_dir + "/exp8_tracks.csv", score_header),
          d_predictions(c.out_dir + "/exp8_predictions.csv", prediction_header)
    {
        csv_file truth(c.out_dir + "/exp8_truth.csv", { "track", "class_id", "class", "frames" });
        for (int i = 0; i < tests.count; ++i)
            truth.row({ std::to_string(i), std::to_string(tests.label[i]), sc.library().at(tests.label[i]).name,
                        std::to_string(tests.length[i]) });
    }

    void write(const std::string& method, const std::string& mask, int np, double snr, const answers& a,
               double us, double train_s, const std::string& model, std::optional<uint64_t> train_seed)
    {
        const auto& ef = d_c.exp8_frames;
        const std::string seed_label = train_seed_label(train_seed);
        std::ostringstream line;
        line << "  " << method << " [N_p " << np << ", train seed " << seed_label << "] " << num(snr) << " dB:";
        for (size_t j = 0; j < ef.size(); ++j) {
            std::vector<int> pred, truth;
            std::ostringstream all;
            for (int i = 0; i < d_tests.count; ++i) {
                const int p = a[size_t(i) * ef.size() + j];
                all << (i ? " " : "") << p;
                if (d_tests.length[i] >= ef[j]) {
                    pred.push_back(p);
                    truth.push_back(d_tests.label[i]);
                }
            }
            d_predictions.row({ method, std::to_string(np), num(snr), seed_label, std::to_string(ef[j]), all.str() });
            if (truth.empty())
                continue;
            const class_score s = score(pred, truth, d_sc.library().size());
            d_scores.row({ "8", "kinematic tracks", method, mask, std::to_string(np), num(snr), std::to_string(ef[j]),
                           num(s.accuracy), num(s.macro_f1), std::to_string(truth.size()),
                           std::to_string(d_test_seed), seed_label, num(us, 4), num(train_s, 4), model });
            line << " " << ef[j] << ":" << num(s.accuracy, 3);
        }
        d_log << line.str() << std::endl;
    }

    const track_grids& tests() const { return d_tests; }
    const scene& sc() const { return d_sc; }

private:
    const config& d_c;
    const track_grids& d_tests;
    const scene& d_sc;
    uint64_t d_test_seed;
    std::ostream& d_log;
    csv_file d_scores, d_predictions;
};

// Where eval frame j sits: the index of t in exp8_frames, or -1.
std::vector<int> eval_slot(const config& c)
{
    std::vector<int> slot(size_t(c.exp8_track_frames) + 1, -1);
    for (size_t j = 0; j < c.exp8_frames.size(); ++j)
        slot[size_t(c.exp8_frames[j])] = static_cast<int>(j);
    return slot;
}

// The temporal decoder on a frame bundle, trained once per settings (cached beside it).
struct track_source {
    model_bundle bundle;
    double train_seconds = 0.0; // the frame bundle's and the temporal model's
    std::string origin;
};

track_source train_or_load_track(const config& c, const std::string& frame_name, const decoder_source& frame,
                                 uint64_t train_seed, std::ostream& log, int super_frames = 1,
                                 const std::string& super_frame_start = "frame")
{
    track_training_settings s;
    s.super_frames = super_frames;
    s.mask_start = super_frame_start;
    s.mask_tracks = std::min(s.mask_tracks, c.exp8_train_tracks * 8 / 10); // the learner's share of the training tracks
    s.frame_bundle = frame.bundle.directory;
    s.track_frames = c.exp8_track_frames;
    s.tracks = c.exp8_train_tracks;
    s.snr_min_db = c.train_snr_min_db;
    s.snr_max_db = c.train_snr_max_db;
    s.epochs = c.exp8_track_epochs;
    s.seed = train_seed;
    s.threads = c.threads;
    s.eval_snr_db = { 10.0 }; // its own test tenth: a progress line only (the experiment's tracks score it)
    s.eval_frames = { 1, c.exp8_track_frames };
    s.verbose = false;
    const std::string name = frame_name +
                             (super_frames > 1 ? "_sf" + std::to_string(super_frames) +
                                                     (super_frame_start == "frame" ? "" : "_" + super_frame_start)
                                               : "") +
                             "_track";
    const auto dir = fsys::path(c.out_dir) / "bundles" / name;
    s.out_dir = dir.string();
    auto key = s.to_json();
    key.erase("command_line");
    key["temporal"] = s.temporal.to_json();
    if (super_frames == 1) // one frame's mask: the keys of bundles cached before super-frames existed
        for (const char* k : { "super_frames", "mask_epochs", "mask_tracks", "mask_lr", "mask_encoder_lr", "mask_start" })
            key.erase(k);
    // A frame bundle trained anew (other settings) makes its temporal decoder stale too.
    key["frame_key"] = read_eval_key(frame.bundle.directory).value("key", nlohmann::json());
    key = nlohmann::json::parse(key.dump());
    const auto key_file = dir / "eval_key.json";
    track_source out;
    if (fsys::exists(key_file) && fsys::exists(dir / model_bundle::bundle_file)) {
        const auto stored = read_eval_key(dir.string());
        if (c.reuse_bundles || stored.value("key", nlohmann::json()) == key) {
            out.bundle = model_bundle::load(dir.string());
            out.train_seconds = frame.train_seconds + stored.value("train_seconds", 0.0);
            out.origin = "cached";
            log << "[" << now_utc() << "] model " << name << ": reusing " << dir.string() << std::endl;
            return out;
        }
    }
    s.command_line = c.command_line + "  [sems_eval model " + name + "]";
    log << "[" << now_utc() << "] model " << name << ": training the temporal decoder (" << s.tracks << " tracks of "
        << s.track_frames << " frames, " << s.epochs << " epochs, seed " << train_seed << ")" << std::endl;
    fsys::create_directories(dir);
    const auto res = train_track(s, nullptr);
    out.bundle = model_bundle::load(dir.string());
    out.train_seconds = frame.train_seconds + res.seconds;
    out.origin = "trained";
    std::ofstream(key_file) << nlohmann::json{ { "key", key }, { "train_seconds", res.seconds } }.dump(1);
    log << "[" << now_utc() << "] model " << name << ": trained in " << num(res.seconds, 4) << " s" << std::endl;
    return out;
}

int argmax(const float* p, int n) { return static_cast<int>(std::max_element(p, p + n) - p); }

// The set each frame of the test tracks is read at: frame f of track i at (i + f) mod F (the
// training's rule: a track starts at any phase of the super-frame); all 0 for F = 1.
std::vector<int> frame_sets(const track_grids& t, int n_sets)
{
    std::vector<int> sets(size_t(t.count) * t.frames);
    for (int i = 0; i < t.count; ++i)
        for (int f = 0; f < t.frames; ++f)
            sets[size_t(i) * t.frames + f] = (i + f) % n_sets;
    return sets;
}

// The test tracks' observations (count*K x N_p), each frame at the pilots of its set, with the
// one noise draw every method sees at each element.
std::vector<gr_complex> observe_sets(const track_grids& t, const model_bundle& b, const std::vector<int>& sets, double snr)
{
    auto obs = t.grids.observe(b.mask_of_set(0), snr);
    const size_t np = static_cast<size_t>(b.mask.size());
    for (int set = 1; set < b.super_frames(); ++set) {
        const auto other = t.grids.observe(b.mask_of_set(set), snr);
        for (size_t r = 0; r < sets.size(); ++r)
            if (sets[r] == set)
                std::copy(other.begin() + r * np, other.begin() + (r + 1) * np, obs.begin() + r * np);
    }
    return obs;
}

// A track bundle on the test tracks at every SNR: the decision over the track and, from the
// same frames, the fusion of independent frames.
void score_track_bundle(const config& c, track_scorer& out, const track_source& src, const std::string& method,
                        const std::string& fusion_method, const std::string& mask_label,
                        std::optional<uint64_t> train_seed)
{
    const auto& t = out.tests();
    const track_classifier tc(src.bundle, c.threads);
    const auto ids = output_classes(src.bundle, out.sc());
    const int np = tc.n_pilots(), e = tc.evidence_size(), nc = tc.n_classes(), k = t.frames;
    const auto slot = eval_slot(c);
    const size_t ne = c.exp8_frames.size();
    const auto sets = frame_sets(t, tc.super_frames());
    for (double snr : c.snrs) {
        const auto obs = observe_sets(t, src.bundle, sets, snr); // count*K x N_p, zero past a track's end
        answers track(size_t(t.count) * ne, -1), fused(size_t(t.count) * ne, -1);
        std::vector<float> probs(nc), fprobs(nc);
        size_t frames_done = 0;
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < t.count; ++i) {
            const int len = t.length[i];
            const auto ev = tc.evidence(obs.data() + size_t(i) * k * np, len, sets.data() + size_t(i) * k);
            auto st = tc.begin();
            for (int f = 0; f < len; ++f) {
                tc.step(st, ev.data() + size_t(f) * e, probs.data(), fprobs.data());
                const int j = slot[size_t(f) + 1];
                if (j >= 0) {
                    track[size_t(i) * ne + j] = ids[argmax(probs.data(), nc)];
                    fused[size_t(i) * ne + j] = ids[argmax(fprobs.data(), nc)];
                }
            }
            frames_done += size_t(len);
        }
        const double us = 1e6 * seconds_between(t0, std::chrono::steady_clock::now()) / double(frames_done);
        out.write(method, mask_label, np, snr, track, us, src.train_seconds, src.origin, train_seed);
        out.write(fusion_method, mask_label, np, snr, fused, us, src.train_seconds, src.origin, train_seed);
    }
}

// The frame bundle with its mask on F subcarriers across the band, one per frame of a
// super-frame (set f: every pilot's subcarrier moved by f·M/F, cyclically; the symbols kept):
// the same decoder sees the target at F places of the band instead of one. Written beside the
// other bundles (no training: the frame bundle's weights).
decoder_source shifted_super_frame(const config& c, const decoder_source& frame, int n_sets)
{
    const auto& b = frame.bundle;
    const int m = b.frame.n_subcarriers;
    std::vector<pilot_mask> sets;
    for (int f = 0; f < n_sets; ++f) {
        std::vector<pilot_position> pos;
        for (auto q : b.mask.positions())
            pos.push_back({ q.n, (q.m + f * m / n_sets) % m });
        sets.emplace_back(b.frame.n_symbols, m, pos, b.mask.pilot_symbol());
    }
    decoder_source out = frame;
    out.bundle.super_frame = super_frame_mask(sets, { { "kind", "shifted" }, { "from", b.directory } });
    out.bundle.mask = sets.front();
    const auto dir = fsys::path(c.out_dir) / "bundles" / (fsys::path(b.directory).filename().string() + "_shifted" +
                                                          std::to_string(n_sets));
    out.bundle.save(dir.string());
    fsys::copy_file(b.weights_path(), dir / b.weights_name, fsys::copy_options::overwrite_existing);
    out.bundle = model_bundle::load(dir.string());
    return out;
}

// The names of a budget's bundles start with this ("cls_kinematic_" at 32 pilots, the main part's).
std::string budget_prefix(int np)
{
    return "cls_kinematic" + (np == 32 ? std::string() : "_np" + std::to_string(np)) + "_";
}

// The SemS frame bundle's training at a budget: every part of experiment 8 trains (or finds
// cached) the same one.
training_settings sems_training(const config& c, const scene& sc, int np, uint64_t seed)
{
    auto s = base_training(c, task_kind::classify, sc, "sems_eval kinematic", seed);
    s.n_pilots = np;
    return s;
}

// A frame bundle's product of per-frame posteriors (a bundle without a temporal model).
void score_fusion(const config& c, track_scorer& out, const decoder_source& src, const std::string& method,
                  const std::string& mask_label, std::optional<uint64_t> train_seed)
{
    const auto& t = out.tests();
    const bundle_decoder dec(src.bundle, c.threads);
    const auto ids = output_classes(src.bundle, out.sc());
    const int np = dec.n_pilots(), nc = static_cast<int>(ids.size()), k = t.frames;
    const auto slot = eval_slot(c);
    const size_t ne = c.exp8_frames.size();
    const auto sets = frame_sets(t, dec.super_frames());
    for (double snr : c.snrs) {
        const auto obs = observe_sets(t, src.bundle, sets, snr);
        answers fused(size_t(t.count) * ne, -1);
        size_t frames_done = 0;
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<double> logp(nc);
        for (int i = 0; i < t.count; ++i) {
            const int len = t.length[i];
            const auto p = dec.classify(obs.data() + size_t(i) * k * np, len, sets.data() + size_t(i) * k);
            std::fill(logp.begin(), logp.end(), 0.0);
            for (int f = 0; f < len; ++f) {
                for (int q = 0; q < nc; ++q)
                    logp[q] += std::log(std::max(double(p[size_t(f) * nc + q]), 1e-30));
                const int j = slot[size_t(f) + 1];
                if (j >= 0)
                    fused[size_t(i) * ne + j] = ids[std::max_element(logp.begin(), logp.end()) - logp.begin()];
            }
            frames_done += size_t(len);
        }
        const double us = 1e6 * seconds_between(t0, std::chrono::steady_clock::now()) / double(frames_done);
        out.write(method, mask_label, np, snr, fused, us, src.train_seconds, src.origin, train_seed);
    }
}

// Per-frame Doppler-moment features of every frame of tracks observed on `mask`.
std::vector<std::vector<double>> frame_features(const doppler_features& fx, const std::vector<gr_complex>& obs,
                                                const track_grids& t, int np)
{
    std::vector<std::vector<double>> out(size_t(t.count) * t.frames);
    for (int i = 0; i < t.count; ++i)
        for (int f = 0; f < t.length[i]; ++f)
            out[size_t(i) * t.frames + f] = fx.extract(obs.data() + (size_t(i) * t.frames + f) * np);
    return out;
}

// The feature SVM over a track: the per-frame features' mean and standard deviation over the
// frames given, trained on tracks of their own (one SNR per track over the training range)
// cut at every observation time.
void score_svm(const config& c, track_scorer& out, int np, uint64_t train_seed, const scene& tsc)
{
    const auto& t = out.tests();
    const auto mask = pilot_mask::from_pattern("doppler", c.fs, np);
    const doppler_features fx(c.fs, mask);
    const auto t0 = std::chrono::steady_clock::now();
    // The training tracks' per-frame features at one SNR per track (uniform over the training
    // range, drawn from (seed, track)), from their pilots alone.
    const auto idx = mask.flat_indices();
    const int k = c.exp8_track_frames, n_tr = c.exp8_svm_tracks;
    std::vector<std::vector<double>> train_fx(size_t(n_tr) * k);
    std::vector<int> train_len(n_tr), train_label(n_tr);
    for_each_track(c, tsc, n_tr, k, train_seed + 303, true,
                   [&](int i, int len, int label, const gr_complex* h, const gr_complex* w) {
                       std::mt19937_64 g(train_seed * 1000003ULL + uint64_t(i));
                       std::uniform_real_distribution<double> u(c.train_snr_min_db, c.train_snr_max_db);
                       const float sigma = static_cast<float>(std::sqrt(channel_model::noise_variance(u(g))));
                       std::vector<gr_complex> obs(np);
                       for (int f = 0; f < len; ++f) {
                           const size_t at = size_t(f) * c.fs.grid_size();
                           for (int q = 0; q < np; ++q)
                               obs[q] = h[at + idx[q]] + sigma * w[at + idx[q]];
                           train_fx[size_t(i) * k + f] = fx.extract(obs.data());
                       }
                       train_len[i] = len;
                       train_label[i] = label;
                   });
    auto track_feature = [](const std::vector<std::vector<double>>& per_frame, size_t first, int t_frames) {
        const size_t d = per_frame[first].size();
        std::vector<double> mean(d, 0.0), sq(d, 0.0);
        for (int f = 0; f < t_frames; ++f)
            for (size_t q = 0; q < d; ++q) {
                mean[q] += per_frame[first + f][q];
                sq[q] += per_frame[first + f][q] * per_frame[first + f][q];
            }
        std::vector<double> x;
        for (size_t q = 0; q < d; ++q) {
            const double m = mean[q] / t_frames;
            x.push_back(m);
            x.push_back(std::sqrt(std::max(0.0, sq[q] / t_frames - m * m)));
        }
        return x;
    };
    std::vector<std::vector<double>> x;
    std::vector<int> y;
    for (int i = 0; i < n_tr; ++i)
        for (int tf : c.exp8_frames)
            if (train_len[i] >= tf) {
                x.push_back(track_feature(train_fx, size_t(i) * k, tf));
                y.push_back(train_label[i]);
            }
    const feature_svm svm(x, y);
    const double train_s = seconds_between(t0, std::chrono::steady_clock::now());
    const size_t ne = c.exp8_frames.size();
    for (double snr : c.snrs) {
        const auto obs = t.grids.observe(mask, snr);
        const auto t1 = std::chrono::steady_clock::now();
        const auto per_frame = frame_features(fx, obs, t, np);
        answers a(size_t(t.count) * ne, -1);
        size_t frames_done = 0;
        for (int i = 0; i < t.count; ++i) {
            for (size_t j = 0; j < ne; ++j)
                if (t.length[i] >= c.exp8_frames[j])
                    a[size_t(i) * ne + j] = svm.predict(track_feature(per_frame, size_t(i) * t.frames, c.exp8_frames[j]));
            frames_done += size_t(t.length[i]);
        }
        const double us = 1e6 * seconds_between(t1, std::chrono::steady_clock::now()) / double(frames_done);
        out.write("SVM over the track (doppler pilots)", "doppler", np, snr, a, us, train_s,
                  "libsvm RBF " + std::to_string(svm.n_support_vectors()) + " SV", train_seed);
    }
}

std::vector<float> spectrograms(const config& c, const track_grids& t)
{
    const size_t img = size_t(c.fs.n_symbols + c.fs.n_subcarriers) * t.frames;
    std::vector<float> out(size_t(t.count) * img);
    for (int i = 0; i < t.count; ++i) {
        const auto s = track_spectrogram(c.fs, t.h(i), t.frames, t.length[i]);
        std::copy(s.begin(), s.end(), out.begin() + size_t(i) * img);
    }
    return out;
}

// The Perfect-CSI spectrogram CNN: trained on its own noiseless tracks (the temporal
// decoders' count), its decisions the same at every SNR (its input has no noise).
void score_spectrogram_cnn(const config& c, track_scorer& out, uint64_t train_seed, const scene& tsc, std::ostream& log)
{
    const auto& t = out.tests();
    const int nc = out.sc().library().size();
    const auto t0 = std::chrono::steady_clock::now();
    log << "[" << now_utc() << "] spectrogram CNN (Perfect CSI): drawing " << c.exp8_train_tracks
        << " noiseless training tracks, seed " << train_seed << std::endl;
    const int k = c.exp8_track_frames, n_tr = c.exp8_train_tracks;
    const size_t img = size_t(c.fs.n_symbols + c.fs.n_subcarriers) * k;
    std::vector<float> train_img(size_t(n_tr) * img);
    std::vector<int> train_len(n_tr), train_label(n_tr);
    for_each_track(c, tsc, n_tr, k, train_seed + 404, false, [&](int i, int len, int label, const gr_complex* h, const gr_complex*) {
        const auto s = track_spectrogram(c.fs, h, k, len);
        std::copy(s.begin(), s.end(), train_img.begin() + size_t(i) * img);
        train_len[i] = len;
        train_label[i] = label;
    });
    spectrogram_cnn cnn(c.fs.n_symbols + c.fs.n_subcarriers, k, nc, train_seed, c.threads);
    cnn.train(train_img, train_len, train_label, c.exp8_cnn_epochs, log);
    const double train_s = seconds_between(t0, std::chrono::steady_clock::now());
    const auto t1 = std::chrono::steady_clock::now();
    const auto test_img = spectrograms(c, t);
    const size_t ne = c.exp8_frames.size();
    answers a(size_t(t.count) * ne, -1);
    for (size_t j = 0; j < ne; ++j) {
        const auto p = cnn.predict(test_img, t.length, c.exp8_frames[j]);
        for (int i = 0; i < t.count; ++i)
            a[size_t(i) * ne + j] = p[i];
    }
    size_t frames_done = 0;
    for (int len : t.length)
        frames_done += size_t(len);
    const double us = 1e6 * seconds_between(t1, std::chrono::steady_clock::now()) / double(frames_done);
    for (double snr : c.snrs)
        out.write("Perfect-CSI spectrogram CNN (noiseless)", "full grid", c.fs.grid_size(), snr, a, us, train_s,
                  "2-D CNN", train_seed);
}

// The hand patterns under the temporal decoder at N_p: the experiment-7 ones that carry every
// symbol's slow time (the uniform and random patterns do not), and burst below N pilots.
std::vector<std::string> track_patterns(const config& c, int np)
{
    std::vector<std::string> p{ "doppler", "staggered" };
    if (np < c.fs.n_symbols)
        p.push_back("burst");
    return p;
}

} // namespace

void run_tracks(const config& c, std::ostream& log)
{
    if (!c.experiments.count(8))
        return;
    const scene sc = recognition_scene("kinematic", c);
    const scene tsc = tracked_scene(sc, c.exp8_track_frames);
    const uint64_t test_seed = c.seed + 808;
    log << "[" << now_utc() << "] exp 8 (kinematic tracks): " << c.exp8_test_tracks << " test tracks of "
        << c.exp8_track_frames << " frames, seed " << test_seed << std::endl;
    const track_grids tests = draw_track_grids(c, tsc, c.exp8_test_tracks, c.exp8_track_frames, test_seed);
    track_scorer out(c, tests, sc, test_seed, log);
    if (!c.shipped_track.empty() && c.exp8_parts.count("main")) {
        // A shipped track bundle on the same tracks: its decision and its frame decoder's fusion.
        track_source shipped;
        shipped.bundle = model_bundle::load(c.shipped_track);
        shipped.origin = c.shipped_track;
        score_track_bundle(c, out, shipped, "shipped track bundle", "shipped track bundle's fusion",
                           "shipped", std::nullopt);
    }
    if (c.only_shipped)
        return;
    std::vector<int> budgets;
    if (c.exp8_parts.count("main"))
        budgets.push_back(32);
    if (c.exp8_parts.count("budget"))
        for (int np : c.exp8_np_sweep)
            if (np != 32 || !c.exp8_parts.count("main"))
                budgets.push_back(np);
    // Learned super-frame masks (F sets from the SemS frame bundle of each budget, with the
    // same temporal decoder's budget); the repeated masks are the budget and main parts'.
    if (c.exp8_parts.count("superframe"))
        for (int np : c.exp8_np_sweep)
            for (uint64_t seed : training_seeds(c)) {
                const std::string sems_name = seeded_name(budget_prefix(np) + "sems", seed);
                const auto sems = train_or_load(c, sems_name, sems_training(c, sc, np, seed), log);
                const std::string f = std::to_string(c.exp8_super_frames);
                const std::string from = c.exp8_super_frame_start == "frame" ? "" : ", " + c.exp8_super_frame_start + " start";
                score_track_bundle(c, out,
                                   train_or_load_track(c, sems_name, sems, seed, log, c.exp8_super_frames,
                                                       c.exp8_super_frame_start),
                                   "SemS super-frame (F = " + f + from + ") + track",
                                   "SemS super-frame (F = " + f + from + ") fusion", "learned super-frame (task)", seed);
                // What diversity across frames alone gives: the SemS frame decoder on its mask
                // moved across the band frame by frame, fused (against its repeated mask's fusion).
                if (c.exp8_super_frame_start == "frame")
                    score_fusion(c, out, shifted_super_frame(c, sems, c.exp8_super_frames),
                                 "SemS decoder (its mask on " + f + " subcarriers across frames) fusion",
                                 "hand super-frame (shifted)", seed);
            }
    for (int np : budgets) {
        const bool main_part = np == 32 && c.exp8_parts.count("main");
        for (uint64_t seed : training_seeds(c)) {
            const std::string prefix = budget_prefix(np);
            const auto sems_settings = sems_training(c, sc, np, seed);
            const std::string sems_name = seeded_name(prefix + "sems", seed);
            const auto sems = train_or_load(c, sems_name, sems_settings, log);
            score_track_bundle(c, out, train_or_load_track(c, sems_name, sems, seed, log), "SemS-track",
                               "SemS fusion", "learned (task)", seed);
            for (const auto& pattern : track_patterns(c, np)) {
                const std::string name = seeded_name(prefix + pattern, seed);
                const auto frame = train_or_load(c, name, hand_pattern_training(sems_settings, pattern), log);
                score_track_bundle(c, out, train_or_load_track(c, name, frame, seed, log),
                                   "SemS decoder (" + pattern + " pilots) + track",
                                   "SemS decoder (" + pattern + " pilots) fusion", pattern, seed);
            }
            if (!main_part)
                continue;
            auto mse_settings = sems_settings;
            mse_settings.objective = "mse";
            const auto mse = train_or_load(c, seeded_name(prefix + "mse", seed), mse_settings, log);
            score_fusion(c, out, mse, "MSE-DL fusion", "learned (MSE)", seed);
            score_svm(c, out, np, seed, tsc);
            score_spectrogram_cnn(c, out, seed, tsc, log);
        }
    }
}

} // namespace sems_eval
