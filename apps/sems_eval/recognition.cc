// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiments 1 and 3: accuracy and macro-F1 against SNR for SemS and every
 * recognition baseline, on the same test frames (default scene; without micro-Doppler;
 * with strong clutter). */
#include "eval.h"
#include <gnuradio/sems/learning/bundle_decoder.h>
#include <gnuradio/sems/baselines/doppler_features.h>
#include <gnuradio/sems/baselines/feature_svm.h>
#include <gnuradio/sems/core/target_class.h>
#include <algorithm>
#include <limits>
#include <memory>

namespace sems_eval {

namespace {

const std::vector<std::string> header{ "experiment", "scenario",  "method",   "mask",          "n_pilots",
                                       "snr_db",     "accuracy",  "macro_f1", "n_frames",      "seed",
                                       "train_seed", "us_per_frame", "train_seconds", "model" };

std::vector<int> truth_labels(const test_set& ts)
{
    std::vector<int> y;
    for (const auto& t : ts.truth)
        y.push_back(t.class_id);
    return y;
}

// Class ids (in the scene's library) of a classifier bundle's outputs; a bundle trained on
// another class library is refused with the reason (model_bundle::check_library).
std::vector<int> output_classes(const model_bundle& b, const scene& sc)
{
    b.check_library(sc.library(), "sems_eval");
    std::vector<int> ids;
    for (const auto& n : b.class_names)
        ids.push_back(sc.library().id_of(n));
    return ids;
}

// Runs the decoder on count x N_p observations in batches; returns class ids.
std::vector<int> classify_all(const bundle_decoder& dec,
                              const std::vector<gr_complex>& obs,
                              int count,
                              const std::vector<int>& ids,
                              double& us_per_frame)
{
    const int np = dec.n_pilots(), c = static_cast<int>(ids.size());
    std::vector<int> pred(count);
    dec.classify(obs.data(), std::min(count, 32)); // warm-up: first-call allocations are not per-frame cost
    const auto t0 = std::chrono::steady_clock::now();
    for (int f0 = 0; f0 < count; f0 += 256) {
        const int b = std::min(256, count - f0);
        const auto p = dec.classify(obs.data() + size_t(f0) * np, b);
        for (int i = 0; i < b; ++i) {
            const float* row = p.data() + size_t(i) * c;
            pred[f0 + i] = ids[std::max_element(row, row + c) - row];
        }
    }
    us_per_frame = 1e6 * seconds_between(t0, std::chrono::steady_clock::now()) / count;
    return pred;
}

// The classical MTI on pilot observations (mask order): each subcarrier's observations minus
// their mean over the symbols observed on it, per frame (what the networks' "mean" stage does).
std::vector<gr_complex> remove_static(std::vector<gr_complex> obs, int count, const pilot_mask& mask)
{
    const auto& pos = mask.positions();
    const int np = static_cast<int>(pos.size());
    std::vector<gr_complex> sum(mask.n_subcarriers());
    std::vector<int> n(mask.n_subcarriers(), 0);
    for (const auto& p : pos)
        ++n[p.m];
    for (int f = 0; f < count; ++f) {
        gr_complex* o = obs.data() + size_t(f) * np;
        std::fill(sum.begin(), sum.end(), gr_complex(0.0f, 0.0f));
        for (int k = 0; k < np; ++k)
            sum[pos[k].m] += o[k];
        for (int k = 0; k < np; ++k)
            o[k] -= sum[pos[k].m] / static_cast<float>(n[pos[k].m]);
    }
    return obs;
}

struct dl_method {
    std::string method, model_name, mask_label; // model_name: the cache name before its seed suffix
    training_settings settings;
    bool noiseless_input = false;
};

// The learned methods of one scenario, trained with train_seed: all by the same trainer at
// the same data budget.
std::vector<dl_method> learned_methods(const config& c, const std::string& scen, const scene& sc, bool exp1,
                                       const std::string& full_mask, int np, uint64_t train_seed)
{
    std::vector<dl_method> dl;
    dl_method m{ "SemS", "cls_" + scen + "_sems", "learned (task)",
                 base_training(c, task_kind::classify, sc, "sems_eval " + scen, train_seed), false };
    m.settings.n_pilots = np;
    // Under static clutter every network gets the documented zero-Doppler stage (MTI: each
    // subcarrier minus its mean over its observed symbols): its best standard form there.
    if (scen == "clutter")
        m.settings.classifier.mti = "mean";
    dl.push_back(m);
    dl_method mse = m;
    mse.method = "MSE-DL";
    mse.model_name = "cls_" + scen + "_mse";
    mse.mask_label = "learned (MSE)";
    mse.settings.objective = "mse";
    dl.push_back(mse);
    dl_method pcsi = m;
    pcsi.method = "Perfect CSI (noiseless)";
    pcsi.model_name = "cls_" + scen + "_pcsi_noiseless";
    pcsi.mask_label = "full grid";
    pcsi.settings.n_pilots = c.fs.grid_size();
    pcsi.settings.mask_file = full_mask;
    pcsi.settings.snr_min_db = pcsi.settings.snr_max_db = std::numeric_limits<double>::infinity();
    // On its fixed (full-grid) mask every epoch trains the decoder: the learned mask's whole
    // budget, as the hand patterns get it.
    pcsi.settings.epochs += pcsi.settings.decoder_epochs;
    pcsi.noiseless_input = true;
    dl.push_back(pcsi);
    // The same decoder on the hand patterns, at the same budget: what the learned mask must beat.
    if (exp1 && c.exp1_hand_patterns)
        for (const std::string pattern : { "doppler", "uniform", "random" }) {
            dl_method hp = m;
            hp.method = "SemS decoder (" + pattern + " pilots)";
            hp.model_name = "cls_" + scen + "_" + pattern;
            hp.mask_label = pattern;
            hp.settings = hand_pattern_training(m.settings, pattern);
            dl.push_back(hp);
        }
    if (scen == "default") {
        dl_method pn = pcsi;
        pn.method = "Perfect CSI (test SNR)";
        pn.model_name = "cls_" + scen + "_pcsi_snr";
        pn.settings.snr_min_db = c.train_snr_min_db;
        pn.settings.snr_max_db = c.train_snr_max_db;
        pn.noiseless_input = false;
        dl.push_back(pn);
    }
    return dl;
}

} // namespace

void run_recognition(const config& c, std::ostream& log)
{
    std::vector<std::string> scenarios;
    if (c.experiments.count(1)) {
        scenarios.push_back("default");
        if (c.exp1_any_heading)
            scenarios.push_back("any"); // the harder scene: approaching, receding and crossing targets
    }
    if (c.experiments.count(3)) {
        scenarios.push_back("no_md");
        scenarios.push_back("clutter");
    }
    if (scenarios.empty())
        return;
    std::unique_ptr<csv_file> csv1, csv3;
    if (c.experiments.count(1))
        csv1 = std::make_unique<csv_file>(c.out_dir + "/exp1_recognition.csv", header);
    if (c.experiments.count(3))
        csv3 = std::make_unique<csv_file>(c.out_dir + "/exp3_conditions.csv", header);
    const int np = 32;
    const std::string full_mask = write_mask(c, full_grid_mask(c.fs), "full_grid");

    for (const auto& scen : scenarios) {
        const bool exp1 = scen == "default" || scen == "any";
        const std::string exp = exp1 ? "1" : "3";
        csv_file& csv = exp1 ? *csv1 : *csv3;
        const scene sc = recognition_scene(scen, c);
        // The same test frames for every method and every training seed.
        const uint64_t test_seed = c.seed + 101;
        log << "[" << now_utc() << "] exp " << exp << " (" << scen << "): " << c.test_frames
            << " test frames, seed " << test_seed << std::endl;
        const test_set ts = make_test_set(c.fs, sc, c.test_frames, test_seed);
        const auto truth = truth_labels(ts);
        const int n_classes = sc.library().size();

        auto write = [&](const std::string& method, const std::string& mask, int pilots, double snr,
                         const class_score& s, double us, double train_s, const std::string& model,
                         std::optional<uint64_t> train_seed) {
            const std::string ts_label = train_seed_label(train_seed);
            csv.row({ exp, scen, method, mask, std::to_string(pilots), num(snr), num(s.accuracy), num(s.macro_f1),
                      std::to_string(ts.count), std::to_string(test_seed), ts_label, num(us, 4), num(train_s, 4),
                      model });
            cost_rows().push_back(
                { exp, scen, method, mask, test_seed, ts_label, pilots, snr, "accuracy", s.accuracy, us, ts.count,
                  train_s });
            log << "  " << scen << " " << method << " [train seed " << ts_label << "] snr " << num(snr) << ": acc "
                << num(s.accuracy, 3) << " F1 " << num(s.macro_f1, 3) << " (" << num(us, 3) << " us/frame)"
                << std::endl;
        };
        auto evaluate = [&](const dl_method& m, const decoder_source& src, std::optional<uint64_t> train_seed) {
            const bundle_decoder dec(src.bundle, c.threads);
            const auto ids = output_classes(src.bundle, sc);
            const int p = dec.n_pilots();
            if (m.noiseless_input) {
                double us = 0.0;
                const auto obs = ts.observe(src.bundle.mask, std::numeric_limits<double>::infinity());
                const auto s = score(classify_all(dec, obs, ts.count, ids, us), truth, n_classes);
                for (double snr : c.snrs) // the input does not depend on the test SNR
                    write(m.method, m.mask_label, p, snr, s, us, src.train_seconds, src.origin, train_seed);
                return;
            }
            for (double snr : c.snrs) {
                double us = 0.0;
                const auto obs = ts.observe(src.bundle.mask, snr);
                const auto s = score(classify_all(dec, obs, ts.count, ids, us), truth, n_classes);
                write(m.method, m.mask_label, p, snr, s, us, src.train_seconds, src.origin, train_seed);
            }
        };

        // Seeds outermost: a stopped run still has every method for its first seeds.
        for (uint64_t seed : c.only_shipped ? std::vector<uint64_t>{} : training_seeds(c)) {
            for (const auto& m : learned_methods(c, scen, sc, exp1, full_mask, np, seed))
                evaluate(m, train_or_load(c, seeded_name(m.model_name, seed), m.settings, log), seed);

            // Feature SVMs: Doppler-spectrum moments from uniform and Doppler-oriented pilots,
            // trained on their own frames (drawn with the training seed) over the same SNR
            // range as the networks.
            const train_set tr =
                make_train_set(c.fs, sc, c.svm_train_frames, seed + 202, c.train_snr_min_db, c.train_snr_max_db);
            // Under clutter also with the classical MTI in front (the SVM's best standard form there).
            std::vector<std::pair<std::string, bool>> svms{ { "uniform", false }, { "doppler", false } };
            if (scen == "clutter")
                svms.insert(svms.end(), { { "uniform", true }, { "doppler", true } });
            for (const auto& [pattern, mti] : svms) {
                const auto mask = pilot_mask::from_pattern(pattern, c.fs, np);
                const doppler_features fx(c.fs, mask);
                auto prepare = [&, mti = mti](std::vector<gr_complex> o, int count) {
                    return mti ? remove_static(std::move(o), count, mask) : o;
                };
                const auto t0 = std::chrono::steady_clock::now();
                const auto tr_obs = prepare(gather(tr.y, c.svm_train_frames, c.fs, mask), c.svm_train_frames);
                std::vector<std::vector<double>> x;
                std::vector<int> y;
                for (int f = 0; f < c.svm_train_frames; ++f) {
                    x.push_back(fx.extract(tr_obs.data() + size_t(f) * np));
                    y.push_back(tr.truth[f].class_id);
                }
                const feature_svm svm(x, y);
                const double train_s = seconds_between(t0, std::chrono::steady_clock::now());
                const std::string method = "SVM (" + pattern + " pilots" + (mti ? ", MTI)" : ")");
                for (double snr : c.snrs) {
                    const auto obs = prepare(ts.observe(mask, snr), ts.count);
                    std::vector<int> pred(ts.count);
                    const auto t1 = std::chrono::steady_clock::now();
                    for (int f = 0; f < ts.count; ++f)
                        pred[f] = svm.predict(fx.extract(obs.data() + size_t(f) * np));
                    const double us = 1e6 * seconds_between(t1, std::chrono::steady_clock::now()) / ts.count;
                    write(method, pattern, np, snr, score(pred, truth, n_classes), us, train_s,
                          "libsvm RBF " + std::to_string(svm.n_support_vectors()) + " SV", seed);
                }
            }
        }

        if (scen == "default" && !c.shipped_classifier.empty()) {
            // Labelled by what its mask is: a shipped classifier may sit on a fixed pattern.
            // Not trained by this run: no training seed.
            decoder_source src;
            src.bundle = model_bundle::load(c.shipped_classifier);
            src.origin = c.shipped_classifier;
            const std::string kind = src.bundle.mask.origin().value("kind", std::string("unknown"));
            const std::string other_library =
                src.bundle.library ? src.bundle.library->difference(sc.library()) : std::string();
            if (src.bundle.task != task_kind::classify || src.bundle.frame != c.fs)
                log << "  shipped classifier " << c.shipped_classifier << " does not match: skipped" << std::endl;
            else if (!other_library.empty())
                log << "  shipped classifier " << c.shipped_classifier << " was trained on class library \""
                    << src.bundle.library->name() << "\", the scene's is \"" << sc.library().name()
                    << "\": skipped (" << other_library << ")" << std::endl;
            else
                evaluate({ "Shipped bundle (" + kind + " pilots)", "", kind, training_settings{}, false }, src,
                         std::nullopt);
        }
    }
}

} // namespace sems_eval
