// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval --model-card DIR: measures a bundle's figures on a fixed test set and writes its
 * model card (gnuradio/sems/learning/bundles/model_card.h) beside bundle.json.
 *
 * Per-frame bundles: frames 0 .. n - 1 of the bundle's training scene on its frame, drawn by
 * channel_model with seed S (a delay bundle: S + 1) and noised row by row as the target_channel
 * block does, each pilot divided by its transmitted symbol as pilot_extractor does, decoded in
 * the sinks' batches: with S = 1 these are the frames scripts/demo.sh streams through
 * examples/sems_demo.grc (its classifier channel has seed 1, its delay channel seed 2), so the
 * demo's table and the cards of the bundles it runs give the same figures. A bundle trained for
 * a radio (bundle.json's training.radio) is scored through that radio (front_end_frame).
 * Track bundles: tracks 0 .. n - 1 of the track's training scene, seed S, each decided frame by
 * frame as the classifier sink does in track mode: accuracy after the first frame and after
 * the whole track.
 * Position bundles: frames 0 .. n - 1 of the position record's scene (with its array), seed
 * S + 3, each element's pilots noised as the pilot extractor reads them, decoded by
 * position_estimator in the sinks' batches: the delay's errors as a delay bundle's and the
 * azimuth's RMSE beside its Cramér–Rao bound (when every test frame's target is one path). */
#include "eval.h"
#include "model_card_speed.h"
#include <gnuradio/sems/core/radio/front_end_frame.h>
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/learning/array/position_estimator.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/bundles/model_card.h>
#include <gnuradio/sems/learning/sinks/sink_defaults.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace sems_eval {

