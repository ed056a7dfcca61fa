// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiments 1, 3 and 7: accuracy and macro-F1 against SNR for SemS and every
 * recognition baseline, on the same test frames (default scene; without micro-Doppler;
 * with strong clutter; targets of moving scatterers from a kinematic class library, with the
 * confusion matrices and the pilot budget sweep). */
#include "eval.h"
#include "predictions.h"
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/baselines/doppler_features.h>
#include <gnuradio/sems/baselines/feature_svm.h>
#include <gnuradio/sems/core/scene/target_class.h>
#include <algorithm>
#include <functional>
#include <limits>
#include <map>
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

enum class method_kind { sems, sems_templates, mse, perfect_csi, pattern };

struct dl_method {
    std::string method, model_name, mask_label; // model_name: the cache name before its seed suffix
    training_settings settings;
    bool noiseless_input = false;
    method_kind kind = method_kind::sems;
};

// The hand patterns the SemS decoder is also trained on (experiments 1 and 7). A body of
// moving scatterers spans part of a delay cell, so experiment 7 adds the staggered band-edge
// pattern: every symbol's slow time, as the Doppler pattern has, and the band's whole aperture.
std::vector<std::string> hand_patterns(const config& c, const std::string& scen)
{
    if (scen == "kinematic")
        return { "doppler", "uniform", "random", "staggered" };
    if (scen == "default" || scen == "any")
        return c.exp1_hand_patterns ? std::vector<std::string>{ "doppler", "uniform", "random" }
                                    : std::vector<std::string>{};
    return {};
}

// The cache names' prefix of a scenario's networks: they carry N_p when it is not the
// experiments' 32.
std::string model_prefix(const std::string& scen, int np)
{
    return "cls_" + scen + (np == 32 ? std::string() : "_np" + std::to_string(np)) + "_";
}

// The SemS decoder on a hand pattern at SemS's budget: what the learned mask must beat.
dl_method hand_pattern_method(const dl_method& sems, const std::string& prefix, const std::string& pattern)
{
    dl_method hp = sems;
    hp.method = "SemS decoder (" + pattern + " pilots)";
    hp.model_name = prefix + pattern;
    hp.mask_label = pattern;
    hp.settings = hand_pattern_training(sems.settings, pattern);
    hp.kind = method_kind::pattern;
    return hp;
}

// The same training with a decoder that also keeps every training frame on its final mask as a
// template bank (classifier_settings::template_frames). The bank's layer draws no random
// numbers, so a learned mask is the one learned without the bank.
dl_method with_template_bank(dl_method m, const std::string& method)
{
    m.method = method;
    m.model_name += "_templates";
    m.settings.classifier.template_frames = -1;
    return m;
}

// The learned methods of one scenario, trained with train_seed: all by the same trainer at
// the same data budget.
std::vector<dl_method> learned_methods(const config& c, const std::string& scen, const scene& sc,
                                       const std::string& full_mask, int np, uint64_t train_seed)
{
    std::vector<dl_method> dl;
    const std::string prefix = model_prefix(scen, np);
    dl_method m{ "SemS", prefix + "sems", "learned (task)",
                 base_training(c, task_kind::classify, sc, "sems_eval " + scen, train_seed), false };
    m.settings.n_pilots = np;
    // Under static clutter every network gets the documented zero-Doppler stage (MTI: each
    // subcarrier minus its mean over its observed symbols): its best standard form there.
    if (scen == "clutter")
        m.settings.classifier.mti = "mean";
    dl.push_back(m);
    if (scen == "kinematic") {
        // SemS with a template bank: the Monte-Carlo Bayes classifier of its own training
        // frames beside the network, on SemS's mask; it differs only in the decoder phase.
        dl_method tb = with_template_bank(m, "SemS + template bank");
        tb.kind = method_kind::sems_templates;
        dl.push_back(tb);
    }
    dl_method mse = m;
    mse.method = "MSE-DL";
    mse.model_name = prefix + "mse";
    mse.mask_label = "learned (MSE)";
    mse.settings.objective = "mse";
    mse.kind = method_kind::mse;
    dl.push_back(mse);
    dl_method pcsi = m;
    pcsi.method = "Perfect CSI (noiseless)";
    pcsi.model_name = prefix + "pcsi_noiseless";
    pcsi.kind = method_kind::perfect_csi;
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
    for (const std::string& pattern : hand_patterns(c, scen))
        dl.push_back(hand_pattern_method(m, prefix, pattern));
    if (scen == "default" || scen == "kinematic") {
        dl_method pn = pcsi;
        pn.method = "Perfect CSI (test SNR)";
        pn.model_name = prefix + "pcsi_snr";
        pn.settings.snr_min_db = c.train_snr_min_db;
        pn.settings.snr_max_db = c.train_snr_max_db;
        pn.noiseless_input = false;
        dl.push_back(pn);
    }
    return dl;
}

