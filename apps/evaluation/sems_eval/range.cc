// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 7, range part: a classifier read against range under a stated link
 * budget. The frames come from a scene with a link budget (--exp7-range-scene, required; e.g.
 * models/scenes/kinematic_sdr_budget.json, as docs/RESULTS.md passes it) on the bundle's own
 * frame, the noise at the budget's thermal noise plus --exp7-range-snr; each class's accuracy per range bin goes to exp7_range.csv beside the
 * mean SNR per resource element the radar equation gave its frames there. */
#include "eval.h"
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sems_eval {

namespace {

// Range bins in m: finer where the SNR changes fastest (R⁻⁴).
const std::vector<double> bin_edges_m{ 5, 10, 20, 30, 50, 75, 100, 150, 200 };

int bin_of(double range_m)
{
    if (!(range_m >= bin_edges_m.front() && range_m <= bin_edges_m.back()))
        return -1;
    const int b = static_cast<int>(std::upper_bound(bin_edges_m.begin(), bin_edges_m.end(), range_m) - bin_edges_m.begin()) - 1;
    return std::min(b, static_cast<int>(bin_edges_m.size()) - 2); // the far end belongs to the last bin
}

} // namespace

void run_kinematic_range(const config& c, std::ostream& log)
{
    const std::string who = "sems_eval --exp7-parts range";
    const model_bundle b = model_bundle::load(c.exp7_range_bundle);
    if (b.task != task_kind::classify)
        throw std::invalid_argument(who + ": --exp7-range-bundle " + c.exp7_range_bundle + " is not a classifier");
    const scene sc = scene::load(c.exp7_range_scene);
    if (!sc.budget())
        throw std::invalid_argument(who + ": --exp7-range-scene " + c.exp7_range_scene +
                                    " has no link_budget (its SNR would not follow the range)");
    const auto ids = output_classes(b, sc); // refuses a bundle of another class library
    const frame_settings& fs = b.frame;
    const bundle_decoder dec(b, c.threads);
    const int classes = sc.library().size(), bins = int(bin_edges_m.size()) - 1;
    const int total = c.exp7_range_frames, chunk = 500;
    const uint64_t seed = c.seed + 107;
    log << "[" << now_utc() << "] exp 7 (range): " << total << " frames of " << c.exp7_range_scene << " on "
        << c.exp7_range_bundle << "'s frame, SNR setting " << c.exp7_range_margin_db << " dB, seed " << seed << std::endl;

    // The frames' pilots (the grids are drawn a chunk at a time: only the pilots are kept).
    channel_model cm(fs, sc, seed);
    std::vector<gr_complex> grid(size_t(chunk) * fs.grid_size()), obs;
    std::vector<frame_truth> truth;
    for (int f0 = 0; f0 < total; f0 += chunk) {
        const int n = std::min(chunk, total - f0);
        const auto t = cm.generate(size_t(n), grid.data(), uint64_t(f0));
        cm.add_noise(grid.data(), size_t(n) * fs.grid_size(), c.exp7_range_margin_db);
        const auto pilots = gather(grid, n, fs, b.mask);
        obs.insert(obs.end(), pilots.begin(), pilots.end());
        truth.insert(truth.end(), t.begin(), t.end());
    }
    double us = 0.0;
    const auto predicted = classify_all(dec, obs, total, ids, us);

    std::vector<long> frames(size_t(classes) * bins, 0), correct(size_t(classes) * bins, 0);
    std::vector<double> snr_sum(size_t(classes) * bins, 0.0);
    int outside = 0;
    for (int f = 0; f < total; ++f) {
        const int bin = bin_of(truth[f].range_m);
        if (bin < 0) {
            ++outside;
            continue;
        }
        const size_t at = size_t(truth[f].class_id) * bins + size_t(bin);
        ++frames[at];
        correct[at] += predicted[f] == truth[f].class_id;
        snr_sum[at] += truth[f].link_snr_db + c.exp7_range_margin_db;
    }
    if (outside > 0) // counted, not hidden: a library with ranges beyond the bins
        log << "  " << outside << " frames outside " << bin_edges_m.front() << "-" << bin_edges_m.back()
            << " m are not in the table" << std::endl;
    csv_file csv(c.out_dir + "/exp7_range.csv", { "class", "range_min_m", "range_max_m", "frames", "accuracy",
                                                  "mean_snr_db", "snr_setting_db", "bundle", "scene" });
    for (int k = 0; k < classes; ++k)
        for (int bin = 0; bin < bins; ++bin) {
            const size_t at = size_t(k) * bins + size_t(bin);
            if (frames[at] == 0)
                continue;
            csv.row({ sc.library().at(k).name, num(bin_edges_m[bin]), num(bin_edges_m[bin + 1]), std::to_string(frames[at]),
                      num(double(correct[at]) / frames[at]), num(snr_sum[at] / frames[at], 4), num(c.exp7_range_margin_db),
                      c.exp7_range_bundle, c.exp7_range_scene });
        }
    log << "[" << now_utc() << "] exp 7 (range): wrote " << csv.path() << std::endl;
}

} // namespace sems_eval
