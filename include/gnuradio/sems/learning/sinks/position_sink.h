// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The position_sink block.
 */
#ifndef INCLUDED_SEMS_LEARNING_POSITION_SINK_H
#define INCLUDED_SEMS_LEARNING_POSITION_SINK_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/sinks/sink_defaults.h>
#include <gnuradio/sync_block.h>
#include <cstdint>
#include <string>

namespace gr {
namespace sems {

/*!
 * \brief Locates the target of interest of each frame, its delay and its azimuth, from an
 *        array's pilots with a position bundle (learning/array/position_estimator.h).
 *
 * \details Input: gr_complex[N_r·N_p] per frame, the pilot extractor's element-major output
 * (element k's pilots at k·N_p, mask order). Output: a PMT dict per frame on message port
 * `result`: frame, delay_s, delay_index (τ·B), range_m (cτ/2) and azimuth_rad and, when a
 * sems_truth tag came with the frame, truth (that dict), abs_error_index and, when the truth
 * has an azimuth (a scene with an array), abs_error_azimuth_rad.
 * Running metrics (frames, frames_scored, frames_skipped, frames_faulted, mae_index, mae_m, frames_scored_azimuth,
 * rmse_azimuth_rad) are readable through the getters and sent on port `metrics` every
 * `metrics_period` frames and at the end unless the last of those carried the final numbers. Frames with NaN or Inf are counted in
 * frames_skipped and never decoded; frames are decoded `batch_size` at a time, the partial last
 * batch in stop().
 */
class SEMS_LEARNING_API position_sink : virtual public gr::sync_block
{
public:
    typedef std::shared_ptr<position_sink> sptr; ///< shared pointer to the block

    /*!
     * \brief Makes a position sink.
     * \param bundle_dir     position bundle (a delay bundle with bundle.json's `position`): a directory or a name
     * \param n_elements     N_r, the receive elements; must equal the bundle's array's
     * \param n_pilots       N_p per element; must match the bundle's mask
     * \param batch_size     frames per inference call (>= 1)
     * \param threads        LibTorch intra-op threads (0: leave LibTorch's setting)
     * \param metrics_period send metrics every K frames (0: only at the end of the stream)
     * \param frame          the stream's frame: a preset's name or a frame file; empty: the paper's.
     *                       The bundle's frame must equal it in every field.
     * \return the block.
     * \throws std::invalid_argument naming the bundle and the mismatch.
     */
    static sptr make(const std::string& bundle_dir,
                     int n_elements,
                     int n_pilots,
                     int batch_size = sink_defaults::batch_size,
                     int threads = sink_defaults::threads,
                     int metrics_period = sink_defaults::metrics_period,
                     const std::string& frame = "");

    /*! \brief Frames handled: answered or skipped. \return the count. */
    virtual uint64_t frames() const = 0;
    /*! \brief Frames answered with a truth to compare. \return the count. */
    virtual uint64_t frames_scored() const = 0;
    /*! \brief Non-finite or faulted frames, never answered. \return the count. */
    virtual uint64_t frames_skipped() const = 0;
    /*! \brief Frames skipped because decoding or the bookkeeping failed. \return the count. */
    virtual uint64_t frames_faulted() const = 0;
    /*! \brief Mean |delay error| in delay indices. \return the MAE; NaN before the first scored frame. */
    virtual double mae_index() const = 0;
    /*! \brief Mean |delay error| in metres of range. \return the MAE; NaN before the first scored frame. */
    virtual double mae_m() const = 0;
    /*! \brief Frames scored whose truth had an azimuth. \return the count. */
    virtual uint64_t frames_scored_azimuth() const = 0;
    /*! \brief Root-mean-square azimuth error in rad. \return the RMSE; NaN before the first such frame. */
    virtual double rmse_azimuth_rad() const = 0;
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

#endif /* INCLUDED_SEMS_LEARNING_POSITION_SINK_H */
