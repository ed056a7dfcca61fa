// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: position_sink implementation. */
#include "learning/sinks/position_sink_impl.h"
#include "core/common/checks.h"

#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/common/tags.h>
#include <cmath>
#include <limits>

namespace gr {
namespace sems {

namespace {
constexpr const char* block_name = "position_sink";

// The stream's frame (a preset or file; empty: the paper's), for the bundle check's N and M.
frame_settings stream_frame(const std::string& frame)
{
    if (frame.empty())
        return frame_settings{};
    try {
        return frame_file::find(frame).frame;
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(block_name) + ": frame: " + e.what());
    }
}
} // namespace

// ---------------------------------------------------------------- position_task

position_task::position_task(std::unique_ptr<bundle_decoder> decoder, int n_elements, int threads)
    : d_estimator(std::move(decoder), threads), d_fs(d_estimator.bundle().frame)
{
    if (d_estimator.n_elements() != n_elements)
        throw std::invalid_argument(std::string(block_name) + ": the bundle " + d_estimator.bundle().directory +
                                    " is for an array of " + std::to_string(d_estimator.n_elements()) +
                                    " receive elements, but n_elements = " + std::to_string(n_elements));
}

std::vector<pmt::pmt_t> position_task::decode(const gr_complex* obs, int batch, const std::vector<detail::frame_meta>&)
{
    const auto found = d_estimator.estimate(obs, batch);
    std::vector<pmt::pmt_t> out;
    out.reserve(size_t(batch));
    for (const auto& e : found) {
        pmt::pmt_t d = pmt::make_dict();
        d = pmt::dict_add(d, pmt::intern(keys::delay_s), pmt::from_double(e.delay_s));
        d = pmt::dict_add(d, pmt::intern(keys::delay_index), pmt::from_double(e.delay_index));
        d = pmt::dict_add(d, pmt::intern(keys::range_m), pmt::from_double(e.range_m));
        d = pmt::dict_add(d, pmt::intern(keys::azimuth_rad), pmt::from_double(e.azimuth_rad));
        out.push_back(d);
    }
    return out;
}

bool position_task::score(pmt::pmt_t& result, const pmt::pmt_t& truth)
{
    double truth_index;
    if (!detail::truth_delay_index(truth, d_fs, truth_index))
        return false;
    const double index = pmt::to_double(pmt::dict_ref(result, pmt::intern(keys::delay_index), pmt::PMT_NIL));
    const double err = std::abs(index - truth_index);
    result = pmt::dict_add(result, pmt::intern(keys::abs_error_index), pmt::from_double(err));
    d_scored++;
    d_sum_abs_index += err;
    double truth_azimuth;
    if (detail::dict_number(truth, keys::azimuth_rad, truth_azimuth) && checks::finite(truth_azimuth)) {
        const double az = pmt::to_double(pmt::dict_ref(result, pmt::intern(keys::azimuth_rad), pmt::PMT_NIL));
        const double e = std::abs(az - truth_azimuth);
        result = pmt::dict_add(result, pmt::intern(keys::abs_error_azimuth_rad), pmt::from_double(e));
        d_scored_azimuth++;
        d_sum_sq_azimuth += e * e;
    }
    return true;
}

double position_task::mae_index() const
{
    return d_scored ? d_sum_abs_index / double(d_scored) : std::numeric_limits<double>::quiet_NaN();
}

double position_task::mae_m() const { return mae_index() * d_fs.range_per_delay_index_m(); }

double position_task::rmse_azimuth_rad() const
{
    return d_scored_azimuth ? std::sqrt(d_sum_sq_azimuth / double(d_scored_azimuth))
                            : std::numeric_limits<double>::quiet_NaN();
}

pmt::pmt_t position_task::add_metrics(pmt::pmt_t dict) const
{
    dict = pmt::dict_add(dict, pmt::intern(keys::mae_index), pmt::from_double(mae_index()));
    dict = pmt::dict_add(dict, pmt::intern(keys::mae_m), pmt::from_double(mae_m()));
    dict = pmt::dict_add(dict, pmt::intern(keys::frames_scored_azimuth), pmt::from_uint64(d_scored_azimuth));
    return pmt::dict_add(dict, pmt::intern(keys::rmse_azimuth_rad), pmt::from_double(rmse_azimuth_rad()));
}

void position_task::reset_metrics()
{
    d_scored = d_scored_azimuth = 0;
    d_sum_abs_index = d_sum_sq_azimuth = 0.0;
}

// ---------------------------------------------------------------- position_sink

position_sink::sptr position_sink::make(const std::string& bundle_dir,
                                        int n_elements,
                                        int n_pilots,
                                        int batch_size,
                                        int threads,
                                        int metrics_period,
                                        const std::string& frame)
{
    return gnuradio::make_block_sptr<position_sink_impl>(
        bundle_dir, n_elements, n_pilots, batch_size, threads, metrics_period, frame);
}

position_sink_impl::position_sink_impl(const std::string& bundle_dir,
                                       int n_elements,
                                       int n_pilots,
                                       int batch_size,
                                       int threads,
                                       int metrics_period,
                                       const std::string& frame)
    : gr::sync_block(block_name,
                     detail::sink_input_signature(block_name, detail::array_item_length(block_name, n_elements, n_pilots), batch_size, threads,
                                                  metrics_period),
                     gr::io_signature::make(0, 0, 0)),
      sink_block(block_name, task_kind::delay, bundle_dir, n_pilots, batch_size, threads, metrics_period,
                 stream_frame(frame).n_symbols, stream_frame(frame).n_subcarriers, frame, n_elements, threads)
{
}

double position_sink_impl::mae_index() const
{
    return d_core.locked([this] { return d_task.mae_index(); });
}

double position_sink_impl::mae_m() const
{
    return d_core.locked([this] { return d_task.mae_m(); });
}

uint64_t position_sink_impl::frames_scored_azimuth() const
{
    return d_core.locked([this] { return d_task.scored_azimuth(); });
}

double position_sink_impl::rmse_azimuth_rad() const
{
    return d_core.locked([this] { return d_task.rmse_azimuth_rad(); });
}

} // namespace sems
} // namespace gr
