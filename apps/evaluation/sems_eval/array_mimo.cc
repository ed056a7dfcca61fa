// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 9, MIMO part: which pilots each transmit element of a MIMO array sends,
 * for a target's azimuth — learned masks (mimo_mask_learner.h) against the hand forms.
 *
 * The array (--exp9-mimo-array, default mimo2x4_3g: 4 receive and 2 transmit elements, an
 * 8-element virtual array) on the frame, N_p = exp9_np pilots in all (each pilot one unit of
 * energy, whichever elements send it). Masks:
 *   "same pilots"          every element sends every pilot at 1/sqrt(N_t)
 *   "time division"        the pattern's symbols to the elements in turn
 *   "frequency division"   the pattern's subcarriers to the elements in turn
 * each on its best standard pattern (uniform, random, doppler, staggered, burst: the one with
 * the lowest mean bound over the scene's azimuths, all listed in exp9_mimo_masks.csv), and
 *   "learned"              learn_mimo_mask, one per seed (exp9_mimo_seeds seeds from --seed),
 * every learner with the same budget (epochs, steps, azimuth draws); beside each, bound only,
 *   "random, polished"     the learner's polish alone (polish_mimo_mask) from a random mask of
 *                          the seed: what the gradient phase adds. Their bound: the azimuth's
 * CRB with the delay, Doppler and complex gain unknown (baselines/mimo_angle.h), its mean over
 * exp9_mimo_azimuths azimuths on [−0.8, 0.8] rad at 0 dB per pilot; the floor of masks whose
 * pilots each come from one element is the virtual array's own bound with N_p/N_t pilots per
 * virtual element, the delay and Doppler known, at the highest subcarrier's frequency
 * (angle_crb_rad2).
 * Estimates: the maximum-likelihood estimator of (φ, τ, ν) (mimo_ml_angle_estimator) on the
 * emulator's frames: an unfaded point target (a car without micro-Doppler; the deterministic
 * amplitude the bound assumes) at an azimuth uniform on [−0.8, 0.8] rad, seen through each
 * mask (mimo_pilots: the same frames and the same unit-variance noise, scaled per SNR, for
 * every mask); each frame's bound at its own gain beside it.
 * Output: exp9_mimo_masks.csv (form, pattern, train_seed, n_pilots, pilots per element,
 * mean_crb_0db_rad2, chosen, seconds, before_polish_rad2: a learned mask's bound before its
 * polish), exp9_mimo.csv (method, train_seed, n_pilots, snr_db,
 * frames, rmse_rad, crb_rad, rmse_over_crb) and exp9_mimo_predictions.csv (every estimate of
 * every frame with its truth and bound: the paired tests of apps/figures/plot_mimo.py); the
 * masks themselves go to <out>/masks_mimo/.
 * Part mimo_budget: the same bounds (hand forms on their best patterns, learned masks, floor)
 * for N_p in exp9_mimo_budget, without the estimates: exp9_mimo_budget.csv (the columns of
 * exp9_mimo_masks.csv). */
#include "eval.h"
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/baselines/mimo_angle.h>
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/channel/mimo_pilots.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/learning/array/mimo_mask_learner.h>
#include <ATen/Parallel.h>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <tuple>

