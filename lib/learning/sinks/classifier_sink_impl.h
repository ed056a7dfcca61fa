// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: classifier_sink implementation — a thin adapter: sink_core does the
 * stream bookkeeping, classifier_task the decoding and the scoring. */
#ifndef INCLUDED_SEMS_LIB_LEARNING_CLASSIFIER_SINK_IMPL_H
#define INCLUDED_SEMS_LIB_LEARNING_CLASSIFIER_SINK_IMPL_H

#include "learning/sinks/sink_block.h"
#include "learning/sinks/sink_core.h"
#include <gnuradio/sems/baselines/array_beamformer.h>
#include <gnuradio/sems/learning/sinks/classifier_sink.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <atomic>
#include <chrono>
#include <map>
#include <string>

namespace gr {
namespace sems {

// Classification: argmax of the class probabilities; accuracy and confusion matrix. With a
// track bundle, the decision over the frame's track so far (track mode, classifier_sink.h).
class classifier_task : public detail::sink_task
{
public:
    // track_idle_s: track mode, the wall time after which a track's next frame starts it
    // again (0: never). n_elements, array: the streams of an item and the array they come
    // from (classifier_sink::make); with an array each frame is beamformed into one antenna's.
    classifier_task(std::unique_ptr<bundle_decoder> decoder, double track_idle_s, int n_elements,
                    const std::string& array);
    int elements() const override { return d_elements; }

    std::vector<pmt::pmt_t> decode(const gr_complex* obs, int batch, const std::vector<detail::frame_meta>& meta) override;
    bool score(pmt::pmt_t& result, const pmt::pmt_t& truth) override;
    pmt::pmt_t add_metrics(pmt::pmt_t dict) const override;
    void reset_metrics() override;

    double accuracy() const;
    const std::vector<std::vector<uint64_t>>& confusion() const { return d_confusion; }
    const std::vector<std::string>& class_names() const { return d_names; }
    // Refuses a truth whose `class_library` differs from the bundle's: throws
    // std::runtime_error naming both libraries and the difference. Each library name is
    // looked up (class_library::find) and compared once. A truth without the key passes.
    void check_library(const pmt::pmt_t& truth);

    bool track_mode() const { return static_cast<bool>(d_track); }
    int super_frames() const { return bundle().super_frames(); }
    uint64_t tracks_started() const { return d_tracks_started; }
    uint64_t track_gaps() const { return d_track_gaps; }
    uint64_t track_idle_resets() const { return d_track_idle; }

private:
    int class_of_truth(const pmt::pmt_t& truth) const; // -1: not one of the bundle's, -2: no class in truth
    const model_bundle& bundle() const { return d_track ? d_track->bundle() : d_decoder->bundle(); }
    std::vector<int> sets_of(const std::vector<detail::frame_meta>& meta, int batch) const;
    std::vector<pmt::pmt_t> decode_tracks(const gr_complex* obs, int batch, const std::vector<detail::frame_meta>& meta);
    pmt::pmt_t answer(const float* probs) const; // label, class_name, probs
    // With an array: each frame's N_r·N_p pilots beamformed into d_beamformed (batch x N_p),
    // their azimuths into d_azimuths; returns what the decoder reads (obs itself without one).
    const gr_complex* combine(const gr_complex* obs, int batch);
    std::vector<pmt::pmt_t> with_azimuths(std::vector<pmt::pmt_t> answers) const;

    std::unique_ptr<bundle_decoder> d_decoder; // per-frame bundles
    std::unique_ptr<track_classifier> d_track; // track bundles
    int d_elements = 1;
    std::unique_ptr<array_beamformer> d_beamformer; // with an array (n_elements > 1)
    std::vector<gr_complex> d_beamformed;
    std::vector<double> d_azimuths;
    const pmt::pmt_t d_azimuth_key;
    // Track mode: the one track followed, and why tracks started.
    track_classifier::state d_state;
    bool d_in_track = false;
    bool d_track_known = false;   // the track's frames carry a track_id
    uint64_t d_track_id = 0;
    uint64_t d_last_index = 0;    // the track's last frame
    std::chrono::steady_clock::time_point d_last_seen; // the track's last frame's arrival
    double d_idle_s = 0.0;
    // Written in decode() (block thread, without the core's lock), read by the getters.
    std::atomic<uint64_t> d_tracks_started{ 0 }, d_track_gaps{ 0 }, d_track_idle{ 0 };
    std::vector<float> d_probs;
    std::vector<std::string> d_names;
    // Interned once (interning hashes and locks): the answer's keys and each class's name.
    const pmt::pmt_t d_label_key, d_class_name_key, d_probs_key, d_track_frames_key, d_track_id_key;
    std::vector<pmt::pmt_t> d_name_symbols;
    uint64_t d_scored = 0;
    uint64_t d_correct = 0;
    std::vector<std::vector<uint64_t>> d_confusion;
    const pmt::pmt_t d_library_key;
    pmt::pmt_t d_accepted_library;               // the last library name that matched (a symbol)
    std::map<std::string, std::string> d_refusals; // library name -> why it is refused
};

class classifier_sink_impl : public detail::sink_block<classifier_sink, classifier_task>
{
public:
    classifier_sink_impl(const std::string& bundle_dir,
                         int n_pilots,
                         int batch_size,
                         int threads,
                         int metrics_period,
                         int n_symbols,
                         int n_subcarriers,
                         const std::string& frame,
                         double track_idle_s,
                         int super_frames,
                         int n_elements,
                         const std::string& array);
    int n_elements() const override { return d_task.elements(); }

    double accuracy() const override;
    std::vector<std::vector<uint64_t>> confusion() const override;
    std::vector<std::string> class_names() const override { return d_task.class_names(); }
    bool track_mode() const override { return d_task.track_mode(); }
    uint64_t tracks_started() const override;
    uint64_t track_gaps() const override;

    // Checks the class library of every truth tag before the frames go to the core: a
    // library other than the bundle's is a wrong flowgraph, not a bad frame. The refusal
    // is logged and ends the stream (WORK_DONE; an exception escaping work() would stop
    // this block's thread and hang the flowgraph).
    int work(int noutput_items, gr_vector_const_void_star& input_items, gr_vector_void_star& output_items) override;

private:
    std::vector<gr::tag_t> d_truth_tags;
    bool d_refused = false;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_CLASSIFIER_SINK_IMPL_H */
