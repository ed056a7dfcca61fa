// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: target_channel_td implementation (see target_channel_td.h). */
#include "blocks/target_channel_td_impl.h"
#include "blocks/common/stream_values.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/common/tags.h>
#include <stdexcept>

namespace gr {
namespace sems {

target_channel_td::sptr target_channel_td::make(const std::string& scene_text,
                                                const std::vector<std::string>& classes,
                                                int n_targets,
                                                int paths_per_target,
                                                bool micro_doppler,
                                                int clutter_paths,
                                                double clutter_csr_db,
                                                double snr_db,
                                                uint64_t seed,
                                                int n_symbols,
                                                int n_subcarriers,
                                                double bandwidth_hz,
                                                double carrier_hz,
                                                double symbol_interval_s,
                                                int cp_len,
                                                const std::string& class_library,
                                                int n_receive,
                                                int n_transmit,
                                                const std::string& array,
                                                double azimuth_min_rad,
                                                double azimuth_max_rad)
{
    const char* const who = target_channel_td_impl::who;
    detail::check_snr(who, snr_db);
    if (cp_len < 0)
        throw std::invalid_argument(std::string(who) + ": cp_len must be >= 0, got " + std::to_string(cp_len));
    frame_settings fs;
    fs.n_symbols = n_symbols;
    fs.n_subcarriers = n_subcarriers;
    fs.bandwidth_hz = bandwidth_hz;
    fs.carrier_hz = carrier_hz;
    fs.symbol_interval_s = symbol_interval_s;
    fs.cp_len = cp_len;
    try {
        fs.validate();
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(who) + ": " + e.what());
    }
    // (No heading parameter here yet: random scenes use the default heading; a scene JSON may set "any".)
    auto sc = detail::channel_block_scene(who, scene_text, classes, n_targets, paths_per_target, micro_doppler,
                                          heading_name(random_spec{}.heading), clutter_paths, clutter_csr_db, class_library,
                                          {}, { n_receive, n_transmit }, { array, azimuth_min_rad, azimuth_max_rad });
    try { // the model checks the scene against the frame, td_channel T against the symbol length
        return gnuradio::make_block_sptr<target_channel_td_impl>(channel_model(fs, sc, seed), snr_db, n_receive,
                                                                  n_transmit);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(who) + ": " + e.what());
    }
}

target_channel_td_impl::target_channel_td_impl(channel_model model, double snr_db, int n_receive, int n_transmit)
    : gr::sync_block(who,
                     gr::io_signature::make(n_transmit, n_transmit, sizeof(gr_complex)),
                     gr::io_signature::make(n_receive, n_receive, sizeof(gr_complex))),
      d_model(std::move(model)),
      d_rx(n_receive),
      d_tx(n_transmit),
      d_n(d_model.settings().n_symbols),
      d_s(d_model.settings().n_subcarriers + d_model.settings().cp_len),
      d_snr_db(snr_db),
      d_frame_snr_db(snr_db),
      d_frame_key(pmt::intern(keys::frame_tag)),
      d_truth(d_model.scene_spec().library().name()),
      d_spacing(who, d_n, d_model.settings().n_subcarriers, d_model.settings().cp_len)
{
    for (const auto& e : d_model.elements())
        d_td.emplace_back(d_model.settings(), e);
    if (d_tx > 1)
        d_sum.resize(size_t(d_s));
    set_output_multiple(d_s); // whole symbols per call
    d_tags.reserve(16);
}

void target_channel_td_impl::set_snr_db(double snr_db)
{
    detail::check_snr(who, snr_db);
    d_snr_db = snr_db; // latched at the next frame start
}

double target_channel_td_impl::snr_db() const { return d_snr_db; }

void target_channel_td_impl::start_frame(uint64_t frame, uint64_t out_offset)
{
    d_frame_snr_db = d_snr_db.load();
    auto r = d_model.draw(frame);
    for (auto& td : d_td)
        td.set_frame(r, frame * static_cast<uint64_t>(d_n));
    d_frame = frame;
    d_row = 0;
    d_started = true;
    ++d_frames;
    const pmt::pmt_t truth = d_truth.make(r, frame, d_frame_snr_db);
    for (int k = 0; k < d_rx; ++k)
        add_item_tag(k, out_offset, d_truth.tag_key(), truth, alias_pmt());
}

int target_channel_td_impl::work(int noutput_items,
                                 gr_vector_const_void_star& input_items,
                                 gr_vector_void_star& output_items)
{
    const uint64_t nread = nitems_read(0), nwritten = nitems_written(0);
    const int symbols = noutput_items / d_s; // output multiple: noutput_items = symbols·S

    get_tags_in_window(d_tags, 0, 0, noutput_items, d_frame_key);
    for (const auto& t : d_tags)
        if (!d_spacing.check(t, d_logger)) // another cyclic prefix upstream: refuse the stream
            return WORK_DONE;
    size_t next_tag = 0;

    for (int k = 0; k < symbols; ++k) {
        const uint64_t first = nread + static_cast<uint64_t>(k) * d_s;
        bool tagged = false;
        uint64_t tagged_frame = 0;
        for (; next_tag < d_tags.size() && d_tags[next_tag].offset < first + d_s; ++next_tag) {
            if (d_tags[next_tag].offset != first) {
                ++d_misaligned; // not on this symbol's first sample: ignored
                continue;
            }
            const auto index = detail::frame_index_of(d_tags[next_tag].value);
            tagged = true;
            tagged_frame = index ? *index : (d_started ? d_frame + 1 : 0); // unreadable: keep counting
        }
        if (tagged)
            start_frame(tagged_frame, nwritten + static_cast<uint64_t>(k) * d_s);
        else if (!d_started || d_row == d_n)
            start_frame(d_started ? d_frame + 1 : 0, nwritten + static_cast<uint64_t>(k) * d_s);

        const size_t at = static_cast<size_t>(k) * d_s;
        for (int j = 0; j < d_tx; ++j)
            if (!detail::all_finite(static_cast<const gr_complex*>(input_items[j]) + at, d_s)) {
                ++d_nonfinite;
                break;
            }
        for (int e = 0; e < d_rx; ++e) { // receive element e hears every transmit element
            gr_complex* y = static_cast<gr_complex*>(output_items[e]) + at;
            for (int j = 0; j < d_tx; ++j) {
                const auto* x = static_cast<const gr_complex*>(input_items[j]) + at;
                d_td[size_t(e * d_tx + j)].apply_symbol(d_row, x, j == 0 ? y : d_sum.data());
                if (j > 0)
                    for (int i = 0; i < d_s; ++i)
                        y[i] += d_sum[size_t(i)];
            }
            d_model.add_noise(y, static_cast<size_t>(d_s), d_frame_snr_db);
        }
        ++d_row;
    }
    return symbols * d_s;
}

} // namespace sems
} // namespace gr