namespace {

constexpr int batch = sink_defaults::batch_size;

// A card scores fresh frames only on another seed than its training's: every trainer draws
// frames (tracks) 0, 1, ... of the same scene from its seed, as the card does from its own, so
// the same seed would score the first training frames again (with other noise).
void check_fresh_seed(uint64_t card, const nlohmann::json& training, const std::string& where)
{
    const auto* seed = training.is_object() && training.contains("seed") ? &training.at("seed") : nullptr;
    if (seed && seed->is_number_unsigned() && seed->get<uint64_t>() == card)
        throw std::invalid_argument(where + ": its training drew frames 0, 1, ... of this scene with seed " +
                                    std::to_string(card) + ", the seed --card-seed gives the card here: the card "
                                    "would score training frames; give another --card-seed");
}

std::string snr_list(const std::vector<double>& snrs)
{
    std::ostringstream s;
    for (size_t i = 0; i < snrs.size(); ++i)
        s << (i ? ", " : "") << snrs[i];
    return s.str();
}

// Per-frame figures: the frames the demo's flowgraph streams, at every SNR.
void measure_frames(const config& c, const model_bundle& b, model_card::test_record& test)
{
    const std::string where = b.directory + "/bundle.json";
    const scene sc = scene::from_json(b.training.at("scene"), where + ": training.scene");
    const uint64_t seed = c.card_seed + (b.task == task_kind::delay ? 1 : 0);
    check_fresh_seed(seed, b.training, where + ": training.seed");
    std::optional<front_end_settings> radio;
    if (b.training.contains("radio") && !b.training.at("radio").is_null()) {
        radio = front_end_settings::from_json(b.training.at("radio"), where + ": training.radio");
        test.radio = b.training.value("radio_source", std::string("bundle.json's training.radio"));
    }
    const int n = b.frame.n_symbols, m = b.frame.n_subcarriers, np = b.mask.size(), count = c.card_frames;
    const size_t grid = size_t(b.frame.grid_size());
    const auto idx = b.mask.flat_indices(); // mask order: sorted by (symbol, subcarrier)
    bundle_decoder dec(b, 1);
    test.seed = seed;
    test.scene = "the bundle's training scene (bundle.json training.scene: " +
                 b.training.value("scene_source", std::string("recorded")) + ")";
    std::ostringstream how;
    how << "frames 0.." << count - 1 << " of channel_model on the bundle's frame and scene, seed " << seed;
    if (radio)
        how << ", through the radio front end (front_end_frame, seed " << seed << " + frame index)";
    else
        how << ", channel and noise applied symbol by symbol as the target_channel block does, pilots divided by "
               "their transmitted symbols as pilot_extractor does (the frames scripts/demo.sh streams)";
    how << "; decoded in batches of " << batch << " on one thread";
    test.frames = how.str();

    for (double snr : c.card_snrs) {
        channel_model cm(b.frame, sc, seed); // a new channel per SNR, as a new flowgraph run
        std::optional<front_end_frame> fe;
        if (radio)
            fe.emplace(b.frame, *radio);
        frame_realization r;
        std::vector<gr_complex> x(static_cast<size_t>(m), gr_complex(0.0f, 0.0f)), y(static_cast<size_t>(m)), h, out;
        if (radio) {
            h.resize(grid);
            out.resize(grid);
        }
        std::vector<gr_complex> obs(static_cast<size_t>(count) * np);
        std::vector<frame_truth> truth(static_cast<size_t>(count));
        for (int f = 0; f < count; ++f) {
            cm.draw(uint64_t(f), r);
            truth[f] = r.truth;
            const auto ch = cm.factors(r, uint64_t(f) * uint64_t(n));
            gr_complex* o = obs.data() + size_t(f) * np;
            if (radio) {
                ch.fill(h.data());
                fe->observe(h.data(), r.truth.delay_index, channel_model::noise_variance(snr), seed + uint64_t(f),
                            out.data());
                for (int k = 0; k < np; ++k)
                    o[k] = out[size_t(idx[k])];
                continue;
            }
            int k = 0;
            for (int row = 0; row < n; ++row) {
                const int first = k;
                for (; k < np && idx[k] / m == row; ++k)
                    x[size_t(idx[k] % m)] = b.mask.transmitted_pilot(k);
                ch.apply_row(row, x.data(), y.data());
                cm.add_noise(y.data(), size_t(m), snr);
                for (int j = first; j < k; ++j) {
                    o[j] = y[size_t(idx[j] % m)] / b.mask.transmitted_pilot(j);
                    x[size_t(idx[j] % m)] = gr_complex(0.0f, 0.0f);
                }
            }
        }
        model_card::snr_figures fig;
        fig.snr_db = snr;
        fig.frames = count;
        if (b.task == task_kind::classify) {
            const int nc = int(b.class_names.size());
            int correct = 0;
            for (int f0 = 0; f0 < count; f0 += batch) {
                const int nb = std::min(batch, count - f0);
                const auto p = dec.classify(obs.data() + size_t(f0) * np, nb);
                for (int i = 0; i < nb; ++i) {
                    const float* row = p.data() + size_t(i) * nc;
                    correct += b.class_names[std::max_element(row, row + nc) - row] == truth[f0 + i].class_name;
                }
            }
            fig.accuracy = double(correct) / count;
        } else {
            std::vector<double> err;
            for (int f0 = 0; f0 < count; f0 += batch) {
                const int nb = std::min(batch, count - f0);
                const auto d = dec.estimate_delay(obs.data() + size_t(f0) * np, nb);
                for (int i = 0; i < nb; ++i) // as the delay sink scores: its index from the delay in s
                    err.push_back(std::abs(b.frame.delay_index(d[i]) - truth[f0 + i].delay_index));
            }
            double sum = 0.0;
            for (double e : err)
                sum += e;
            fig.mae_index = sum / count;
            fig.mae_m = *fig.mae_index * b.frame.range_per_delay_index_m();
            std::nth_element(err.begin(), err.begin() + count / 2, err.end());
            double median = err[count / 2];
            if (count % 2 == 0)
                median = 0.5 * (median + *std::max_element(err.begin(), err.begin() + count / 2));
            fig.median_abs_error_index = median;
        }
        test.by_snr.push_back(fig);
    }
}

// Position figures: delay and azimuth of the frames of the position record's scene.
void measure_positions(const config& c, const model_bundle& b, model_card::test_record& test)
{
    const std::string where = b.directory + "/bundle.json: position.training.scene";
    const auto& record = b.position.at("training");
    const scene sc = scene::from_json(record.at("scene"), where);
    const uint64_t seed = c.card_seed + 3;
    check_fresh_seed(seed, record, b.directory + "/bundle.json: position.training.seed");
    const position_estimator pos(b, 1);
    const int k = pos.n_elements(), np = pos.n_pilots(), count = c.card_frames;
    const double lambda = pilot_wavelength_m(b.frame, b.mask);
    const auto idx = b.mask.flat_indices();
    test.seed = seed;
    test.scene = "the position bundle's training scene (bundle.json position.training.scene: " +
                 record.value("scene_source", std::string("recorded")) + ")";
    std::ostringstream how;
    how << "frames 0.." << count - 1 << " of channel_model on the bundle's frame, scene and array, seed " << seed
        << ", noise CN(0, sigma^2) per pilot and element; decoded in batches of " << batch << " on one thread";
    test.frames = how.str();
    std::vector<gr_complex> clean(size_t(count) * k * np), h(size_t(b.frame.grid_size()));
    std::vector<frame_realization> frames;
    {
        channel_model cm(b.frame, sc, seed);
        for (int f = 0; f < count; ++f) {
            frames.push_back(cm.draw(uint64_t(f)));
            for (int e = 0; e < k; ++e) {
                cm.factors(frames.back(), uint64_t(f) * uint64_t(b.frame.n_symbols), e).fill(h.data());
                for (int i = 0; i < np; ++i)
                    clean[(size_t(f) * k + size_t(e)) * np + size_t(i)] = h[size_t(idx[size_t(i)])];
            }
        }
    }
    for (double snr : c.card_snrs) {
        channel_model noise(b.frame, sc, seed); // a new generator per SNR, as a new flowgraph run
        auto obs = clean;
        noise.add_noise(obs.data(), obs.size(), snr);
        std::vector<double> err, az_err;
        for (int f0 = 0; f0 < count; f0 += batch) {
            const int nb = std::min(batch, count - f0);
            const auto e = pos.estimate(obs.data() + size_t(f0) * k * np, nb);
            for (int i = 0; i < nb; ++i) {
                const auto& t = frames[size_t(f0 + i)].truth;
                err.push_back(std::abs(e[size_t(i)].delay_index - t.delay_index));
                az_err.push_back(e[size_t(i)].azimuth_rad - t.azimuth_rad);
            }
        }
        model_card::snr_figures fig;
        fig.snr_db = snr;
        fig.frames = count;
        double sum = 0.0, sq = 0.0, crb = 0.0;
        bool bounded = true;
        for (int f = 0; f < count; ++f) {
            sum += err[size_t(f)];
            sq += az_err[size_t(f)] * az_err[size_t(f)];
            const auto& r = frames[size_t(f)];
            bounded = bounded && r.paths.size() == 1;
            if (bounded)
                crb += angle_crb_rad2(pos.array(), r.truth.azimuth_rad, 0.0, lambda,
                                      np * std::norm(r.paths[0].gain) / channel_model::noise_variance(snr));
        }
        fig.mae_index = sum / count;
        fig.mae_m = *fig.mae_index * b.frame.range_per_delay_index_m();
        std::nth_element(err.begin(), err.begin() + count / 2, err.end());
        fig.median_abs_error_index = err[size_t(count / 2)];
        fig.rmse_azimuth_rad = std::sqrt(sq / count);
        if (bounded)
            fig.crb_azimuth_rad = std::sqrt(crb / count);
        test.by_snr.push_back(fig);
    }
}

// Track figures: the track decision after the first frame and after the whole track.
void measure_tracks(const config& c, const model_bundle& b, model_card::test_record& test)
{
    const std::string where = b.directory + "/bundle.json";
    const auto& tt = b.track.at("training");
    const scene tsc = scene::from_json(tt.at("scene"), where + ": track.training.scene");
    check_fresh_seed(c.card_seed, tt, where + ": track.training.seed");
    const int K = c.card_track_frames > 0 ? c.card_track_frames : tt.at("track_frames").get<int>();
    const int np = b.mask.size(), tracks = c.card_tracks;
    const size_t grid = size_t(b.frame.grid_size());
    const auto idx = b.mask.flat_indices();
    track_classifier tc(b, 1);
    test.seed = c.card_seed;
    test.track_frames = K;
    test.scene = "the track's training scene (bundle.json track.training.scene: " +
                 tt.value("scene_source", std::string("recorded")) + ")";

    // Each track's pilots, noiseless, and unit-variance noise at them (the same at every SNR).
    channel_model cm(b.frame, tsc, c.card_seed);
    frame_realization r;
    std::vector<gr_complex> h(grid), hp, w;
    std::vector<std::string> label;
    int cut = 0;
    for (int i = 0; i < tracks; ++i) {
        const int len = cm.begin_track(uint64_t(i));
        if (len < K) { // cut short at the scene's range bounds: scored after K frames, so left out
            ++cut;
            continue;
        }
        for (int f = 0; f < K; ++f) {
            cm.draw(uint64_t(f), r);
            if (f == 0)
                label.push_back(r.truth.class_name);
            cm.factors(r, 0).fill(h.data()); // the track's own clock
            for (int k = 0; k < np; ++k)
                hp.push_back(h[size_t(idx[k])]);
        }
    }
    const int scored = int(label.size());
    if (scored == 0)
        throw std::invalid_argument(where + ": none of " + std::to_string(tracks) + " test tracks lasts " +
                                    std::to_string(K) + " frames");
    w.assign(hp.size(), gr_complex(0.0f, 0.0f));
    cm.add_noise(w.data(), w.size(), 0.0); // CN(0, 1) from the model's own noise generator
    std::ostringstream how;
    how << "tracks 0.." << tracks - 1 << " of channel_model on the bundle's frame and the track scene, seed "
        << c.card_seed << " (" << scored << " last " << K << " frames and are scored; " << cut
        << " ended sooner), noise drawn once and scaled to each SNR; each track decided frame by frame as the "
           "classifier sink does in track mode, on one thread";
    test.frames = how.str();

    const int e = tc.evidence_size(), nc = tc.n_classes();
    std::vector<float> p(static_cast<size_t>(nc));
    std::vector<gr_complex> obs(static_cast<size_t>(K) * np);
    for (double snr : c.card_snrs) {
        const double sigma = std::sqrt(channel_model::noise_variance(snr));
        int first = 0, last = 0;
        for (int i = 0; i < scored; ++i) {
            const size_t at = size_t(i) * K * np;
            for (size_t j = 0; j < obs.size(); ++j)
                obs[j] = hp[at + j] + float(sigma * b.mask.noise_scale(int(j % np))) * w[at + j];
            const auto ev = tc.evidence(obs.data(), K);
            auto st = tc.begin();
            for (int f = 0; f < K; ++f) {
                tc.step(st, ev.data() + size_t(f) * e, p.data());
                const auto best = std::max_element(p.begin(), p.end()) - p.begin();
                const bool right = b.class_names[best] == label[i];
                if (f == 0)
                    first += right;
                if (f == K - 1)
                    last += right;
            }
        }
        model_card::snr_figures fig;
        fig.snr_db = snr;
        fig.frames = scored;
        fig.first_frame_accuracy = double(first) / scored;
        fig.accuracy = double(last) / scored;
        test.by_snr.push_back(fig);
    }
}

} // namespace