// One scenario's test frames and outputs: every method is scored on these frames and written
// to csv, its per-frame class ids to kept (and, where given, its confusion matrix at the
// confusion SNR).
struct scenario_run {
    std::string experiment, scenario;
    const scene& sc;
    const test_set& ts;
    uint64_t test_seed;
    csv_file& csv;
    kept_predictions& kept;
    csv_file* confusion = nullptr;
};

class scorer
{
public:
    scorer(const config& c, const scenario_run& run, std::ostream& log)
        : d_c(c), d_run(run), d_log(log), d_truth(truth_labels(run.ts)), d_n_classes(run.sc.library().size())
    {
    }

    // Scores predictions at one SNR and writes the CSV row, the kept class ids, the cost row
    // and, at the confusion SNR, the confusion matrix.
    void write(const std::string& method, const std::string& mask, int pilots, double snr,
               const std::vector<int>& pred, double us, double train_s, const std::string& model,
               std::optional<uint64_t> train_seed)
    {
        const class_score s = score(pred, d_truth, d_n_classes);
        d_run.kept.add({ d_run.scenario, method, mask, pilots, snr, train_seed, d_run.test_seed }, pred, d_n_classes);
        const std::string ts_label = train_seed_label(train_seed);
        d_run.csv.row({ d_run.experiment, d_run.scenario, method, mask, std::to_string(pilots), num(snr),
                        num(s.accuracy), num(s.macro_f1), std::to_string(d_run.ts.count),
                        std::to_string(d_run.test_seed), ts_label, num(us, 4), num(train_s, 4), model });
        cost_rows().push_back({ d_run.experiment, d_run.scenario, method, mask, d_run.test_seed, ts_label, pilots,
                                snr, "accuracy", s.accuracy, us, d_run.ts.count, train_s });
        d_log << "  " << d_run.scenario << " " << method << " [N_p " << pilots << ", train seed " << ts_label
              << "] snr " << num(snr) << ": acc " << num(s.accuracy, 3) << " F1 " << num(s.macro_f1, 3) << " ("
              << num(us, 3) << " us/frame)" << std::endl;
        if (d_run.confusion && snr == d_c.confusion_snr_db) {
            std::vector<int> counts(size_t(d_n_classes) * d_n_classes, 0);
            for (size_t i = 0; i < pred.size(); ++i)
                if (pred[i] >= 0 && pred[i] < d_n_classes)
                    ++counts[size_t(d_truth[i]) * d_n_classes + pred[i]];
            for (int t = 0; t < d_n_classes; ++t)
                for (int p = 0; p < d_n_classes; ++p)
                    d_run.confusion->row({ d_run.experiment, d_run.scenario, method, mask, std::to_string(pilots),
                                           num(snr), ts_label, d_run.sc.library().at(t).name,
                                           d_run.sc.library().at(p).name,
                                           std::to_string(counts[size_t(t) * d_n_classes + p]) });
        }
    }

