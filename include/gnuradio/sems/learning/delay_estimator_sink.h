// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: delay_estimator_sink — estimates the delay of the target of interest of each
 * frame with a model bundle.
 *
 * Input: gr_complex[N_p] per frame, the pilot observations Y/s_p in mask order (from
 * pilot_extractor). Output: a PMT dict per frame on message port `result`:
 *   frame, delay_s, delay_index (τ·B) and range_m (cτ/2) and, when a sems_truth tag came
 *   with the frame, truth (that dict) and abs_error_index (|estimate − truth| in delay
 *   indices; the truth's delay_index, else its delay_s·B).
 * Running metrics (frames, frames_scored, frames_skipped, mae_index, mae_m) are readable
 * through the getters and sent on port `metrics` every `metrics_period` frames and once
 * when the stream ends.
 *
 * Frames are decoded `batch_size` at a time; the partial last batch is decoded in stop().
 * Note (GNU Radio): messages sent in stop() only reach subscribers whose thread is still
 * running; read the getters after wait() for the final numbers.
 */
#ifndef INCLUDED_SEMS_DELAY_ESTIMATOR_SINK_H
#define INCLUDED_SEMS_DELAY_ESTIMATOR_SINK_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/sink_defaults.h>
#include <gnuradio/sems/core/frame_settings.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <string>

namespace gr {
namespace sems {

class SEMS_LEARNING_API delay_estimator_sink : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<delay_estimator_sink> sptr;

    /*!
     * \param bundle_dir     model bundle directory (bundle.json, mask.json, decoder.pt), task `delay`
     * \param n_pilots       N_p, the input vector length; must match the bundle's mask
     * \param batch_size     frames per inference call (>= 1)
     * \param threads        LibTorch intra-op threads (0: leave LibTorch's setting)
     * \param metrics_period send metrics every K frames (0: only at the end of the stream)
     * \param n_symbols      N of the stream's frames; must match the bundle
     * \param n_subcarriers  M of the stream's frames; must match the bundle
     * Throws std::invalid_argument naming the bundle and the mismatch.
     */
    static sptr make(const std::string& bundle_dir,
                     int n_pilots,
                     int batch_size = sink_defaults::batch_size,
                     int threads = sink_defaults::threads,
                     int metrics_period = sink_defaults::metrics_period,
                     int n_symbols = frame_settings().n_symbols,
                     int n_subcarriers = frame_settings().n_subcarriers);

    virtual uint64_t frames() const = 0;         // handled: answered or skipped
    virtual uint64_t frames_scored() const = 0;  // answered with a truth to compare
    virtual uint64_t frames_skipped() const = 0; // non-finite or faulted, never answered
    // Skipped because decoding or the bookkeeping failed (an exception in work(), logged
    // once per kind); the stream goes on. frames() = answered + frames_skipped().
    virtual uint64_t frames_faulted() const = 0;
    virtual double mae_index() const = 0;        // mean |error| in delay indices; NaN before the first scored frame
    virtual double mae_m() const = 0;            // the same in metres of range
    virtual void reset_metrics() = 0;

    virtual int batch_size() const = 0;
    virtual int metrics_period() const = 0;
    virtual void set_metrics_period(int k) = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_DELAY_ESTIMATOR_SINK_H */