namespace sems_eval {

namespace {

// The scene's azimuths (rad): the interval the bound is averaged over and the targets are drawn from.
constexpr double azimuth_lo = -0.8, azimuth_hi = 0.8;

struct mimo_method {
    std::string name, pattern;
    std::optional<uint64_t> train_seed;
    mimo_mask mask;
    double mean_crb = 0.0;
};

std::string counts_text(const mimo_mask& m)
{
    std::string out;
    for (int c : m.pilots_per_element())
        out += (out.empty() ? "" : "/") + std::to_string(c);
    return out;
}

std::vector<std::string> mask_columns()
{
    return { "form",    "pattern", "train_seed", "n_pilots", "pilots_per_element", "mean_crb_0db_rad2",
             "chosen",  "seconds", "before_polish_rad2" };
}

// The masks of N_p pilots compared, with their mean bound at 0 dB over the scene's azimuths:
// each hand form on its best standard pattern (every pattern tried is a row of `csv`), the
// learned masks (one per seed, the same budget), and the floor's row. With mask_dir, the
// compared masks are written there.
std::vector<mimo_method> mimo_masks(const config& c, const array_geometry& a, int np, int azimuths, csv_file& csv,
                                    std::ostream& log, const std::string& mask_dir)
{
    const frame_settings& fs = c.fs;
    const int nt = a.n_transmit();
    const double lo = azimuth_lo, hi = azimuth_hi;
    std::vector<mimo_method> methods;
    using form_fn = mimo_mask (*)(const pilot_mask&, int);
    const std::vector<std::tuple<std::string, std::string, form_fn>> forms = {
        { "same pilots", "same_pilots", &mimo_mask::same_pilots },
        { "time division", "time_division", &mimo_mask::time_division },
        { "frequency division", "frequency_division", &mimo_mask::frequency_division }
    };
    for (const auto& [name, file, form] : forms) {
        std::vector<mimo_method> tried;
        for (const std::string pattern : { "uniform", "random", "doppler", "staggered", "burst" }) {
            const auto p = pilot_mask::from_pattern(pattern, fs, np, c.seed);
            try {
                const auto m = form(p, nt);
                tried.push_back({ name, pattern, std::nullopt, m, mimo_mean_crb_rad2(a, m, fs, lo, hi, azimuths) });
            } catch (const std::invalid_argument& e) {
                log << "  N_p " << np << ", " << name << " on the " << pattern << " pattern: none (" << e.what() << ")"
                    << std::endl;
            }
        }
        if (tried.empty())
            throw std::invalid_argument("experiment 9 (MIMO): no standard pattern of " + std::to_string(np) +
                                        " pilots gives a " + name + " mask");
        size_t best = 0;
        for (size_t i = 1; i < tried.size(); ++i)
            if (tried[i].mean_crb < tried[best].mean_crb)
                best = i;
        for (size_t i = 0; i < tried.size(); ++i) {
            csv.row({ name, tried[i].pattern, "", std::to_string(np), counts_text(tried[i].mask), num(tried[i].mean_crb, 8),
                      i == best ? "1" : "0", "", "" });
            log << "  N_p " << np << ", " << name << " on the " << tried[i].pattern << " pattern: root mean CRB at 0 dB "
                << num(std::sqrt(tried[i].mean_crb), 5) << " rad" << (i == best ? " (kept)" : "") << std::endl;
        }
        if (!mask_dir.empty())
            tried[best].mask.save(mask_dir + "/" + file + ".json");
        methods.push_back(tried[best]);
    }
    for (int i = 0; i < c.exp9_mimo_seeds; ++i) {
        mimo_mask_settings s;
        s.array = c.exp9_mimo_array;
        s.frame = fs;
        s.n_pilots = np;
        s.azimuth_min_rad = lo;
        s.azimuth_max_rad = hi;
        s.eval_azimuths = azimuths;
        s.epochs = c.exp9_mimo_epochs;
        s.steps = c.exp9_mimo_steps;
        s.draws = c.exp9_mimo_draws;
        s.seed = c.seed + uint64_t(i);
        s.threads = c.threads;
        s.command_line = "sems_eval --experiments 9 (MIMO, N_p " + std::to_string(np) + ", seed " + std::to_string(s.seed) + ")";
        s.verbose = false;
        const auto r = learn_mimo_mask(s, &log);
        csv.row({ "learned", "", std::to_string(s.seed), std::to_string(np), counts_text(r.mask), num(r.mean_crb_rad2, 8),
                  "1", num(r.seconds, 3), num(r.mean_crb_learned_rad2, 8) });
        log << "  N_p " << np << ", learned (seed " << s.seed << "): root mean CRB at 0 dB "
            << num(std::sqrt(r.mean_crb_rad2), 5) << " rad (" << num(std::sqrt(r.mean_crb_learned_rad2), 5)
            << " before " << r.polish_changes << " single changes), pilots per element " << counts_text(r.mask) << ", "
            << num(r.seconds, 3) << " s" << std::endl;
        if (!mask_dir.empty())
            r.mask.save(mask_dir + "/learned_s" + std::to_string(s.seed) + ".json");
        methods.push_back({ "learned", "", s.seed, r.mask, r.mean_crb_rad2 });
        // The same polish from a random mask of the seed (random resource elements, each to a
        // random element): what the gradient phase adds over the polish alone. Bound only.
        std::mt19937_64 g(s.seed + 77);
        std::uniform_int_distribution<int> element(0, nt - 1);
        std::vector<int> tx;
        const auto p = pilot_mask::from_pattern("random", fs, np, s.seed);
        for (int k = 0; k < np; ++k)
            tx.push_back(element(g));
        const mimo_mask start(p, nt, tx, "random start");
        const double before = mimo_mean_crb_rad2(a, start, fs, lo, hi, azimuths);
        double v = 0.0;
        int changes = 0;
        const auto polished = polish_mimo_mask(start, s, &v, &changes);
        csv.row({ "random, polished", "random", std::to_string(s.seed), std::to_string(np), counts_text(polished),
                  num(v, 8), "", "", num(before, 8) });
        log << "  N_p " << np << ", random (seed " << s.seed << "), polished: root mean CRB at 0 dB " << num(std::sqrt(v), 5)
            << " rad (" << num(std::sqrt(before), 5) << " before " << changes << " single changes)" << std::endl;
    }
    // The floor of masks whose pilots each come from one element: the virtual array's bound
    // with N_p/N_t pilots per virtual element (balanced: the largest spread of the transmit
    // positions), the delay and Doppler known, at the highest subcarrier's frequency (the
    // shortest wavelength: the largest electrical aperture any pilot has).
    const double floor = mimo_floor_crb_rad2(a, fs, np, lo, hi, azimuths);
    csv.row({ "virtual array floor", "", "", std::to_string(np), "", num(floor, 8), "", "", "" });
    log << "  N_p " << np << ", virtual array floor: root mean CRB at 0 dB " << num(std::sqrt(floor), 5) << " rad"
        << std::endl;
    return methods;
}

array_geometry mimo_array(const config& c)
{
    const array_geometry a = array_geometry::find(c.exp9_mimo_array);
    if (a.n_transmit() < 2)
        throw std::invalid_argument("--exp9-mimo-array: " + c.exp9_mimo_array + " has " + std::to_string(a.n_transmit()) +
                                    " transmit element; the MIMO part compares masks of two or more");
    return a;
}

} // namespace

void run_array_mimo(const config& c, std::ostream& log)
{
    if (!c.experiments.count(9) || !c.exp9_parts.count("mimo"))
        return;
    const frame_settings& fs = c.fs;
    const array_geometry a = mimo_array(c);
    const int nt = a.n_transmit(), nr = a.n_receive(), np = c.exp9_np;
    const double lo = azimuth_lo, hi = azimuth_hi;
    const int azimuths = c.exp9_mimo_azimuths;
    namespace fsys = std::filesystem;
    const std::string mask_dir = c.out_dir + "/masks_mimo";
    fsys::create_directories(mask_dir);
    log << "[" << now_utc() << "] experiment 9 (MIMO): " << c.exp9_mimo_array << " (" << nr << " receive, " << nt
        << " transmit), N_p " << np << ", " << c.exp9_frames << " frames per point, " << c.exp9_mimo_seeds
        << " learned masks" << std::endl;

    csv_file masks_csv(c.out_dir + "/exp9_mimo_masks.csv", mask_columns());
    auto methods = mimo_masks(c, a, np, azimuths, masks_csv, log, mask_dir);
    // The test frames: one unfaded point target, the same for every mask.
    random_spec rs;
    rs.classes = { target_class::car };
    rs.micro_doppler = false;
    rs.azimuth_min_rad = lo;
    rs.azimuth_max_rad = hi;
    channel_model cm(fs, scene::random(rs, std::nullopt, fading_kind::none).with_array(a), c.seed + 9401);
    const int frames = c.exp9_frames;
    std::vector<frame_realization> r;
    std::vector<std::vector<std::vector<gr_complex>>> y(methods.size()); // method, frame: N_r·N_p
    std::vector<std::vector<gr_complex>> w(static_cast<size_t>(frames));
    {
        std::mt19937_64 g(c.seed + 9402);
        std::normal_distribution<float> n(0.0f, std::sqrt(0.5f));
        for (int f = 0; f < frames; ++f) {
            r.push_back(cm.draw(uint64_t(f)));
            for (size_t m = 0; m < methods.size(); ++m)
                y[m].push_back(mimo_pilots(cm, r.back(), uint64_t(f) * fs.n_symbols, methods[m].mask));
            for (int i = 0; i < nr * np; ++i)
                w[size_t(f)].emplace_back(n(g), n(g));
        }
    }
    csv_file csv(c.out_dir + "/exp9_mimo.csv", { "method", "train_seed", "n_pilots", "snr_db", "frames", "rmse_rad",
                                                 "crb_rad", "rmse_over_crb" });
    csv_file predictions(c.out_dir + "/exp9_mimo_predictions.csv",
                         { "snr_db", "frame", "method", "train_seed", "azimuth_rad", "truth_rad", "crb_rad" });
    angle_search search;
    search.min_rad = -1.0;
    search.max_rad = 1.0;
    search.grid = 64;
    for (size_t m = 0; m < methods.size(); ++m) {
        const mimo_ml_angle_estimator ml(a, methods[m].mask, fs, 0.0, search, 2);
        const std::string seed_text = methods[m].train_seed ? std::to_string(*methods[m].train_seed) : "";
        for (double snr : c.exp9_snrs) {
            const double sigma2 = std::pow(10.0, -snr / 10.0);
            std::vector<double> est(static_cast<size_t>(frames)), bound(static_cast<size_t>(frames));
            at::parallel_for(0, frames, 8, [&](int64_t b, int64_t e) {
                std::vector<gr_complex> v(size_t(nr) * np);
                for (int64_t f = b; f < e; ++f) {
                    for (size_t i = 0; i < v.size(); ++i)
                        v[i] = y[m][size_t(f)][i] + float(std::sqrt(sigma2)) * w[size_t(f)][i];
                    est[size_t(f)] = ml.estimate(v.data()).azimuth_rad;
                    const double g2 = std::norm(r[size_t(f)].paths[0].gain);
                    bound[size_t(f)] = mimo_angle_crb_rad2(a, methods[m].mask, fs, r[size_t(f)].truth.azimuth_rad, 0.0,
                                                           std::max(g2 / sigma2, 1e-300));
                }
            });
            double se = 0.0, crb = 0.0;
            for (int f = 0; f < frames; ++f) {
                const double az = r[size_t(f)].truth.azimuth_rad;
                se += (est[size_t(f)] - az) * (est[size_t(f)] - az);
                crb += bound[size_t(f)];
                predictions.row({ num(snr), std::to_string(f), methods[m].name, seed_text, num(est[size_t(f)], 9),
                                  num(az, 9), num(std::sqrt(bound[size_t(f)]), 6) });
            }
            const double rmse = std::sqrt(se / frames), crb_rad = std::sqrt(crb / frames);
            csv.row({ methods[m].name, seed_text, std::to_string(np), num(snr), std::to_string(frames), num(rmse),
                      num(crb_rad), num(rmse / crb_rad) });
            log << "  " << methods[m].name << (seed_text.empty() ? "" : " [seed " + seed_text + "]") << " snr " << snr
                << ": RMSE " << num(rmse, 4) << " rad (CRB " << num(crb_rad, 4) << ", x" << num(rmse / crb_rad, 3) << ")"
                << std::endl;
        }
    }
}

void run_array_mimo_budget(const config& c, std::ostream& log)
{
    if (!c.experiments.count(9) || !c.exp9_parts.count("mimo_budget"))
        return;
    const array_geometry a = mimo_array(c);
    log << "[" << now_utc() << "] experiment 9 (MIMO, pilot budget): " << c.exp9_mimo_array << ", N_p";
    for (int np : c.exp9_mimo_budget)
        log << " " << np;
    log << ", " << c.exp9_mimo_seeds << " learned masks each" << std::endl;
    csv_file csv(c.out_dir + "/exp9_mimo_budget.csv", mask_columns());
    for (int np : c.exp9_mimo_budget)
        mimo_masks(c, a, np, c.exp9_mimo_azimuths, csv, log, "");
}

} // namespace sems_eval
