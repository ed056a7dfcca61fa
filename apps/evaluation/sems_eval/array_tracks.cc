// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 9, tracks part: decisions over a track with 1, 4 and 8 receive elements,
 * as SemS Classifier Sink does it with a track bundle over an array: each frame's N_r·N_p
 * pilots beamformed towards the peak of its beamforming spectrum (array_beamformer.h), the
 * track bundle's frame decoder and temporal network stepping over the track's frames.
 *
 * Test tracks: the track bundle's classes (any heading, one path, Rayleigh
 * gains new every frame), bodies moving straight in the ground plane from an azimuth uniform on
 * [−0.8, 0.8] rad (so they cross the line of sight), exp9_track_frames frames planned (a track
 * ends early at its range or azimuth bound), seen by half-wavelength ULAs of each element count;
 * the same seed draws the same tracks for every count (checked). Each element has its own
 * unit-variance noise, drawn once per frame and scaled per SNR (element k's is the same in every
 * array). A decision after t frames is scored on the tracks that have at least t frames, as in
 * experiment 8.
 * Output: exp9_tracks.csv (method, elements, n_pilots, snr_db, frames: the observation time,
 * tracks, accuracy, macro_f1, test_seed), exp9_tracks_predictions.csv (per method, SNR and
 * observation time every track's decided class id, space-separated in track order; −1 where the
 * track is shorter) and exp9_tracks_truth.csv (each track's class and length) for the paired
 * tests of apps/figures/plot_array_classes.py. */
#include "eval.h"
#include <gnuradio/sems/baselines/array_beamformer.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

namespace sems_eval {

namespace {

// One array's test tracks: per track its frames' K·N_p noiseless pilots (element-major), with
// the first frame's truth.
struct array_tracks {
    array_geometry array;
    std::vector<std::vector<std::vector<gr_complex>>> y; // track, frame, K·N_p
    std::vector<frame_truth> first;
};

array_tracks draw_tracks(const frame_settings& fs, const scene& sc, const array_geometry& a, const pilot_mask& mask,
                         int count, uint64_t seed)
{
    array_tracks out{ a, {}, {} };
    channel_model cm(fs, sc.with_array(a), seed);
    const auto flat = mask.flat_indices();
    std::vector<gr_complex> h(size_t(fs.grid_size()));
    for (int t = 0; t < count; ++t) {
        const int frames = cm.begin_track(uint64_t(t));
        std::vector<std::vector<gr_complex>> track;
        for (int f = 0; f < frames; ++f) {
            const auto r = cm.draw(uint64_t(f));
            if (f == 0)
                out.first.push_back(r.truth);
            track.push_back(array_pilots(cm, r, uint64_t(f) * fs.n_symbols, flat, h));
        }
        out.y.push_back(std::move(track));
    }
    return out;
}

// The observation times scored: 1, 2, 4, ... up to k, and k itself.
std::vector<int> observation_times(int k)
{
    std::vector<int> t;
    for (int n = 1; n < k; n *= 2)
        t.push_back(n);
    t.push_back(k);
    return t;
}

} // namespace

void run_array_tracks(const config& c, std::ostream& log)
{
    if (!c.experiments.count(9) || !c.exp9_parts.count("tracks"))
        return;
    const frame_settings& fs = c.fs;
    const model_bundle bundle = model_bundle::load(c.exp9_track_bundle);
    if (!track_classifier::is_track_bundle(bundle) || bundle.super_frames() != 1)
        throw std::invalid_argument("--exp9-track-bundle: " + bundle.directory +
                                    " is not a track bundle of one frame's mask (sems_train --frame-bundle makes one)");
    const track_classifier tc(bundle, c.threads);
    const pilot_mask& mask = bundle.mask;
    const int np = mask.size();
    track_draw_spec tracks;
    tracks.frames_min = tracks.frames_max = c.exp9_track_frames;
    tracks.motion = track_motion::straight;
    const scene sc = array_test_scene(bundle, tracks);
    const auto ids = output_classes(bundle, sc);
    const int n_classes = sc.library().size();
    const double lambda = pilot_wavelength_m(fs, mask);
    const uint64_t test_seed = c.seed + 9401;
    const int kmax = *std::max_element(c.exp9_class_elements.begin(), c.exp9_class_elements.end());
    const auto times = observation_times(c.exp9_track_frames);
    log << "[" << now_utc() << "] experiment 9 (tracks): " << c.exp9_track_bundle << " over " << c.exp9_track_count
        << " straight tracks of up to " << c.exp9_track_frames << " frames, ULAs of";
    for (int k : c.exp9_class_elements)
        log << " " << k;
    log << " elements" << std::endl;

    std::vector<array_tracks> arrays;
    for (int k : c.exp9_class_elements) {
        arrays.push_back(draw_tracks(fs, sc, array_geometry::ula(k, 0.5 * fs.wavelength_m()), mask, c.exp9_track_count,
                                     test_seed));
        for (int t = 0; t < c.exp9_track_count; ++t) {
            const auto& a = arrays.back().first[size_t(t)];
            const auto& b = arrays.front().first[size_t(t)];
            if (a.class_id != b.class_id || a.azimuth_rad != b.azimuth_rad ||
                arrays.back().y[size_t(t)].size() != arrays.front().y[size_t(t)].size())
                throw std::logic_error("experiment 9 (tracks): track " + std::to_string(t) + " differs with " +
                                       std::to_string(k) + " elements from the first array's");
        }
    }
    const auto& first = arrays.front();
    std::vector<int> truth, length;
    for (int t = 0; t < c.exp9_track_count; ++t) {
        truth.push_back(first.first[size_t(t)].class_id);
        length.push_back(static_cast<int>(first.y[size_t(t)].size()));
    }
    csv_file csv(c.out_dir + "/exp9_tracks.csv",
                 { "method", "elements", "n_pilots", "snr_db", "frames", "tracks", "accuracy", "macro_f1", "test_seed" });
    csv_file predictions(c.out_dir + "/exp9_tracks_predictions.csv", { "method", "elements", "snr_db", "frames", "predicted" });
    {
        csv_file truth_csv(c.out_dir + "/exp9_tracks_truth.csv", { "track", "class_id", "class", "frames" });
        for (int t = 0; t < c.exp9_track_count; ++t)
            truth_csv.row({ std::to_string(t), std::to_string(truth[size_t(t)]), sc.library().at(truth[size_t(t)]).name,
                            std::to_string(length[size_t(t)]) });
    }

    std::vector<float> probs(size_t(tc.n_classes()));
    for (double snr : c.snrs) {
        const float sigma = float(std::pow(10.0, -snr / 20.0));
        for (const auto& ap : arrays) {
            const int k = ap.array.n_receive();
            const std::string method = k == 1 ? std::string("1 element") : std::to_string(k) + " elements, beamformed";
            const array_beamformer combiner(ap.array, lambda);
            std::vector<std::vector<int>> decided(times.size(), std::vector<int>(size_t(c.exp9_track_count), -1));
            for (int t = 0; t < c.exp9_track_count; ++t) {
                const auto& track = ap.y[size_t(t)];
                const int frames = static_cast<int>(track.size());
                // The track's noise: its own generator, element-major per frame, kmax elements.
                std::mt19937_64 g(c.seed + 9402 + uint64_t(t));
                std::normal_distribution<float> n(0.0f, std::sqrt(0.5f));
                std::vector<gr_complex> combined(size_t(frames) * np), y(size_t(k) * np);
                for (int f = 0; f < frames; ++f) {
                    std::vector<gr_complex> w(size_t(kmax) * np);
                    for (auto& x : w)
                        x = gr_complex(n(g), n(g));
                    for (size_t i = 0; i < y.size(); ++i)
                        y[i] = track[size_t(f)][i] + sigma * w[i];
                    combiner.combine(y.data(), np, combined.data() + size_t(f) * np);
                }
                const auto ev = tc.evidence(combined.data(), frames);
                auto st = tc.begin();
                const size_t e = size_t(tc.evidence_size());
                for (int f = 0; f < frames; ++f) {
                    tc.step(st, ev.data() + size_t(f) * e, probs.data());
                    for (size_t j = 0; j < times.size(); ++j)
                        if (times[j] == f + 1)
                            decided[j][size_t(t)] = ids[size_t(std::max_element(probs.begin(), probs.end()) - probs.begin())];
                }
            }
            std::ostringstream line;
            line << "  " << method << " snr " << snr << ":";
            for (size_t j = 0; j < times.size(); ++j) {
                std::vector<int> pred, want;
                std::ostringstream all;
                for (int t = 0; t < c.exp9_track_count; ++t) {
                    all << (t ? " " : "") << decided[j][size_t(t)];
                    if (length[size_t(t)] >= times[j]) {
                        pred.push_back(decided[j][size_t(t)]);
                        want.push_back(truth[size_t(t)]);
                    }
                }
                predictions.row({ method, std::to_string(k), num(snr), std::to_string(times[j]), all.str() });
                if (want.empty())
                    continue;
                const class_score s = score(pred, want, n_classes);
                csv.row({ method, std::to_string(k), std::to_string(np), num(snr), std::to_string(times[j]),
                          std::to_string(want.size()), num(s.accuracy), num(s.macro_f1), std::to_string(test_seed) });
                line << " " << times[j] << ":" << num(s.accuracy, 3);
            }
            log << line.str() << std::endl;
        }
    }
    log << "[" << now_utc() << "] experiment 9 (tracks) done: " << csv.path() << std::endl;
}

} // namespace sems_eval
