// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 2: the classifier decoder's 16-d features under uniform,
 * Doppler-oriented, MSE-learned and SemS pilots, for the t-SNE in plot_results.py. */
#include "eval.h"
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/core/scene/target_class.h>
#include <algorithm>

namespace sems_eval {

void run_tsne(const config& c, std::ostream& log)
{
    if (!c.experiments.count(2))
        return;
    const scene sc = recognition_scene("default", c);
    const uint64_t test_seed = c.seed + 101; // the first frames of experiment 1's test set
    const test_set ts = make_test_set(c.fs, sc, c.tsne_frames, test_seed);
    log << "[" << now_utc() << "] exp 2: features of " << ts.count << " frames at " << c.tsne_snr_db << " dB"
        << std::endl;
    const int np = 32;
    struct item {
        std::string method, model;
        training_settings s;
    };
    std::vector<item> items;
    // The networks of the first training seed: the same bundles experiment 1 trained (cache).
    const uint64_t train_seed = training_seeds(c).front();
    auto base = base_training(c, task_kind::classify, sc, "sems_eval default", train_seed);
    base.n_pilots = np;
    // Experiment 1's hand-pattern decoders: the same name and settings, so one bundle (before,
    // a mask file and fewer epochs here under the same name retrained and overwrote it).
    for (const std::string pattern : { "uniform", "doppler" })
        items.push_back({ pattern == "uniform" ? "Uniform pilots" : "Doppler pilots",
                          seeded_name("cls_default_" + pattern, train_seed), hand_pattern_training(base, pattern) });
    auto mse = base;
    mse.objective = "mse";
    items.push_back({ "MSE-learned pilots", seeded_name("cls_default_mse", train_seed), mse });
    items.push_back({ "SemS pilots", seeded_name("cls_default_sems", train_seed), base });

    std::vector<std::string> header{ "method", "frame",  "class_id",  "class_name",
                                     "snr_db", "predicted", "seed", "train_seed" };
    const int nf = nn::classifier_settings{}.features;
    for (int i = 0; i < nf; ++i)
        header.push_back("f" + std::to_string(i));
    csv_file csv(c.out_dir + "/exp2_tsne_features.csv", header);
    for (const auto& it : items) {
        const auto src = train_or_load(c, it.model, it.s, log);
        src.bundle.check_library(sc.library(), "sems_eval"); // refused with the reason
        const bundle_decoder dec(src.bundle, c.threads);
        const auto obs = ts.observe(src.bundle.mask, c.tsne_snr_db);
        const int d = dec.feature_size(), p = dec.n_pilots(), nc = static_cast<int>(src.bundle.class_names.size());
        if (d != nf)
            throw std::runtime_error(it.model + ": feature size " + std::to_string(d) + ", expected " +
                                     std::to_string(nf));
        const auto t0 = std::chrono::steady_clock::now();
        const auto feats = dec.features(obs.data(), ts.count);
        const auto probs = dec.classify(obs.data(), ts.count);
        const double us = 1e6 * seconds_between(t0, std::chrono::steady_clock::now()) / ts.count;
        int correct = 0;
        for (int f = 0; f < ts.count; ++f) {
            const float* pr = probs.data() + size_t(f) * nc;
            const int pred = sc.library().id_of(src.bundle.class_names[std::max_element(pr, pr + nc) - pr]);
            correct += pred == ts.truth[f].class_id;
            std::vector<std::string> row{ it.method, std::to_string(f), std::to_string(ts.truth[f].class_id),
                                          ts.truth[f].class_name, num(c.tsne_snr_db), std::to_string(pred),
                                          std::to_string(test_seed), std::to_string(train_seed) };
            for (int i = 0; i < d; ++i)
                row.push_back(num(feats[size_t(f) * d + i], 6));
            csv.row(row);
        }
        const double acc = double(correct) / ts.count;
        cost_rows().push_back({ "2", "default", it.method,
                                src.bundle.mask.origin().value("kind", std::string("unknown")), test_seed,
                                std::to_string(train_seed), p, c.tsne_snr_db, "accuracy", acc, us, ts.count,
                                src.train_seconds });
        log << "  " << it.method << ": accuracy " << num(acc, 3) << " at " << c.tsne_snr_db << " dB (train seed "
            << train_seed << ")" << std::endl;
    }
}

} // namespace sems_eval
