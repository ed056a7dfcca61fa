// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: target_channel implementation (see target_channel.h). */
#include "blocks/target_channel_impl.h"
#include "blocks/common/stream_values.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/common/tags.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace gr {
namespace sems {


target_channel::sptr target_channel::make(const std::string& scene_text,
                                          const std::vector<std::string>& classes,
                                          int n_targets,
                                          int paths_per_target,
                                          bool micro_doppler,
                                          const std::string& heading,
                                          int clutter_paths,
                                          double clutter_csr_db,
                                          double snr_db,
                                          uint64_t seed,
                                          int n_symbols,
                                          int n_subcarriers,
                                          double bandwidth_hz,
                                          double carrier_hz,
                                          double symbol_interval_s,
                                          const std::string& class_library,
                                          int track_frames,
                                          const std::string& track_gains,
                                          double track_coherence_time_s,
                                          int n_receive,
                                          int n_transmit,
                                          const std::string& track_motion,
                                          const std::string& array,
                                          double azimuth_min_rad,
                                          double azimuth_max_rad)
{
    const char* const who = target_channel_impl::who;
    detail::check_snr(who, snr_db);
    frame_settings fs;
    fs.n_symbols = n_symbols;
    fs.n_subcarriers = n_subcarriers;
    fs.bandwidth_hz = bandwidth_hz;
    fs.carrier_hz = carrier_hz;
    fs.symbol_interval_s = symbol_interval_s;
    fs.cp_len = 0; // the frequency-domain emulator has no cyclic prefix (ofdm_tx/rx add it)
    fs.validate();
    auto sc = detail::channel_block_scene(who, scene_text, classes, n_targets, paths_per_target, micro_doppler,
                                          heading, clutter_paths, clutter_csr_db, class_library,
                                          { track_frames, track_gains, track_coherence_time_s, track_motion },
                                          { n_receive, n_transmit }, { array, azimuth_min_rad, azimuth_max_rad });
    return gnuradio::make_block_sptr<target_channel_impl>(channel_model(fs, sc, seed), snr_db, n_receive, n_transmit);
}

target_channel_impl::target_channel_impl(channel_model model, double snr_db, int n_receive, int n_transmit)
    : gr::sync_block(who,
                     gr::io_signature::make(n_transmit, n_transmit, sizeof(gr_complex) * model.settings().n_subcarriers),
                     gr::io_signature::make(n_receive, n_receive, sizeof(gr_complex) * model.settings().n_subcarriers)),
      d_model(std::move(model)),
      d_n(d_model.settings().n_symbols),
      d_m(d_model.settings().n_subcarriers),
      d_rx(n_receive),
      d_tx(n_transmit),
      d_snr_db(snr_db),
      d_frame_snr_db(snr_db),
      d_channels(d_model.settings(), d_model.elements()),
      d_frame_key(pmt::intern(keys::frame_tag)),
      d_truth(d_model.scene_spec().library().name())
{
    d_tags.reserve(16);
    if (d_tx > 1)
        d_sum.resize(size_t(d_m));
}

void target_channel_impl::set_snr_db(double snr_db)
{
    detail::check_snr(who, snr_db);
    d_snr_db = snr_db; // latched at the next frame start
}

double target_channel_impl::snr_db() const { return d_snr_db; }

void target_channel_impl::start_frame(uint64_t frame, uint64_t out_offset)
{
    d_frame_snr_db = d_snr_db.load();
    ++d_frames; // started, even if drawing it fails below
    d_model.draw(frame, d_realization); // no allocation once the buffers have grown
    const auto& r = d_realization;
    const uint64_t first_symbol = frame * static_cast<uint64_t>(d_n);
    d_channels.update(r, first_symbol); // reuses the buffers
    d_frame = frame;
    d_row = 0;
    d_started = true;

    const pmt::pmt_t truth = d_truth.make(r, frame, d_frame_snr_db);
    for (int k = 0; k < d_rx; ++k)
        add_item_tag(k, out_offset, d_truth.tag_key(), truth, alias_pmt());
}

void target_channel_impl::apply_symbol(const gr_vector_const_void_star& input_items,
                                       gr_vector_void_star& output_items,
                                       int i)
{
    const size_t at = static_cast<size_t>(i) * d_m;
    for (int k = 0; k < d_rx; ++k) {
        gr_complex* y = static_cast<gr_complex*>(output_items[k]) + at;
        if (d_tx == 1) {
            d_channels.element(k).apply_row(d_row, static_cast<const gr_complex*>(input_items[0]) + at, y);
        } else { // receive element k hears every transmit element: Σ_j H_{k,j} ⊙ x_j
            for (int j = 0; j < d_tx; ++j) {
                const auto* x = static_cast<const gr_complex*>(input_items[j]) + at;
                d_channels.element(k * d_tx + j).apply_row(d_row, x, j == 0 ? y : d_sum.data());
                if (j > 0)
                    for (int m = 0; m < d_m; ++m)
                        y[m] += d_sum[size_t(m)];
            }
        }
        d_model.add_noise(y, static_cast<size_t>(d_m), d_frame_snr_db);
    }
}

int target_channel_impl::work(int noutput_items,
                              gr_vector_const_void_star& input_items,
                              gr_vector_void_star& output_items)
{
    const uint64_t nread = nitems_read(0), nwritten = nitems_written(0);

    get_tags_in_window(d_tags, 0, 0, noutput_items, d_frame_key);
    size_t next_tag = 0;

    for (int i = 0; i < noutput_items; ++i) {
        bool tagged = false;
        uint64_t tagged_frame = 0;
        for (; next_tag < d_tags.size() && d_tags[next_tag].offset == nread + i; ++next_tag) {
            const auto index = detail::frame_index_of(d_tags[next_tag].value);
            tagged = true;
            tagged_frame = index ? *index : (d_started ? d_frame + 1 : 0); // unreadable: keep counting
        }
        // Nothing escapes work(): a frame whose computation throws goes out as NaN (the
        // extractor counts it as skipped), the fault is counted and logged once per kind.
        const char* where = "frame start";
        try {
            if (tagged || !d_started || d_row == d_n) {
                const uint64_t frame = tagged ? tagged_frame : (d_started ? d_frame + 1 : 0);
                d_frame_faulted = false;
                d_frame = frame; // also when start_frame() throws: the next frame is frame + 1
                d_row = 0;
                d_started = true;
                start_frame(frame, nwritten + i);
            }
            where = "channel";
            if (!d_frame_faulted)
                apply_symbol(input_items, output_items, i);
        } catch (const std::exception& e) {
            if (!d_frame_faulted)
                ++d_faulted;
            d_frame_faulted = true;
            if (d_faults.first(where, e))
                d_logger->error("fault in {}: {}; frame {} is sent as NaN (counted downstream as skipped); "
                                "further faults of this kind are only counted",
                                where, e.what(), d_frame);
        }
        const size_t at = static_cast<size_t>(i) * d_m;
        if (d_frame_faulted)
            for (int k = 0; k < d_rx; ++k) {
                gr_complex* y = static_cast<gr_complex*>(output_items[k]) + at;
                std::fill(y, y + d_m, gr_complex(std::numeric_limits<float>::quiet_NaN(), 0.0f));
            }
        for (int j = 0; j < d_tx; ++j)
            if (!detail::all_finite(static_cast<const gr_complex*>(input_items[j]) + at, d_m)) {
                ++d_nonfinite;
                break;
            }
        ++d_row;
    }
    return noutput_items;
}

} // namespace sems
} // namespace gr
