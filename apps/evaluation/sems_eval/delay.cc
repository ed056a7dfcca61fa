// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiments 4 and 5: delay-index errors against SNR (single path and
 * multipath) for SemS and the classical estimators, with the CRB; and SemS against
 * the pilot budget N_p. Each row reports the mean, RMS and median absolute error, and
 * experiment 4's the fraction of frames off by more than half a delay index (gross errors).
 *
 * The classical side is fair: OMP also with off-grid LS refinement, and the oracle-order
 * least-squares reference (grid search, then nonlinear least squares over all delays and
 * the shared Doppler, the true number of paths) both on 32 random subcarriers of one
 * symbol and on the SemS bundle's own pilots. Bounds: the single-path CRB (at the direct
 * path's mean power in multipath) and, in multipath, the CRB of the direct path with all
 * paths unknown, evaluated on every test frame's true paths. */
#include "eval.h"
#include "predictions.h"
#include <gnuradio/sems/baselines/ls_delay_estimator.h>
#include <gnuradio/sems/baselines/subcarrier_masks.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/baselines/music_delay_estimator.h>
#include <gnuradio/sems/baselines/omp_delay_estimator.h>
#include <gnuradio/sems/baselines/periodogram_delay_estimator.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/baselines/delay_crb.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <stdexcept>
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>

