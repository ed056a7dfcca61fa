// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: position_sink implementation — a thin adapter: sink_core does the stream
 * bookkeeping, position_task the decoding (position_estimator) and the scoring. */
#ifndef INCLUDED_SEMS_LIB_LEARNING_POSITION_SINK_IMPL_H
#define INCLUDED_SEMS_LIB_LEARNING_POSITION_SINK_IMPL_H

#include "learning/sinks/sink_block.h"
#include "learning/sinks/sink_core.h"
#include <gnuradio/sems/learning/array/position_estimator.h>
#include <gnuradio/sems/learning/sinks/position_sink.h>

namespace gr {
namespace sems {

// Delay and azimuth of the target of interest; the delay's mean absolute error (as delay_task)
// and the azimuth's root-mean-square error.
class position_task : public detail::sink_task
{
public:
    // `decoder`: the position bundle's delay decoder; `n_elements`: the block's N_r.
    position_task(std::unique_ptr<bundle_decoder> decoder, int n_elements, int threads);

    std::vector<pmt::pmt_t> decode(const gr_complex* obs, int batch, const std::vector<detail::frame_meta>& meta) override;
    bool score(pmt::pmt_t& result, const pmt::pmt_t& truth) override;
    pmt::pmt_t add_metrics(pmt::pmt_t dict) const override;
    void reset_metrics() override;
    int elements() const override { return d_estimator.n_elements(); }

    double mae_index() const;
    double mae_m() const;
    uint64_t scored_azimuth() const { return d_scored_azimuth; }
    double rmse_azimuth_rad() const;

private:
    position_estimator d_estimator;
    frame_settings d_fs;
    uint64_t d_scored = 0, d_scored_azimuth = 0;
    double d_sum_abs_index = 0.0, d_sum_sq_azimuth = 0.0;
};

class position_sink_impl : public detail::sink_block<position_sink, position_task>
{
public:
    position_sink_impl(const std::string& bundle_dir,
                       int n_elements,
                       int n_pilots,
                       int batch_size,
                       int threads,
                       int metrics_period,
                       const std::string& frame);

    double mae_index() const override;
    double mae_m() const override;
    uint64_t frames_scored_azimuth() const override;
    double rmse_azimuth_rad() const override;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_POSITION_SINK_IMPL_H */
