// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The delay_estimator_sink block.
 */
#ifndef INCLUDED_SEMS_LEARNING_DELAY_ESTIMATOR_SINK_H
#define INCLUDED_SEMS_LEARNING_DELAY_ESTIMATOR_SINK_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/sinks/sink_defaults.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <string>

namespace gr {
namespace sems {

/*!
 * \brief Estimates the delay of the target of interest of each
 * frame with a model bundle.
 *
 * \details Input: gr_complex[N_p] per frame, the pilot observations Y/x_k (x_k the pilot sent) in mask order (from
 * pilot_extractor). Output: a PMT dict per frame on message port `result`:
 *   frame, delay_s, delay_index (τ·B) and range_m (cτ/2) and, when a sems_truth tag came
 *   with the frame, truth (that dict) and abs_error_index (|estimate − truth| in delay
 *   indices; the truth's delay_index, else its delay_s·B).
 * Running metrics (frames, frames_scored, frames_skipped, frames_faulted, mae_index, mae_m) are readable
 * through the getters and sent on port `metrics` every `metrics_period` frames and at the
 * end, unless the last of those already carried the final numbers.
 *
 * Frames are decoded `batch_size` at a time; the partial last batch is decoded in stop().
 * Note (GNU Radio): messages sent in stop() only reach subscribers whose thread is still
 * running; read the getters after wait() for the final numbers.
 */
class SEMS_LEARNING_API delay_estimator_sink : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<delay_estimator_sink> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes a delay estimator sink.
     * \param bundle_dir     model bundle directory (bundle.json, mask.json, decoder.pt), task `delay`
     * \param n_pilots       N_p, the input vector length; must match the bundle's mask
     * \param batch_size     frames per inference call (>= 1)
     * \param threads        LibTorch intra-op threads (0: leave LibTorch's setting)
     * \param metrics_period send metrics every K frames (0: only at the end of the stream)
     * \param n_symbols      N of the stream's frames; must match the bundle
     * \param n_subcarriers  M of the stream's frames; must match the bundle
     * \param frame          the stream's frame: a preset's name (e.g. `sdr_2g4_20mhz`) or a frame
     *                       file (`"format": "sems.frame"`); its N and M must equal n_symbols and
     *                       n_subcarriers. Empty: the paper's frame with n_symbols x n_subcarriers.
     *                       The bundle's frame must equal it in every field (N, M, B, f_c, T, CP, guards).
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
                     const std::string& frame = "");

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
    /*! \brief Mean |error| in delay indices. \return the MAE; NaN before the first scored frame. */
    virtual double mae_index() const = 0;
    /*! \brief Mean |error| in metres of range. \return the MAE; NaN before the first scored frame. */
    virtual double mae_m() const = 0;
    /*! \brief Restarts the running metrics (counters and sums) from zero. */
    virtual void reset_metrics() = 0;

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

#endif /* INCLUDED_SEMS_LEARNING_DELAY_ESTIMATOR_SINK_H */
