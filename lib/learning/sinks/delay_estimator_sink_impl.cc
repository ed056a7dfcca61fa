// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: delay_estimator_sink implementation. */
#include "learning/sinks/delay_estimator_sink_impl.h"

#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/common/tags.h>
#include <cmath>
#include <limits>

namespace gr {
namespace sems {

namespace {
constexpr const char* block_name = "delay_estimator_sink";
}

// ---------------------------------------------------------------- delay_task

delay_task::delay_task(std::unique_ptr<bundle_decoder> decoder)
    : d_decoder(std::move(decoder)), d_fs(d_decoder->bundle().frame)
{
}

std::vector<pmt::pmt_t> delay_task::decode(const gr_complex* obs, int batch, const std::vector<detail::frame_meta>&)
{
    const std::vector<double> delays = d_decoder->estimate_delay(obs, batch);
    std::vector<pmt::pmt_t> out;
    out.reserve(batch);
    for (int i = 0; i < batch; i++) {
        pmt::pmt_t d = pmt::make_dict();
        d = pmt::dict_add(d, pmt::intern(keys::delay_s), pmt::from_double(delays[i]));
        d = pmt::dict_add(d, pmt::intern(keys::delay_index), pmt::from_double(d_fs.delay_index(delays[i])));
        d = pmt::dict_add(d, pmt::intern(keys::range_m), pmt::from_double(d_fs.range_from_delay(delays[i])));
        out.push_back(d);
    }
    return out;
}

bool delay_task::score(pmt::pmt_t& result, const pmt::pmt_t& truth)
{
    double truth_index;
    if (!detail::truth_delay_index(truth, d_fs, truth_index))
        return false;
    const double estimate = pmt::to_double(pmt::dict_ref(result, pmt::intern(keys::delay_index), pmt::PMT_NIL));
    const double err = std::abs(estimate - truth_index);
    result = pmt::dict_add(result, pmt::intern(keys::abs_error_index), pmt::from_double(err));
    d_scored++;
    d_sum_abs_index += err;
    return true;
}

double delay_task::mae_index() const
{
    return d_scored ? d_sum_abs_index / d_scored : std::numeric_limits<double>::quiet_NaN();
}

double delay_task::mae_m() const { return mae_index() * d_fs.range_per_delay_index_m(); }

pmt::pmt_t delay_task::add_metrics(pmt::pmt_t dict) const
{
    dict = pmt::dict_add(dict, pmt::intern(keys::mae_index), pmt::from_double(mae_index()));
    return pmt::dict_add(dict, pmt::intern(keys::mae_m), pmt::from_double(mae_m()));
}

void delay_task::reset_metrics()
{
    d_scored = 0;
    d_sum_abs_index = 0.0;
}

// ---------------------------------------------------------------- delay_estimator_sink

delay_estimator_sink::sptr delay_estimator_sink::make(const std::string& bundle_dir,
                                                      int n_pilots,
                                                      int batch_size,
                                                      int threads,
                                                      int metrics_period,
                                                      int n_symbols,
                                                      int n_subcarriers,
                                                      const std::string& frame)
{
    return gnuradio::make_block_sptr<delay_estimator_sink_impl>(
        bundle_dir, n_pilots, batch_size, threads, metrics_period, n_symbols, n_subcarriers, frame);
}

delay_estimator_sink_impl::delay_estimator_sink_impl(const std::string& bundle_dir,
                                                     int n_pilots,
                                                     int batch_size,
                                                     int threads,
                                                     int metrics_period,
                                                     int n_symbols,
                                                     int n_subcarriers,
                                                     const std::string& frame)
    : gr::sync_block(block_name,
                     detail::sink_input_signature(block_name, n_pilots, batch_size, threads, metrics_period),
                     gr::io_signature::make(0, 0, 0)),
      sink_block(block_name, task_kind::delay, bundle_dir, n_pilots, batch_size, threads, metrics_period,
                 n_symbols, n_subcarriers, frame)
{
}

double delay_estimator_sink_impl::mae_index() const
{
    return d_core.locked([this] { return d_task.mae_index(); });
}

double delay_estimator_sink_impl::mae_m() const
{
    return d_core.locked([this] { return d_task.mae_m(); });
}

} // namespace sems
} // namespace gr
