// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiments 4 and 5: delay-index MAE against SNR (single path and
 * multipath) for SemS and the classical estimators, with the CRB; and SemS against
 * the pilot budget N_p. */
#include "eval.h"
#include <gnuradio/sems/baselines/subcarrier_masks.h>
#include <gnuradio/sems/baselines/music_delay_estimator.h>
#include <gnuradio/sems/baselines/omp_delay_estimator.h>
#include <gnuradio/sems/baselines/periodogram_delay_estimator.h>
#include <gnuradio/sems/learning/bundle_decoder.h>
#include <gnuradio/sems/baselines/delay_crb.h>
#include <gnuradio/sems/learning/network_settings.h>
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>

namespace sems_eval {

namespace {

struct errors {
    double mae = 0, rmse = 0, median = 0;
};

errors delay_errors(const std::vector<double>& est, const test_set& ts)
{
    errors e;
    std::vector<double> a;
    for (int f = 0; f < ts.count; ++f) {
        const double d = est[f] - ts.truth[f].delay_index;
        a.push_back(std::abs(d));
        e.mae += std::abs(d);
        e.rmse += d * d;
    }
    e.mae /= ts.count;
    e.rmse = std::sqrt(e.rmse / ts.count);
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

std::string model_name(const std::string& scen, int np) { return "delay_" + scen + "_np" + std::to_string(np); }

training_settings delay_training(const config& c, const std::string& scen, int paths, int np)
{
    auto s = base_training(c, task_kind::delay, delay_scene(paths), "sems_eval delay " + scen);
    s.n_pilots = np;
    return s;
}

// The classical estimators' search window: the delay decoder's default dictionary range.
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
                   "median_abs_error_index", "crb_mae_index", "n_frames", "seed", "us_per_frame", "train_seconds",
                   "model" });
    const int np = 32;
    for (const auto& scenario : std::vector<std::pair<std::string, int>>{ { "single", 1 },
                                                                         { "multipath", c.multipath_paths } }) {
        const std::string scen = scenario.first;
        const int paths = scenario.second;
        const uint64_t test_seed = c.seed + (paths == 1 ? 303 : 304);
        const test_set ts = make_test_set(c.fs, delay_scene(paths), c.test_frames, test_seed);
        log << "[" << now_utc() << "] exp 4 (" << scen << ", " << paths << " path(s)): " << ts.count
            << " test frames, seed " << test_seed << std::endl;

        auto write = [&](const std::string& method, const std::string& mask, int p, double snr, const errors& e,
                         double crb, double us, double train_s, const std::string& model) {
            csv.row({ "4", scen, method, mask, std::to_string(p), num(snr), num(e.mae), num(e.rmse), num(e.median),
                      num(crb), std::to_string(ts.count), std::to_string(test_seed), num(us, 4), num(train_s, 4),
                      model });
            cost_rows().push_back({ "4", scen, method, p, snr, "mae_index", e.mae, us, ts.count, train_s });
            log << "  " << scen << " " << method << " snr " << num(snr) << ": MAE " << num(e.mae, 4) << " (CRB "
                << num(crb, 3) << ", " << num(us, 3) << " us/frame)" << std::endl;
        };
        auto crb_of = [&](const pilot_mask& m, double snr) {
            try {
                return delay_crb::mae_index(c.fs, m, snr, false, true);
            } catch (const std::invalid_argument&) {
                return std::nan("");
            }
        };

        // SemS (trained here; and the shipped bundle when given).
        std::vector<std::pair<std::string, decoder_source>> sems;
        if (!c.only_shipped)
            sems.emplace_back("SemS", train_or_load(c, model_name(scen, np), delay_training(c, scen, paths, np), log));
        const std::string& shipped = paths == 1 ? c.shipped_delay_single : c.shipped_delay_multi;
        if (!shipped.empty()) {
            decoder_source s;
            s.bundle = model_bundle::load(shipped);
            s.origin = shipped;
            const std::string kind = s.bundle.mask.origin().value("kind", std::string("unknown"));
            if (s.bundle.task == task_kind::delay && s.bundle.frame == c.fs)
                sems.emplace_back("Shipped bundle (" + kind + " pilots)", s);
            else
                log << "  shipped delay bundle " << shipped << " does not match the frame: skipped" << std::endl;
        }
        for (const auto& [method, src] : sems) {
            const bundle_decoder dec(src.bundle, c.threads);
            for (double snr : c.delay_snrs) {
                double us = 0;
                const auto est = run_bundle(dec, ts.observe(src.bundle.mask, snr), ts.count, us);
                write(method, src.bundle.mask.origin().value("kind", std::string("unknown")), dec.n_pilots(), snr,
                      delay_errors(est, ts), crb_of(src.bundle.mask, snr),
                      us, src.train_seconds, src.origin);
            }
        }

        if (c.only_shipped)
            continue;
        // Classical estimators, model order = the scene's paths per target.
        const auto win = classic_window(c);
        const auto random = pilot_mask::random(c.fs.n_symbols, c.fs.n_subcarriers, np, 1);
        const auto uniform = pilot_mask::uniform(c.fs.n_symbols, c.fs.n_subcarriers, np);
        const auto rp = random_subcarrier_mask(c.fs.n_symbols, c.fs.n_subcarriers, np, 1);
        const auto op = nested_subcarrier_mask(c.fs.n_symbols, c.fs.n_subcarriers, np);
        struct classic {
            std::string method, mask_label;
            const pilot_mask* mask;
            std::function<double(const gr_complex*)> estimate;
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
        for (const auto& m : methods)
            for (double snr : c.delay_snrs) {
                const auto obs = ts.observe(*m.mask, snr);
                std::vector<double> est(ts.count);
                const auto t0 = std::chrono::steady_clock::now();
                for (int f = 0; f < ts.count; ++f)
                    est[f] = m.estimate(obs.data() + size_t(f) * np);
                const double us = 1e6 * seconds_between(t0, std::chrono::steady_clock::now()) / ts.count;
                write(m.method, m.mask_label, np, snr, delay_errors(est, ts), crb_of(*m.mask, snr), us, 0.0,
                      "classical");
            }
        // The bound itself, for the random pattern the periodogram and OMP use.
        for (double snr : c.delay_snrs) {
            const double crb = crb_of(random, snr);
            csv.row({ "4", scen, "CRB (random pilots)", "random", std::to_string(np), num(snr), num(crb), "nan",
                      "nan", num(crb), std::to_string(ts.count), std::to_string(test_seed), "nan", "0",
                      "closed form; single path; unknown Doppler; Rayleigh-averaged MAE" });
        }
    }
}

void run_pilot_budget(const config& c, std::ostream& log)
{
    if (!c.experiments.count(5))
        return;
    csv_file csv(c.out_dir + "/exp5_pilot_budget.csv",
                 { "experiment", "scenario", "method", "n_pilots", "snr_db", "mae_index", "rmse_index",
                   "median_abs_error_index", "crb_mae_index", "n_frames", "seed", "us_per_frame", "train_seconds",
                   "model" });
    const std::string scen = "multipath";
    const uint64_t test_seed = c.seed + 304; // experiment 4's multipath frames
    const test_set ts = make_test_set(c.fs, delay_scene(c.multipath_paths), c.test_frames, test_seed);
    log << "[" << now_utc() << "] exp 5: N_p sweep on " << ts.count << " multipath frames" << std::endl;
    for (int np : c.np_sweep) {
        const auto src = train_or_load(c, model_name(scen, np), delay_training(c, scen, c.multipath_paths, np), log);
        const bundle_decoder dec(src.bundle, c.threads);
        for (double snr : c.delay_snrs) {
            double us = 0;
            const auto est = run_bundle(dec, ts.observe(src.bundle.mask, snr), ts.count, us);
            const auto e = delay_errors(est, ts);
            double crb = std::nan("");
            try {
                crb = delay_crb::mae_index(c.fs, src.bundle.mask, snr, false, true);
            } catch (const std::invalid_argument&) {
            }
            csv.row({ "5", scen, "SemS", std::to_string(np), num(snr), num(e.mae), num(e.rmse), num(e.median), num(crb),
                      std::to_string(ts.count), std::to_string(test_seed), num(us, 4), num(src.train_seconds, 4),
                      src.origin });
            cost_rows().push_back({ "5", scen, "SemS N_p=" + std::to_string(np), np, snr, "mae_index", e.mae, us,
                                    ts.count, src.train_seconds });
            log << "  N_p " << np << " snr " << num(snr) << ": MAE " << num(e.mae, 4) << std::endl;
        }
    }
}

void write_cost(const config& c, std::ostream& log)
{
    if (!c.experiments.count(6))
        return;
    csv_file csv(c.out_dir + "/exp6_cost.csv",
                 { "experiment", "scenario", "method", "n_pilots", "snr_db", "metric", "value", "us_per_frame",
                   "n_frames", "seed", "train_seconds" });
    for (const auto& r : cost_rows())
        csv.row({ r.experiment, r.scenario, r.method, std::to_string(r.n_pilots), num(r.snr_db), r.metric,
                  num(r.value), num(r.us_per_frame, 4), std::to_string(r.n_frames), std::to_string(c.seed),
                  num(r.train_seconds, 4) });
    log << "[" << now_utc() << "] exp 6: " << cost_rows().size() << " cost rows" << std::endl;
}

} // namespace sems_eval
