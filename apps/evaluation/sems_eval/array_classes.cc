// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 9, classes part: classification per frame with 1, 4 and 8 receive
 * elements, as SemS Classifier Sink does it over an array (array_beamformer.h): each frame's
 * N_r·N_p pilots beamformed towards the peak of its beamforming spectrum, then read by a
 * classifier bundle trained on one antenna.
 *
 * Test frames: the bundle's classes (any heading, one path, Rayleigh) at an
 * azimuth uniform on [−0.8, 0.8] rad, seen by a half-wavelength ULA of each element count (one
 * element: the single-antenna model). The same channel seed draws the same bodies, gains and
 * azimuths for every count (class, delay, radial velocity and azimuth checked), so every array
 * sees the same targets; each element has
 * its own unit-variance noise, drawn once per frame and scaled per SNR (element k's noise is the
 * same in every array). The SNR is per pilot and element.
 * Methods, for each classifier bundle (--exp9-classifier-bundles; one per training seed) and SNR:
 *   "N elements, beamformed"           the sink's combination ("1 element": its pilots as they are)
 *   "N elements, beamformed at the true azimuth"   the combination's own reference: the direction
 *                                      known, so what the azimuth search costs is the difference
 *   "one antenna at +10 log10 N dB"    the array's gain as a closed form: one antenna with the
 *                                      noise divided by N, which beamforming matches for a target
 *                                      that is a plane wave over the aperture
 * Output: exp9_classes.csv (scenario, method, mask, elements, n_pilots, snr_db, train_seed,
 * test_seed, frames, accuracy, macro_f1, us_per_frame; us_per_frame of a beamformed row includes
 * the combination), exp9_classes_predictions.npz and exp9_truth.npz (every
 * frame's class id per series; predictions.h) for the paired tests of
 * apps/figures/plot_array_classes.py. */
#include "eval.h"
#include "predictions.h"
#include <gnuradio/sems/baselines/array_beamformer.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

namespace sems_eval {

namespace {

// One array's test frames: per frame its K·N_p noiseless pilots (element-major).
struct array_test_frames {
    array_geometry array;
    std::vector<std::vector<gr_complex>> y;
    std::vector<frame_truth> truth;
};

array_test_frames draw(const frame_settings& fs, const scene& sc, const array_geometry& a, const pilot_mask& mask,
                  int count, uint64_t seed)
{
    array_test_frames out{ a, {}, {} };
    channel_model cm(fs, sc.with_array(a), seed);
    const auto flat = mask.flat_indices();
    std::vector<gr_complex> h(size_t(fs.grid_size()));
    for (int f = 0; f < count; ++f) {
        const auto r = cm.draw(uint64_t(f));
        out.y.push_back(array_pilots(cm, r, uint64_t(f) * fs.n_symbols, flat, h));
        out.truth.push_back(r.truth);
    }
    return out;
}

bool same_targets(const frame_truth& a, const frame_truth& b)
{
    return a.class_id == b.class_id && a.delay_index == b.delay_index && a.velocity_mps == b.velocity_mps &&
           a.azimuth_rad == b.azimuth_rad;
}

} // namespace

void run_array_classes(const config& c, std::ostream& log)
{
    if (!c.experiments.count(9) || !c.exp9_parts.count("classes"))
        return;
    const frame_settings& fs = c.fs;
    std::vector<model_bundle> bundles;
    for (const auto& name : c.exp9_classifier_bundles)
        bundles.push_back(model_bundle::load(name));
    const model_bundle& first = bundles.front();
    for (const auto& b : bundles) {
        if (b.task != task_kind::classify || b.super_frames() != 1)
            throw std::invalid_argument("--exp9-classifier-bundles: " + b.directory +
                                        " is not a classifier bundle of one frame's mask");
        if (b.mask.size() != first.mask.size() || b.class_names != first.class_names)
            throw std::invalid_argument("--exp9-classifier-bundles: " + b.directory + " has another pilot count or "
                                        "other classes than " + first.directory + ": the seeds of one method share both");
    }
    const int np = first.mask.size();
    for (size_t i = 0; i < bundles.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (bundles[i].training.value("seed", -1) == bundles[j].training.value("seed", -1))
                throw std::invalid_argument("--exp9-classifier-bundles: " + bundles[i].directory + " and " +
                                            bundles[j].directory + " were trained with the same seed (" +
                                            bundles[i].training.value("seed", nlohmann::json("none")).dump() +
                                            "): give one bundle per training seed");
    const scene sc = array_test_scene(first);
    const auto ids = output_classes(first, sc);
    const int n_classes = sc.library().size();
    const uint64_t test_seed = c.seed + 9301;
    const int kmax = *std::max_element(c.exp9_class_elements.begin(), c.exp9_class_elements.end());
    log << "[" << now_utc() << "] experiment 9 (classes): " << bundles.size() << " classifier bundle(s) of "
        << first.directory << "'s mask (N_p " << np << "), " << c.test_frames << " frames per point, ULAs of";
    for (int k : c.exp9_class_elements)
        log << " " << k;
    log << " elements" << std::endl;

    // Unit-variance noise per frame, element and pilot; element k's is the same in every array.
    std::vector<std::vector<gr_complex>> noise(size_t(c.test_frames));
    {
        std::mt19937_64 g(c.seed + 9302);
        std::normal_distribution<float> n(0.0f, std::sqrt(0.5f));
        for (auto& w : noise) {
            w.resize(size_t(kmax) * size_t(np));
            for (auto& x : w)
                x = gr_complex(n(g), n(g));
        }
    }
    // Each bundle's pilots of the same frames (its own mask: a training seed learns its own),
    // drawn for every element count; the first draw is the truth every other must match.
    std::vector<frame_truth> truths;
    std::vector<int> truth_ids;
    auto draw_all = [&](const pilot_mask& mask) {
        std::vector<array_test_frames> arrays;
        for (int k : c.exp9_class_elements) {
            arrays.push_back(draw(fs, sc, array_geometry::ula(k, 0.5 * fs.wavelength_m()), mask, c.test_frames, test_seed));
            if (truths.empty())
                truths = arrays.back().truth;
            for (int f = 0; f < c.test_frames; ++f)
                if (!same_targets(arrays.back().truth[size_t(f)], truths[size_t(f)]))
                    throw std::logic_error("experiment 9 (classes): frame " + std::to_string(f) + " holds another "
                                           "target with " + std::to_string(k) + " elements than the first array's");
        }
        return arrays;
    };
    truth_file truth(c.out_dir + "/exp9_truth.npz", "9");
    kept_predictions kept(predictions_path(c.out_dir, "exp9_classes"), "9", kept_predictions::kind::class_id);
    csv_file csv(c.out_dir + "/exp9_classes.csv", { "scenario", "method", "mask", "elements", "n_pilots", "snr_db",
                                                    "train_seed", "test_seed", "frames", "accuracy", "macro_f1",
                                                    "us_per_frame" });

    for (const auto& b : bundles) {
        const bundle_decoder dec(b, c.threads);
        const double lambda = pilot_wavelength_m(fs, b.mask);
        const auto arrays = draw_all(b.mask);
        if (truth_ids.empty()) {
            for (const auto& t : truths)
                truth_ids.push_back(t.class_id);
            truth.add("kinematic_array", test_seed, truths, class_names(sc));
        }
        const std::optional<uint64_t> train_seed =
            b.training.contains("seed") ? std::optional<uint64_t>(b.training["seed"].get<uint64_t>()) : std::nullopt;
        for (double snr : c.snrs) {
            const float sigma = float(std::pow(10.0, -snr / 20.0));
            auto score_series = [&](const std::string& method, int k, const std::vector<gr_complex>& obs, double us_extra) {
                double us = 0.0;
                const auto pred = classify_all(dec, obs, c.test_frames, ids, us);
                const auto s = score(pred, truth_ids, n_classes);
                kept.add({ "kinematic_array", method, "bundle", np, snr, train_seed, test_seed }, pred, n_classes);
                kept.write();
                csv.row({ "kinematic_array", method, "bundle", std::to_string(k), std::to_string(np), num(snr), train_seed_label(train_seed),
                          std::to_string(test_seed), std::to_string(c.test_frames), num(s.accuracy), num(s.macro_f1),
                          num(us + us_extra, 4) });
                log << "  " << method << " [" << b.directory << "] snr " << snr << ": acc " << num(s.accuracy, 3)
                    << std::endl;
            };
            for (const auto& ap : arrays) {
                const int k = ap.array.n_receive();
                const array_beamformer combiner(ap.array, lambda);
                std::vector<gr_complex> found(size_t(c.test_frames) * np), aimed(found.size()), y(size_t(k) * np);
                const auto t0 = std::chrono::steady_clock::now();
                for (int f = 0; f < c.test_frames; ++f) {
                    const auto& h = ap.y[size_t(f)];
                    const auto& w = noise[size_t(f)];
                    for (size_t i = 0; i < y.size(); ++i)
                        y[i] = h[i] + sigma * w[i];
                    combiner.combine(y.data(), np, found.data() + size_t(f) * np);
                }
                const double us_combine = 1e6 * seconds_between(t0, std::chrono::steady_clock::now()) / c.test_frames;
                score_series(k == 1 ? std::string("1 element") : std::to_string(k) + " elements, beamformed", k, found,
                             us_combine);
                if (k == 1)
                    continue;
                for (int f = 0; f < c.test_frames; ++f) {
                    const auto& h = ap.y[size_t(f)];
                    const auto& w = noise[size_t(f)];
                    for (size_t i = 0; i < y.size(); ++i)
                        y[i] = h[i] + sigma * w[i];
                    beamform_pilots(ap.array, ap.truth[size_t(f)].azimuth_rad, 0.0, lambda, y.data(), np,
                                    aimed.data() + size_t(f) * np);
                }
                score_series(std::to_string(k) + " elements, beamformed at the true azimuth", k, aimed, 0.0);
                // One antenna (the first array's, the single-antenna model) with the noise over k.
                const auto& one = arrays.front();
                if (one.array.n_receive() != 1)
                    continue;
                std::vector<gr_complex> gained(size_t(c.test_frames) * np);
                const float sigma_k = sigma / std::sqrt(float(k));
                for (int f = 0; f < c.test_frames; ++f)
                    for (int i = 0; i < np; ++i)
                        gained[size_t(f) * np + i] = one.y[size_t(f)][size_t(i)] + sigma_k * noise[size_t(f)][size_t(i)];
                score_series("one antenna at +10 log10 " + std::to_string(k) + " dB", k, gained, 0.0);
            }
        }
    }
    log << "[" << now_utc() << "] experiment 9 (classes) done: " << csv.path() << std::endl;
}

} // namespace sems_eval
