// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: delay_estimator_sink implementation — a thin adapter: sink_core does the
 * stream bookkeeping, delay_task the decoding and the scoring. */
#ifndef INCLUDED_SEMS_LIB_LEARNING_DELAY_ESTIMATOR_SINK_IMPL_H
#define INCLUDED_SEMS_LIB_LEARNING_DELAY_ESTIMATOR_SINK_IMPL_H

#include "learning/sinks/sink_block.h"
#include "learning/sinks/sink_core.h"
#include <gnuradio/sems/learning/sinks/delay_estimator_sink.h>

namespace gr {
namespace sems {

// Delay estimation of the target of interest; mean absolute error in delay indices and metres.
class delay_task : public detail::sink_task
{
public:
    explicit delay_task(std::unique_ptr<bundle_decoder> decoder);

    std::vector<pmt::pmt_t> decode(const gr_complex* obs, int batch, const std::vector<detail::frame_meta>& meta) override;
    bool score(pmt::pmt_t& result, const pmt::pmt_t& truth) override;
    pmt::pmt_t add_metrics(pmt::pmt_t dict) const override;
    void reset_metrics() override;

    double mae_index() const;
    double mae_m() const;

private:
    std::unique_ptr<bundle_decoder> d_decoder;
    frame_settings d_fs; // the bundle's: converts delay to index and range
    uint64_t d_scored = 0;
    double d_sum_abs_index = 0.0;
};

class delay_estimator_sink_impl : public detail::sink_block<delay_estimator_sink, delay_task>
{
public:
    delay_estimator_sink_impl(const std::string& bundle_dir,
                              int n_pilots,
                              int batch_size,
                              int threads,
                              int metrics_period,
                              int n_symbols,
                              int n_subcarriers,
                              const std::string& frame);

    double mae_index() const override;
    double mae_m() const override;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_DELAY_ESTIMATOR_SINK_IMPL_H */