namespace sems_eval {

namespace {

struct errors {
    double mae = 0, rmse = 0, median = 0, gross = 0; // gross: fraction with |error| > 0.5 index
};

// Each frame's error, estimate minus the true delay index, rounded once to float32: what the
// kept predictions hold (<csv stem>_predictions.npz) and what every score below is computed
// from, so the CSV's scores are exactly those of the kept errors.
std::vector<float> index_errors(const std::vector<double>& est, const test_set& ts)
{
    std::vector<float> out(ts.count);
    for (int f = 0; f < ts.count; ++f)
        out[f] = static_cast<float>(est[f] - ts.truth[f].delay_index);
    return out;
}

errors delay_errors(const std::vector<float>& err)
{
    errors e;
    std::vector<double> a;
    const size_t count = err.size();
    for (float ef : err) {
        const double d = ef;
        a.push_back(std::abs(d));
        e.mae += std::abs(d);
        e.rmse += d * d;
        e.gross += std::abs(d) > 0.5 ? 1.0 : 0.0;
    }
    e.gross /= count;
    e.mae /= count;
    e.rmse = std::sqrt(e.rmse / count);
    std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
    e.median = a[a.size() / 2];
    return e;
}

std::vector<double> run_bundle(const bundle_decoder& dec, const std::vector<gr_complex>& obs, int count, double& us)
{
    const int np = dec.n_pilots();
    std::vector<double> out;
    dec.estimate_delay_index(obs.data(), std::min(count, 32)); // warm-up, untimed
    const auto t0 = std::chrono::steady_clock::now();
    for (int f0 = 0; f0 < count; f0 += 256) {
        const int b = std::min(256, count - f0);
        const auto e = dec.estimate_delay_index(obs.data() + size_t(f0) * np, b);
        out.insert(out.end(), e.begin(), e.end());
    }
    us = 1e6 * seconds_between(t0, std::chrono::steady_clock::now()) / count;
    return out;
}

std::string model_name(const std::string& scen, int np, uint64_t train_seed)
{
    return seeded_name("delay_" + scen + "_np" + std::to_string(np), train_seed);
}

training_settings delay_training(const config& c, const std::string& scen, int paths, int np, uint64_t train_seed)
{
    auto s = base_training(c, task_kind::delay, delay_scene(paths), "sems_eval delay " + scen, train_seed);
    s.n_pilots = np;
    return s;
}

// 32 (np) random subcarriers on the middle symbol: the classical side's one-symbol pattern
// (pilots on one symbol see no Doppler rotation between them). Drawn among the frame's
// usable subcarriers, so a frame with guards gets none on a guard.
pilot_mask one_symbol_mask(const frame_settings& fs, int np, uint64_t seed)
{
    const auto usable = fs.usable_subcarriers();
    if (np > static_cast<int>(usable.size()))
        throw std::invalid_argument("sems_eval: " + std::to_string(np) + " pilots on one symbol, but the frame has " +
                                    std::to_string(usable.size()) + " usable subcarriers");
    const auto r = pilot_mask::random(1, static_cast<int>(usable.size()), np, seed); // np distinct columns
    std::vector<pilot_position> pos;
    for (const auto& p : r.positions())
        pos.push_back({ fs.n_symbols / 2, usable[p.m] });
    return pilot_mask(fs.n_symbols, fs.n_subcarriers, pos, gr_complex(1.0f, 0.0f),
                      { { "kind", "random subcarriers, one symbol" }, { "seed", seed } });
}

// The true paths of every test frame (the draws make_test_set made: same scene, seed, order).
std::vector<std::vector<crb_path>> test_paths(const frame_settings& fs, const scene& sc, int count, uint64_t seed)
{
    channel_model cm(fs, sc, seed);
    std::vector<std::vector<crb_path>> out;
    for (int f = 0; f < count; ++f) {
        std::vector<crb_path> p;
        for (const auto& cp : cm.draw(f).paths)
            p.push_back({ fs.delay_index(cp.delay_s), cp.gain });
        out.push_back(p);
    }
    return out;
}

// The classical estimators' search window: the delay decoder's default dictionary range.
// The direct path's mean power in a delay scene of `paths` paths: 1 / Σ_k 10^(-k·decay/10)
// (1 for one path), where the single-path CRB of a multipath frame is taken.
double direct_path_power(int paths)
{
    const auto r = *delay_scene(paths).random_settings();
    double sum = 0.0;
    for (int k = 0; k < paths; ++k)
        sum += std::pow(10.0, -k * r.path_power_decay_db / 10.0);
    return 1.0 / sum;
}

delay_search classic_window(const config& c)
{
    delay_search w;
    const nn::delay_settings d{};
    w.oversample = c.classic_oversample;
    w.min_index = d.tau_min_index;
    w.max_index = d.tau_max_index;
    return w;
}

} // namespace

void run_delay(const config& c, std::ostream& log)
{
    if (!c.experiments.count(4))
        return;
    csv_file csv(c.out_dir + "/exp4_delay.csv",
                 { "experiment", "scenario", "method", "mask", "n_pilots", "snr_db", "mae_index", "rmse_index",
                   "median_abs_error_index", "frac_error_over_half_index", "crb_mae_index", "n_frames", "seed",
                   "train_seed", "us_per_frame", "train_seconds", "model" });
    // Every method's per-frame errors beside the CSV (the bounds have none), and the truth.
    kept_predictions kept(predictions_path(c.out_dir, "exp4_delay"), "4", kept_predictions::kind::delay_index);
    truth_file truth(c.out_dir + "/exp4_truth.npz", "4");
    const int np = 32;
    for (const auto& scenario : std::vector<std::pair<std::string, int>>{ { "single", 1 },
                                                                         { "multipath", c.multipath_paths } }) {
        const std::string scen = scenario.first;
        if (!c.delay_scenarios.count(scen))
            continue;
        const int paths = scenario.second;
        const uint64_t test_seed = c.seed + (paths == 1 ? 303 : 304);
        const test_set ts = make_test_set(c.fs, delay_scene(paths), c.test_frames, test_seed);
        log << "[" << now_utc() << "] exp 4 (" << scen << ", " << paths << " path(s)): " << ts.count
            << " test frames, seed " << test_seed << std::endl;
        truth.add(scen, test_seed, ts.truth, class_names(delay_scene(paths)));

        // Scores one method's errors at one SNR: the CSV row, the kept errors and the cost row.
        auto write = [&](const std::string& method, const std::string& mask, int p, double snr,
                         const std::vector<float>& err, double crb, double us, double train_s,
                         const std::string& model, std::optional<uint64_t> train_seed) {
            const errors e = delay_errors(err);
            kept.add({ scen, method, mask, p, snr, train_seed, test_seed }, err);
            const std::string ts_label = train_seed_label(train_seed);
            csv.row({ "4", scen, method, mask, std::to_string(p), num(snr), num(e.mae), num(e.rmse), num(e.median),
                      num(e.gross), num(crb), std::to_string(ts.count), std::to_string(test_seed), ts_label,
                      num(us, 4), num(train_s, 4), model });
            cost_rows().push_back(
                { "4", scen, method, mask, test_seed, ts_label, p, snr, "mae_index", e.mae, us, ts.count, train_s });
            log << "  " << scen << " " << method << " [train seed " << ts_label << "] snr " << num(snr) << ": MAE "
                << num(e.mae, 4) << ", median "
                << num(e.median, 4) << ", > 0.5: " << num(e.gross, 4) << " (CRB " << num(crb, 3) << ", "
                << num(us, 3) << " us/frame)" << std::endl;
        };
        const double direct_power = direct_path_power(paths);
        auto crb_of = [&](const pilot_mask& m, double snr) {
            try {
                return delay_crb::mae_index(c.fs, m, snr, false, true, direct_power);
            } catch (const std::invalid_argument&) {
                return std::nan("");
            }
        };

        // SemS, once per training seed (and the shipped bundle when given: not trained here,
        // no training seed).
        struct learned {
            std::string method;
            decoder_source src;
            std::optional<uint64_t> train_seed;
        };
        std::vector<learned> sems;
        if (!c.only_shipped)
            for (uint64_t seed : training_seeds(c))
                sems.push_back(
                    { "SemS",
                      train_or_load(c, model_name(scen, np, seed), delay_training(c, scen, paths, np, seed), log),
                      seed });
        const std::string& shipped = paths == 1 ? c.shipped_delay_single : c.shipped_delay_multi;
        if (!shipped.empty()) {
            decoder_source s;
            s.bundle = model_bundle::load(shipped);
            s.origin = shipped;
            const std::string kind = s.bundle.mask.origin().value("kind", std::string("unknown"));
            if (s.bundle.task == task_kind::delay) // its frame is the run's (checked at the start)
                sems.push_back({ "Shipped bundle (" + kind + " pilots)", s, std::nullopt });
            else
                log << "  shipped delay bundle " << shipped << " is not a delay model: skipped" << std::endl;
        }
        // A bundle with a refinement stage is also scored without it (the network alone).
        for (size_t i = 0, n = sems.size(); i < n; ++i) {
            const auto& st = sems[i].src.bundle.decoder;
            if (st.contains("settings") && st["settings"].value("refine_paths", 0) > 0) {
                auto alone = sems[i];
                alone.method += ", network only";
                alone.src.bundle.decoder["settings"]["refine_paths"] = 0;
                sems.push_back(alone);
            }
        }
        for (const auto& [method, src, train_seed] : sems) {
            const bundle_decoder dec(src.bundle, c.threads);
            for (double snr : c.delay_snrs) {
                double us = 0;
                const auto est = run_bundle(dec, ts.observe(src.bundle.mask, snr), ts.count, us);
                write(method, src.bundle.mask.origin().value("kind", std::string("unknown")), dec.n_pilots(), snr,
                      index_errors(est, ts), crb_of(src.bundle.mask, snr), us, src.train_seconds, src.origin,
                      train_seed);
            }
            kept.write(); // after each method: a stopped run keeps what it scored
        }

        if (c.only_shipped)
            continue;
        // Classical estimators, model order = the scene's paths per target.
        const auto win = classic_window(c);
        const auto random = pilot_mask::from_pattern("random", c.fs, np, 1);
        const auto uniform = pilot_mask::from_pattern("uniform", c.fs, np);
        const auto rp = random_subcarrier_mask(c.fs.n_symbols, c.fs.n_subcarriers, np, 1);
        const auto op = nested_subcarrier_mask(c.fs.n_symbols, c.fs.n_subcarriers, np);
        const auto one_symbol = one_symbol_mask(c.fs, np, 1);
        // The pilots of each SemS bundle trained here (one per training seed), for the LS
        // reference and the bounds on them: rows that carry that training seed, since the
        // mask is what the training learned.
        std::vector<std::pair<pilot_mask, uint64_t>> sems_masks;
        for (const auto& l : sems)
            if (l.method == "SemS")
                sems_masks.emplace_back(l.src.bundle.mask, *l.train_seed);
        struct classic {
            std::string method, mask_label;
            const pilot_mask* mask;
            std::function<double(const gr_complex*)> estimate;
            std::optional<uint64_t> train_seed; // set when the mask is a trained bundle's
        };
        std::vector<classic> methods;
        periodogram_delay_estimator::settings ps;
        ps.search = win;
        auto pg = std::make_shared<periodogram_delay_estimator>(c.fs, random, ps);
        methods.push_back({ "Periodogram", "random", &random, [pg](const gr_complex* o) { return pg->estimate_index(o); } });
        omp_delay_estimator::settings os;
        os.search = win;
        os.n_atoms = paths;
        auto omp = std::make_shared<omp_delay_estimator>(c.fs, random, os);
        methods.push_back({ "OMP", "random", &random, [omp](const gr_complex* o) { return omp->estimate_index(o); } });
        os.refine = true;
        auto ompr = std::make_shared<omp_delay_estimator>(c.fs, random, os);
        methods.push_back(
            { "OMP + LS refinement", "random", &random, [ompr](const gr_complex* o) { return ompr->estimate_index(o); } });
        auto omp1 = std::make_shared<omp_delay_estimator>(c.fs, one_symbol, os);
        methods.push_back({ "OMP + LS refinement", "random subcarriers, one symbol", &one_symbol,
                            [omp1](const gr_complex* o) { return omp1->estimate_index(o); } });
        ls_delay_estimator::settings ls;
        ls.search = win;
        ls.n_paths = paths;
        {
            auto est = std::make_shared<ls_delay_estimator>(c.fs, one_symbol, ls);
            methods.push_back({ "LS reference (oracle order)", "random subcarriers, one symbol", &one_symbol,
                                [est](const gr_complex* o) { return est->estimate_index(o); } });
        }
        for (const auto& [m, seed] : sems_masks) {
            auto est = std::make_shared<ls_delay_estimator>(c.fs, m, ls);
            methods.push_back({ "LS reference (oracle order)", "SemS pilots", &m,
                                [est](const gr_complex* o) { return est->estimate_index(o); }, seed });
        }
        for (const auto& [name, label, mask] :
             std::vector<std::tuple<std::string, std::string, const pilot_mask*>>{
                 { "UP-MUSIC", "uniform", &uniform }, { "RP-MUSIC", "random subcarriers", &rp },
                 { "OP-MUSIC", "nested subcarriers", &op } }) {
            music_delay_estimator::settings ms;
            ms.search = win;
            ms.n_paths = paths;
            try {
                auto mu = std::make_shared<music_delay_estimator>(c.fs, *mask, ms);
                log << "  " << name << ": co-array spacing " << mu->coarray_spacing() << ", length "
                    << mu->coarray_length() << std::endl;
                methods.push_back({ name, label, mask, [mu](const gr_complex* o) { return mu->estimate_index(o); } });
            } catch (const std::invalid_argument& e) {
                log << "  " << name << " not applicable: " << e.what() << std::endl;
            }
        }
        for (const auto& m : methods) {
            for (double snr : c.delay_snrs) {
                const auto obs = ts.observe(*m.mask, snr);
                std::vector<double> est(ts.count);
                const auto t0 = std::chrono::steady_clock::now();
                for (int f = 0; f < ts.count; ++f)
                    est[f] = m.estimate(obs.data() + size_t(f) * np);
                const double us = 1e6 * seconds_between(t0, std::chrono::steady_clock::now()) / ts.count;
                write(m.method, m.mask_label, np, snr, index_errors(est, ts), crb_of(*m.mask, snr), us, 0.0,
                      "classical", m.train_seed);
            }
            kept.write();
        }
        // The bounds: the single-path closed form (at the direct path's mean power) for the
        // random pattern, the one-symbol pattern and the SemS pilots; in multipath also the
        // direct path's bound with every path unknown, on each test frame's true paths
        // (mean of the MAE of an efficient estimator √(2/π)·√CRB; median √CRB).
        const auto truth_paths = paths > 1 ? test_paths(c.fs, delay_scene(paths), ts.count, test_seed)
                                           : std::vector<std::vector<crb_path>>{};
        struct bound_mask {
            std::string label;
            const pilot_mask* mask;
            std::optional<uint64_t> train_seed; // set for a trained bundle's pilots
        };
        std::vector<bound_mask> bound_masks{ { "random", &random, std::nullopt },
                                             { "random subcarriers, one symbol", &one_symbol, std::nullopt } };
        for (const auto& [m, seed] : sems_masks)
            bound_masks.push_back({ "SemS pilots", &m, seed });
        for (const auto& [label, m, train_seed] : bound_masks) {
            const std::string ts_label = train_seed_label(train_seed);
            for (double snr : c.delay_snrs) {
                const double crb = crb_of(*m, snr);
                csv.row({ "4", scen, paths > 1 ? "CRB (single path at the direct path's mean power)" : "CRB", label,
                          std::to_string(np), num(snr), num(crb), "nan", "nan", "nan", num(crb),
                          std::to_string(ts.count), std::to_string(test_seed), ts_label, "nan", "0",
                          "closed form; single path; unknown Doppler; Rayleigh-averaged MAE" });
                if (paths == 1)
                    continue;
                std::vector<double> sd;
                double mae = 0.0;
                for (const auto& p : truth_paths) {
                    double v = std::numeric_limits<double>::infinity();
                    try {
                        v = delay_crb::multipath_variance_index(c.fs, *m, snr, p, false);
                    } catch (const std::invalid_argument&) { // a direct path of zero gain
                    }
                    sd.push_back(std::sqrt(v));
                    mae += std::sqrt(2.0 / M_PI) * std::sqrt(v);
                }
                mae /= truth_paths.size();
                std::nth_element(sd.begin(), sd.begin() + sd.size() / 2, sd.end());
                csv.row({ "4", scen, "CRB (multipath, direct path)", label, std::to_string(np), num(snr), num(mae),
                          "nan", num(sd[sd.size() / 2]), "nan", num(mae), std::to_string(ts.count),
                          std::to_string(test_seed), ts_label, "nan", "0",
                          "all paths unknown + shared Doppler; per test frame; mean sqrt(2/pi)*sqrt(CRB), median sqrt(CRB)" });
                log << "  " << scen << " multipath CRB (" << label << ", train seed " << ts_label << ") snr "
                    << num(snr) << ": mean MAE "
                    << num(mae, 4) << ", median sqrt(CRB) " << num(sd[sd.size() / 2], 4) << std::endl;
            }
        }
    }
}

void run_pilot_budget(const config& c, std::ostream& log)
{
    if (!c.experiments.count(5))
        return;
    csv_file csv(c.out_dir + "/exp5_pilot_budget.csv",
                 { "experiment", "scenario", "method", "n_pilots", "snr_db", "mae_index", "rmse_index",
                   "median_abs_error_index", "crb_mae_index", "n_frames", "seed", "train_seed", "us_per_frame",
                   "train_seconds", "model" });
    const std::string scen = "multipath";
    const uint64_t test_seed = c.seed + 304; // experiment 4's multipath frames
    const test_set ts = make_test_set(c.fs, delay_scene(c.multipath_paths), c.test_frames, test_seed);
    log << "[" << now_utc() << "] exp 5: N_p sweep on " << ts.count << " multipath frames" << std::endl;
    kept_predictions kept(predictions_path(c.out_dir, "exp5_pilot_budget"), "5", kept_predictions::kind::delay_index);
    truth_file(c.out_dir + "/exp5_truth.npz", "5")
        .add(scen, test_seed, ts.truth, class_names(delay_scene(c.multipath_paths)));
    // Seeds outermost: a stopped run still has every N_p for its first seeds.
    for (uint64_t seed : training_seeds(c)) {
        for (int np : c.np_sweep) {
            const auto src =
                train_or_load(c, model_name(scen, np, seed), delay_training(c, scen, c.multipath_paths, np, seed), log);
            const bundle_decoder dec(src.bundle, c.threads);
            const std::string mask = src.bundle.mask.origin().value("kind", std::string("unknown"));
            for (double snr : c.delay_snrs) {
                double us = 0;
                const auto est = run_bundle(dec, ts.observe(src.bundle.mask, snr), ts.count, us);
                const auto err = index_errors(est, ts);
                const auto e = delay_errors(err);
                kept.add({ scen, "SemS", mask, np, snr, seed, test_seed }, err);
                double crb = std::nan("");
                try {
                    crb = delay_crb::mae_index(c.fs, src.bundle.mask, snr, false, true,
                                               direct_path_power(c.multipath_paths));
                } catch (const std::invalid_argument&) {
                }
                csv.row({ "5", scen, "SemS", std::to_string(np), num(snr), num(e.mae), num(e.rmse), num(e.median),
                          num(crb), std::to_string(ts.count), std::to_string(test_seed), std::to_string(seed),
                          num(us, 4), num(src.train_seconds, 4), src.origin });
                cost_rows().push_back({ "5", scen, "SemS N_p=" + std::to_string(np), mask, test_seed,
                                        std::to_string(seed), np, snr, "mae_index", e.mae, us, ts.count,
                                        src.train_seconds });
                log << "  N_p " << np << " [train seed " << seed << "] snr " << num(snr) << ": MAE " << num(e.mae, 4)
                    << std::endl;
            }
            kept.write();
        }
    }
}

void write_cost(const config& c, std::ostream& log)
{
    if (!c.experiments.count(6))
        return;
    csv_file csv(c.out_dir + "/exp6_cost.csv",
                 { "experiment", "scenario", "method", "mask", "n_pilots", "snr_db", "metric", "value", "us_per_frame",
                   "n_frames", "seed", "train_seed", "train_seconds" });
    for (const auto& r : cost_rows())
        csv.row({ r.experiment, r.scenario, r.method, r.mask, std::to_string(r.n_pilots), num(r.snr_db), r.metric,
                  num(r.value), num(r.us_per_frame, 4), std::to_string(r.n_frames), std::to_string(r.test_seed),
                  r.train_seed, num(r.train_seconds, 4) });
    log << "[" << now_utc() << "] exp 6: " << cost_rows().size() << " cost rows" << std::endl;
}

} // namespace sems_eval