    // A trained decoder on the test frames at every SNR (once, noiseless, for a noiseless method).
    void evaluate(const dl_method& m, const decoder_source& src, std::optional<uint64_t> train_seed)
    {
        const bundle_decoder dec(src.bundle, d_c.threads);
        const auto ids = output_classes(src.bundle, d_run.sc);
        const int p = dec.n_pilots();
        if (m.noiseless_input) {
            double us = 0.0;
            const auto obs = d_run.ts.observe(src.bundle.mask, std::numeric_limits<double>::infinity());
            const auto pred = classify_all(dec, obs, d_run.ts.count, ids, us);
            for (double snr : d_c.snrs) // the input does not depend on the test SNR
                write(m.method, m.mask_label, p, snr, pred, us, src.train_seconds, src.origin, train_seed);
            d_run.kept.write();
            return;
        }
        for (double snr : d_c.snrs) {
            double us = 0.0;
            const auto obs = d_run.ts.observe(src.bundle.mask, snr);
            const auto pred = classify_all(dec, obs, d_run.ts.count, ids, us); // sets us before it is written
            write(m.method, m.mask_label, p, snr, pred, us, src.train_seconds, src.origin, train_seed);
        }
        d_run.kept.write(); // after each method: a stopped run keeps what it scored
    }

    // Feature SVMs: Doppler-spectrum moments from uniform and Doppler-oriented pilots, trained
    // on their own frames (drawn with the training seed) over the same SNR range as the
    // networks; under clutter also with the classical MTI in front (its best standard form there).
    void svms(int np, uint64_t seed)
    {
        const int count = d_c.svm_train_frames;
        const train_set tr =
            make_train_set(d_c.fs, d_run.sc, count, seed + 202, d_c.train_snr_min_db, d_c.train_snr_max_db);
        std::vector<std::pair<std::string, bool>> svms{ { "uniform", false }, { "doppler", false } };
        if (d_run.scenario == "clutter")
            svms.insert(svms.end(), { { "uniform", true }, { "doppler", true } });
        for (const auto& [pattern, mti] : svms) {
            const auto mask = pilot_mask::from_pattern(pattern, d_c.fs, np);
            const doppler_features fx(d_c.fs, mask);
            auto prepare = [&, mti = mti](std::vector<gr_complex> o, int n) {
                return mti ? remove_static(std::move(o), n, mask) : o;
            };
            const auto t0 = std::chrono::steady_clock::now();
            const auto tr_obs = prepare(gather(tr.y, count, d_c.fs, mask), count);
            std::vector<std::vector<double>> x;
            std::vector<int> y;
            for (int f = 0; f < count; ++f) {
                x.push_back(fx.extract(tr_obs.data() + size_t(f) * np));
                y.push_back(tr.truth[f].class_id);
            }
            const feature_svm svm(x, y);
            const double train_s = seconds_between(t0, std::chrono::steady_clock::now());
            const std::string method = "SVM (" + pattern + " pilots" + (mti ? ", MTI)" : ")");
            for (double snr : d_c.snrs) {
                const auto obs = prepare(d_run.ts.observe(mask, snr), d_run.ts.count);
                std::vector<int> pred(d_run.ts.count);
                const auto t1 = std::chrono::steady_clock::now();
                for (int f = 0; f < d_run.ts.count; ++f)
                    pred[f] = svm.predict(fx.extract(obs.data() + size_t(f) * np));
                const double us = 1e6 * seconds_between(t1, std::chrono::steady_clock::now()) / d_run.ts.count;
                write(method, pattern, np, snr, pred, us, train_s,
                      "libsvm RBF " + std::to_string(svm.n_support_vectors()) + " SV", seed);
            }
            d_run.kept.write();
        }
    }

private:
    const config& d_c;
    const scenario_run& d_run;
    std::ostream& d_log;
    std::vector<int> d_truth;
    int d_n_classes;
};

const std::vector<std::string> confusion_header{ "experiment", "scenario", "method", "mask", "n_pilots", "snr_db",
                                                 "train_seed", "true_class", "predicted_class", "count" };

test_set scenario_test_set(const config& c, const std::string& scen, const scene& sc, uint64_t test_seed,
                           std::ostream& log, const std::string& exp)
{
    log << "[" << now_utc() << "] exp " << exp << " (" << scen << "): " << c.test_frames << " test frames, seed "
        << test_seed << std::endl;
    return make_test_set(c.fs, sc, c.test_frames, test_seed);
}

