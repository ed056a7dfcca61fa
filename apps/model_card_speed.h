// SPDX-License-Identifier: GPL-3.0-or-later
/* The speed record of a model card (gnuradio/sems/learning/bundles/model_card.h): the sink's
 * decoder timed beside an anchor in the same run. sems_train and sems_eval --model-card both
 * write it, from here. */
#ifndef SEMS_APPS_MODEL_CARD_SPEED_H
#define SEMS_APPS_MODEL_CARD_SPEED_H

#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/learning/array/position_estimator.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/bundles/model_card.h>
#include <gnuradio/sems/learning/sinks/sink_defaults.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <algorithm>
#include <cmath>
#include <ctime>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace apps {

//! The anchor every card's decoder is timed beside: the same work for every bundle, so the
//! ratios compare across cards.
inline std::string card_anchor()
{
    return "frame generator: channel_model drawing frames of the paper preset's default random scene "
           "(pedestrian, car, drone; one path) with noise, one thread";
}

/*!
 * The sink's decoder timed beside the anchor, interleaved, on one thread, in process CPU time:
 * `frames` frames of the bundle's training scene at `snr_db` decoded in the sinks' batches (a
 * track bundle: their evidence, then one track step per frame; a position bundle: its array's
 * pilots, through position_estimator), and as many frames drawn by the
 * anchor (card_anchor()), `repeats` times each; the fastest run of each counts.
 */
inline model_card::speed_record
measure_card_speed(const model_bundle& b, double snr_db, int frames, int repeats, uint64_t seed)
{
    if (frames < 1 || repeats < 1)
        throw std::invalid_argument("model card speed: frames and repeats must be >= 1, got " + std::to_string(frames) +
                                    " and " + std::to_string(repeats));
    // A position bundle's frames are its array's (position.training.scene), the others' one antenna's.
    const bool position = !b.position.is_null();
    const nlohmann::json& record = position ? b.position.value("training", nlohmann::json()) : b.training;
    const std::string where =
        b.directory + "/" + model_bundle::bundle_file + (position ? ": position.training.scene" : ": training.scene");
    if (!record.is_object() || !record.contains("scene") || record.at("scene").is_null())
        throw std::invalid_argument(where + ": missing (the card's frames are drawn from the bundle's training scene)");
    model_card::speed_record s;
    s.threads = 1;
    s.batch = std::min(sink_defaults::batch_size, frames);
    s.snr_db = snr_db;
    s.frames = frames;
    s.repeats = repeats;
    s.anchor = card_anchor();

    // The frames to decode: pilot observations (frames x N_p, mask order; a position bundle's
    // frames x N_r·N_p, element-major).
    std::vector<gr_complex> obs;
    if (position) {
        channel_model cm(b.frame, scene::from_json(record.at("scene"), where), seed);
        std::vector<gr_complex> h(size_t(b.frame.grid_size()));
        for (int f = 0; f < frames; ++f) {
            const auto r = cm.draw(uint64_t(f));
            for (int e = 0; e < cm.n_elements(); ++e) {
                cm.factors(r, uint64_t(f) * uint64_t(b.frame.n_symbols), e).fill(h.data());
                for (int i : b.mask.flat_indices())
                    obs.push_back(h[size_t(i)]);
            }
        }
        cm.add_noise(obs.data(), obs.size(), snr_db);
    } else {
        channel_model cm(b.frame, scene::from_json(record.at("scene"), where), seed);
        const size_t grid = static_cast<size_t>(b.frame.grid_size());
        std::vector<gr_complex> h(size_t(frames) * grid);
        cm.generate(size_t(frames), h.data());
        cm.add_noise(h.data(), h.size(), snr_db);
        for (int f = 0; f < frames; ++f)
            for (int i : b.mask.flat_indices())
                obs.push_back(h[size_t(f) * grid + size_t(i)]);
    }
    std::unique_ptr<bundle_decoder> dec;
    std::unique_ptr<track_classifier> track;
    std::unique_ptr<position_estimator> where_is;
    if (position)
        where_is = std::make_unique<position_estimator>(b, 1);
    else if (track_classifier::is_track_bundle(b))
        track = std::make_unique<track_classifier>(b, 1);
    else
        dec = std::make_unique<bundle_decoder>(b, 1);
    const int np = b.mask.size() * (where_is ? where_is->n_elements() : 1); // observations per frame
    std::vector<float> probs(b.class_names.size() + 1);
    auto decode = [&](int f0, int n) {
        const gr_complex* y = obs.data() + size_t(f0) * np;
        if (where_is) {
            where_is->estimate(y, n);
        } else if (track) { // the sink in track mode: the frames' evidence, then one step per frame
            const auto ev = track->evidence(y, n);
            auto st = track->begin();
            for (int i = 0; i < n; ++i)
                track->step(st, ev.data() + size_t(i) * track->evidence_size(), probs.data());
        } else if (b.task == task_kind::classify) {
            dec->classify(y, n);
        } else {
            dec->estimate_delay(y, n);
        }
    };
    const frame_settings anchor_frame;
    channel_model anchor(anchor_frame, scene::random(random_spec{}), seed);
    std::vector<gr_complex> grids(size_t(frames) * anchor_frame.grid_size());
    uint64_t anchor_first = 0;

    // Process CPU time, not wall time: on a loaded machine the time this process waits for a
    // core would count against whichever of the two was running, and the ratio would be the load's.
    auto cpu_now = [] {
        timespec t;
        ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
        return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
    };
    auto rate = [&](double t0) { return frames / std::max(cpu_now() - t0, 1e-9); };
    decode(0, std::min(frames, s.batch)); // warm-up: first-call allocations are no per-frame cost
    for (int r = 0; r < repeats; ++r) { // interleaved, so a change of load hits both
        double t0 = cpu_now();
        anchor.generate(size_t(frames), grids.data(), anchor_first);
        anchor.add_noise(grids.data(), grids.size(), snr_db);
        anchor_first += uint64_t(frames);
        s.anchor_fps = std::max(s.anchor_fps, rate(t0));
        t0 = cpu_now();
        for (int f0 = 0; f0 < frames; f0 += s.batch)
            decode(f0, std::min(s.batch, frames - f0));
        s.decoder_fps = std::max(s.decoder_fps, rate(t0));
    }
    // Three significant digits: the rates move by more than that from run to run.
    auto sig3 = [](double x) {
        std::ostringstream t;
        t.precision(3);
        t << x;
        return std::stod(t.str());
    };
    s.decoder_fps = sig3(s.decoder_fps);
    s.anchor_fps = sig3(s.anchor_fps);
    return s;
}

} // namespace apps
} // namespace sems
} // namespace gr

#endif