void run_model_cards(const config& c, std::ostream& log)
{
    for (const auto& name : c.model_cards) {
        const auto b = model_bundle::load(name);
        auto card = model_card::of_bundle(b);
        // What people wrote on the card (its summary, the SNR to cite) stays when it is measured again.
        const std::string file = b.directory + "/" + model_card::card_file;
        if (std::filesystem::exists(file)) {
            try {
                const auto old = model_card::load(file);
                card.summary = old.summary;
                card.cite_snr_db = old.cite_snr_db;
            } catch (const std::invalid_argument& e) {
                log << "sems_eval --model-card: " << e.what() << "; the card is written anew" << std::endl;
            }
        }
        if (!c.card_summary.empty())
            card.summary = c.card_summary;
        if (std::isfinite(c.card_cite_snr_db))
            card.cite_snr_db = c.card_cite_snr_db;
        if (std::find(c.card_snrs.begin(), c.card_snrs.end(), card.cite_snr_db) == c.card_snrs.end())
            throw std::invalid_argument("--model-card " + name + ": the SNR to cite (" + num(card.cite_snr_db) +
                                        " dB) is not one of --card-snrs (" + snr_list(c.card_snrs) + ")");
        card.test = model_card::test_record{};
        card.test.measured_by = "sems_eval --model-card";
        card.test.command = c.command_line;
        const auto t0 = std::chrono::steady_clock::now();
        if (track_classifier::is_track_bundle(b))
            measure_tracks(c, b, card.test);
        else if (!b.position.is_null())
            measure_positions(c, b, card.test);
        else
            measure_frames(c, b, card.test);
        const auto t1 = std::chrono::steady_clock::now();
        card.speed = apps::measure_card_speed(b, card.cite_snr_db, c.card_speed_frames, c.card_speed_repeats,
                                               c.card_seed + 2);
        card.save(b.directory);
        const auto& cited = card.cited();
        log << "[" << now_utc() << "] " << file << ": ";
        if (cited.rmse_azimuth_rad)
            log << "azimuth RMSE " << num(1e3 * *cited.rmse_azimuth_rad, 4) << " mrad, ";
        if (cited.mae_index)
            log << "delay MAE " << num(*cited.mae_index, 4) << " index (" << num(*cited.mae_m, 3) << " m)";
        else
            log << "accuracy " << num(100.0 * *cited.accuracy, 4) << " %"
                << (cited.first_frame_accuracy ? " (first frame " + num(100.0 * *cited.first_frame_accuracy, 4) + " %)" : "");
        log << " at " << num(card.cite_snr_db) << " dB on " << cited.frames << (card.test.track_frames ? " tracks" : " frames")
            << "; decoder " << num(card.speed.decoder_fps, 4) << " frames/s = " << num(card.speed.ratio(), 3)
            << " x the anchor; figures in " << num(seconds_between(t0, t1), 3) << " s" << std::endl;
    }
}

} // namespace sems_eval