// One part of experiment 7 beside the main one: experiment 7's scene and test frames, its own
// CSV, and the methods `pick` keeps of each (N_p, training seed), trained and scored; N_p outermost, in the order given (the largest budgets first answer the question a
// sweep asks soonest), then seeds, so a stopped run has every method of its budgets.
void run_kinematic_part(const config& c, std::ostream& log, const std::string& what, const std::string& csv_name,
                        const std::vector<int>& budgets,
                        const std::function<std::vector<dl_method>(std::vector<dl_method>)>& pick)
{
    const scene sc = recognition_scene("kinematic", c);
    const uint64_t test_seed = c.seed + 101;
    const test_set ts = scenario_test_set(c, "kinematic", sc, test_seed, log, "7 (" + what + ")");
    csv_file csv(c.out_dir + "/" + csv_name, header);
    // Every part keeps its class ids beside its CSV, and the same test frames' truth.
    kept_predictions kept(predictions_path(c.out_dir, csv_name.substr(0, csv_name.size() - 4)), "7",
                          kept_predictions::kind::class_id);
    truth_file(c.out_dir + "/exp7_truth.npz", "7").add("kinematic", test_seed, ts.truth, class_names(sc));
    const scenario_run run{ "7", "kinematic", sc, ts, test_seed, csv, kept, nullptr };
    scorer sc_run(c, run, log);
    const std::string full_mask = write_mask(c, full_grid_mask(c.fs), "full_grid");
    for (int np : budgets)
        for (uint64_t seed : training_seeds(c))
            for (const auto& m : pick(learned_methods(c, "kinematic", sc, full_mask, np, seed)))
                sc_run.evaluate(m, train_or_load(c, seeded_name(m.model_name, seed), m.settings, log), seed);
}

// Experiment 7's pilot budget sweep: SemS with learned pilots against the best hand patterns
// (Doppler and staggered) at every N_p of c.exp7_np_sweep.
void run_kinematic_budget(const config& c, std::ostream& log)
{
    run_kinematic_part(c, log, "pilot budget", "exp7_pilot_budget.csv", c.exp7_np_sweep, [](std::vector<dl_method> all) {
        std::vector<dl_method> out;
        for (auto& m : all)
            if (m.kind == method_kind::sems ||
                (m.kind == method_kind::pattern && (m.mask_label == "doppler" || m.mask_label == "staggered")))
                out.push_back(std::move(m));
        return out;
    });
}

// Experiment 7's pilot energies: SemS whose mask learner also shares the total pilot energy
// among its pilots, at each N_p of c.exp7_power_np, against the equal-energy rows of the main
// part and the budget sweep (the same test frames, seeds and budget).
void run_kinematic_power(const config& c, std::ostream& log)
{
    run_kinematic_part(c, log, "pilot energies", "exp7_pilot_power.csv", c.exp7_power_np, [](std::vector<dl_method> all) {
        dl_method m = all.front(); // SemS
        m.method = "SemS (learned energies)";
        m.model_name += "_power";
        m.mask_label = "learned (task, energies)";
        m.settings.pilot_power = "learned";
        return std::vector<dl_method>{ m };
    });
}

// Experiment 7's bank part: at each N_p of c.exp7_bank_np, SemS + template bank against the
// Doppler pattern's decoder with a template bank. The bank matches a frame against its training
// frames whatever the pilots' spacing, where the spectral network's slow-time DFT favours
// evenly spaced symbols: whether a learned mask that trails a hand pattern with the network
// alone trails it with the bank too (docs/results/notes/bayes_classifier.md).
void run_kinematic_bank(const config& c, std::ostream& log)
{
    run_kinematic_part(c, log, "template banks", "exp7_bank.csv", c.exp7_bank_np, [](std::vector<dl_method> all) {
        std::vector<dl_method> out;
        for (auto& m : all) {
            if (m.kind == method_kind::sems_templates) {
                out.push_back(m);
            } else if (m.kind == method_kind::pattern && m.mask_label == "doppler") {
                out.push_back(with_template_bank(m, "SemS decoder + template bank (doppler pilots)"));
            }
        }
        return out;
    });
}

