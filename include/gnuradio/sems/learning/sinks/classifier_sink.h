// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The classifier_sink block.
 */
#ifndef INCLUDED_SEMS_LEARNING_CLASSIFIER_SINK_H
#define INCLUDED_SEMS_LEARNING_CLASSIFIER_SINK_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/sinks/sink_defaults.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief Classifies the target of each frame with a model bundle.
 *
 * \details Input: gr_complex[N_p] per frame, the pilot observations Y/x_k (x_k the pilot sent) in mask order (from
 * pilot_extractor); from an array, gr_complex[N_r·N_p], element-major (the extractor's N_r
 * inputs). Output: a PMT dict per frame on message port `result`:
 *   frame, label, class_name, probs (f32vector, one per class of the bundle) and, when a
 *   sems_truth tag came with the frame, truth (that dict) and correct (bool; the truth's
 *   class_name, else its class id, compared with the predicted class name).
 * Running metrics (frames, frames_scored, frames_skipped, frames_faulted, accuracy, confusion) are
 * readable through the getters and sent on port `metrics` every `metrics_period` frames
 * and at the end, unless the last of those already carried the final numbers.
 *
 * Track mode (a track bundle: a classifier bundle with a `track` record, trained by
 * `sems_train --frame-bundle`): each frame is decided from every frame of its track so far,
 * one causal step per frame on the track's kept state (track_classifier.h), and its result
 * also holds track_frames (the frames the decision rests on) and the track_id when known.
 * A frame's track is the `track_id` of its sems_truth tag (the channel emulators' tracks; a
 * tracker upstream sets the same key); frames without one form one track. The state starts
 * again at a new track_id, at a frame whose index does not follow the track's last one (frames
 * lost, skipped as non-finite, or out of order: counted in track_gaps), and after
 * `track_idle_s` seconds without a frame (counted too); one track is followed at a time, so two
 * tracks are never mixed. The metrics add tracks_started, track_gaps and track_idle_resets.
 *
 * Super-frames: a bundle whose mask spans F frames (pilots across frames) reads the frame of
 * index i at set i mod F, the set the pilot mapper and extractor used for it; `super_frames`
 * states the F of the stream, and a bundle of another F is refused naming both.
 *
 * Arrays: given the array its streams come from (`array`, N_r = `n_elements` receive elements,
 * one transmit element), each frame's N_r·N_p pilots are beamformed into one antenna's N_p
 * towards the azimuth where the frame's beamforming spectrum peaks (array_beamformer.h: one
 * antenna's pilots at N_r times the SNR for a plane wave), and the bundle, trained on one
 * antenna, reads those; the result also holds azimuth_rad, the direction beamformed towards.
 *
 * Frames are decoded `batch_size` at a time; the partial last batch is decoded in stop().
 * Note (GNU Radio): messages sent in stop() only reach subscribers whose thread is still
 * running; read the getters after wait() for the final numbers.
 */
class SEMS_LEARNING_API classifier_sink : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<classifier_sink> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes a classifier sink.
     * \param bundle_dir     model bundle directory (bundle.json, mask.json, decoder.pt), task `classify`
     * \param n_pilots       N_p, the pilots per element (the input vector is n_elements·N_p); must match the bundle's mask
     * \param batch_size     frames per inference call (>= 1)
     * \param threads        LibTorch intra-op threads (0: leave LibTorch's setting)
     * \param metrics_period send metrics every K frames (0: only at the end of the stream)
     * \param n_symbols      N of the stream's frames; must match the bundle
     * \param n_subcarriers  M of the stream's frames; must match the bundle
     * \param frame          the stream's frame: a preset's name (e.g. `sdr_2g4_20mhz`) or a frame
     *                       file (`"format": "sems.frame"`); its N and M must equal n_symbols and
     *                       n_subcarriers. Empty: the paper's frame with n_symbols x n_subcarriers.
     *                       The bundle's frame must equal it in every field (N, M, B, f_c, T, CP, guards).
     * \param track_idle_s   track mode: seconds of wall time without a frame after which the next
     *                       frame starts its track again (0: no limit; >= 0)
     * \param super_frames   F of the stream's pilot mask (the frames of its super-frame, 1 for one
     *                       frame's mask); must match the bundle's mask
     * \param n_elements     N_r, the receive elements whose pilots each item holds (1: one antenna)
     * \param array          with N_r > 1, the array the streams come from: a preset's name (e.g.
     *                       `ula8_3g`), an array file, or its JSON text (array_setting.h); its
     *                       receive elements must number n_elements, with one transmit element.
     *                       Empty: one antenna (n_elements must be 1).
     * \return the block.
     * \throws std::invalid_argument naming the bundle and the mismatch.
     */
    static sptr make(const std::string& bundle_dir,
                     int n_pilots,
                     int batch_size = sink_defaults::batch_size,
                     int threads = sink_defaults::threads,
                     int metrics_period = sink_defaults::metrics_period,
                     int n_symbols = frame_settings().n_symbols,
                     int n_subcarriers = frame_settings().n_subcarriers,
                     const std::string& frame = "",
                     double track_idle_s = 0.0,
                     int super_frames = 1,
                     int n_elements = 1,
                     const std::string& array = "");

    /*! \brief Frames handled: answered or skipped. \return the count. */
    virtual uint64_t frames() const = 0;
    /*! \brief Frames answered with a truth to compare. \return the count. */
    virtual uint64_t frames_scored() const = 0;
    /*! \brief Non-finite or faulted frames, never answered. \return the count. */
    virtual uint64_t frames_skipped() const = 0;
    /*!
     * \brief Frames skipped because decoding or the bookkeeping failed (an exception in
     *        work(), logged once per kind); the stream goes on.
     * \return the count; frames() = answered + frames_skipped().
     */
    virtual uint64_t frames_faulted() const = 0;
    /*! \brief Fraction of scored frames classified correctly. \return the accuracy; NaN before the first scored frame. */
    virtual double accuracy() const = 0;
    /*!
     * \brief The confusion matrix over the bundle's classes (truths of other classes are
     *        scored as wrong but have no row).
     * \return confusion[truth][predicted].
     */
    virtual std::vector<std::vector<uint64_t>> confusion() const = 0;
    /*! \brief The bundle's classes. \return the class names, indexed by label. */
    virtual std::vector<std::string> class_names() const = 0;
    /*! \brief Restarts the running metrics (counters and sums) from zero. */
    virtual void reset_metrics() = 0;
    /*! \brief Whether the bundle decides over tracks. \return true for a track bundle. */
    virtual bool track_mode() const = 0;
    /*! \brief Track mode: tracks begun (first frame, new track_id, gap or idle time). \return the count. */
    virtual uint64_t tracks_started() const = 0;
    /*! \brief Track mode: tracks begun again because frames were missing or out of order. \return the count. */
    virtual uint64_t track_gaps() const = 0;

    /*! \brief N_r, the receive elements of each item. \return the count (1: one antenna). */
    virtual int n_elements() const = 0;

    /*! \brief Frames per inference call. \return the batch size. */
    virtual int batch_size() const = 0;
    /*! \brief Frames between `metrics` messages. \return K (0: only at the end of the stream). */
    virtual int metrics_period() const = 0;
    /*!
     * \brief Sets the frames between `metrics` messages.
     * \param k K (>= 0; 0: only at the end of the stream).
     * \throws std::invalid_argument if k < 0.
     */
    virtual void set_metrics_period(int k) = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_CLASSIFIER_SINK_H */