// Experiment 7's burst part: the SemS decoder on the burst pattern (consecutive symbols of the
// Doppler pattern's subcarriers) at each N_p of c.exp7_burst_np, beside the budget part's
// rows of the same seeds and test frames. Below N pilots a learned mask may pack its symbols
// into part of the frame; the burst is the hand pattern that does so.
void run_kinematic_burst(const config& c, std::ostream& log)
{
    run_kinematic_part(c, log, "burst pattern", "exp7_burst.csv", c.exp7_burst_np, [](std::vector<dl_method> all) {
        const dl_method& sems = all.front();
        return std::vector<dl_method>{ hand_pattern_method(sems, model_prefix("kinematic", sems.settings.n_pilots),
                                                           "burst") };
    });
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
    if (c.experiments.count(7) && c.exp7_parts.count("main"))
        scenarios.push_back("kinematic");
    // Per experiment: its CSV, its kept class ids (<csv stem>_predictions.npz) and its test
    // frames' truth (exp<N>_truth.npz).
    struct outputs {
        std::unique_ptr<csv_file> csv;
        std::unique_ptr<kept_predictions> kept;
        std::unique_ptr<truth_file> truth;
    };
    std::map<std::string, outputs> out;
    for (const auto& [exp, stem] : { std::pair<std::string, std::string>{ "1", "exp1_recognition" },
                                     { "3", "exp3_conditions" }, { "7", "exp7_kinematic" } }) {
        if (!c.experiments.count(std::stoi(exp)) || (exp == "7" && !c.exp7_parts.count("main")))
            continue;
        out[exp] = { std::make_unique<csv_file>(c.out_dir + "/" + stem + ".csv", header),
                     std::make_unique<kept_predictions>(predictions_path(c.out_dir, stem), exp,
                                                        kept_predictions::kind::class_id),
                     std::make_unique<truth_file>(c.out_dir + "/exp" + exp + "_truth.npz", exp) };
    }
    std::unique_ptr<csv_file> confusion7;
    if (out.count("7"))
        confusion7 = std::make_unique<csv_file>(c.out_dir + "/exp7_confusion.csv", confusion_header);
    const int np = 32;
    const std::string full_mask = scenarios.empty() ? "" : write_mask(c, full_grid_mask(c.fs), "full_grid");

    for (const auto& scen : scenarios) {
        const bool exp1 = scen == "default" || scen == "any", exp7 = scen == "kinematic";
        const std::string exp = exp1 ? "1" : exp7 ? "7" : "3";
        const scene sc = recognition_scene(scen, c);
        // The same test frames for every method and every training seed.
        const uint64_t test_seed = c.seed + 101;
        const test_set ts = scenario_test_set(c, scen, sc, test_seed, log, exp);
        outputs& o = out.at(exp);
        o.truth->add(scen, test_seed, ts.truth, class_names(sc));
        const scenario_run run{ exp, scen, sc, ts, test_seed, *o.csv, *o.kept, exp7 ? confusion7.get() : nullptr };
        scorer sc_run(c, run, log);

        // Seeds outermost: a stopped run still has every method for its first seeds.
        for (uint64_t seed : c.only_shipped ? std::vector<uint64_t>{} : training_seeds(c)) {
            for (const auto& m : learned_methods(c, scen, sc, full_mask, np, seed))
                sc_run.evaluate(m, train_or_load(c, seeded_name(m.model_name, seed), m.settings, log), seed);
            sc_run.svms(np, seed);
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
            if (src.bundle.task != task_kind::classify) // its frame is the run's (checked at the start)
                log << "  shipped classifier " << c.shipped_classifier << " is not a classifier: skipped" << std::endl;
            else if (!other_library.empty())
                log << "  shipped classifier " << c.shipped_classifier << " was trained on class library \""
                    << src.bundle.library->name() << "\", the scene's is \"" << sc.library().name()
                    << "\": skipped (" << other_library << ")" << std::endl;
            else
                sc_run.evaluate({ "Shipped bundle (" + kind + " pilots)", "", kind, training_settings{}, false }, src,
                                std::nullopt);
        }
    }
    if (c.experiments.count(7) && c.exp7_parts.count("budget") && !c.only_shipped)
        run_kinematic_budget(c, log);
    if (c.experiments.count(7) && c.exp7_parts.count("power") && !c.only_shipped)
        run_kinematic_power(c, log);
    if (c.experiments.count(7) && c.exp7_parts.count("bank") && !c.only_shipped)
        run_kinematic_bank(c, log);
    if (c.experiments.count(7) && c.exp7_parts.count("burst") && !c.only_shipped)
        run_kinematic_burst(c, log);
}

} // namespace sems_eval
