// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: target_channel implementation (see target_channel.h). */
#include "blocks/target_channel_impl.h"
#include "blocks/stream_values.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/tags.h>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace gr {
namespace sems {

static const char* const who = "target_channel";

namespace {

void check_snr(double snr_db)
{
    if (std::isnan(snr_db) || snr_db == -std::numeric_limits<double>::infinity())
        throw std::invalid_argument(std::string(who) + ": snr_db must be a number or +inf (noiseless), got " +
                                    std::to_string(snr_db));
}

scene build_scene(const std::string& text,
                  const std::vector<std::string>& classes,
                  int n_targets,
                  int paths_per_target,
                  bool micro_doppler,
                  int clutter_paths,
                  double clutter_csr_db)
{
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos) { // a fixed scene: file or JSON text
        const random_spec defaults;
        if (!classes.empty() || n_targets != defaults.n_targets ||
            paths_per_target != defaults.paths_per_target || micro_doppler != defaults.micro_doppler ||
            clutter_paths != 0 || clutter_csr_db != 0.0)
            throw std::invalid_argument(std::string(who) +
                                        ": classes, n_targets, paths_per_target, micro_doppler and clutter_* "
                                        "describe random scenes; a fixed scene (scene = file or JSON) carries "
                                        "its own, so leave them at their defaults");
        if (text[first] == '{')
            return scene::parse(text, std::string(who) + " scene JSON");
        return scene::load(text);
    }

    random_spec r;
    if (!classes.empty()) {
        r.classes.clear();
        for (const auto& name : classes) {
            try {
                r.classes.push_back(class_from_name(name));
            } catch (const std::invalid_argument& e) {
                throw std::invalid_argument(std::string(who) + ": classes: " + e.what());
            }
        }
    }
    r.n_targets = n_targets;
    r.paths_per_target = paths_per_target;
    r.micro_doppler = micro_doppler;
    std::optional<clutter_spec> clutter;
    if (clutter_paths < 0)
        throw std::invalid_argument(std::string(who) + ": clutter_paths must be >= 0, got " +
                                    std::to_string(clutter_paths));
    if (clutter_paths > 0) {
        clutter_spec c;
        c.n_paths = clutter_paths;
        c.csr_db = clutter_csr_db;
        clutter = c;
    }
    auto sc = scene::random(r, clutter);
    sc.validate(std::string(who) + " random scene");
    return sc;
}

} // namespace

target_channel::sptr target_channel::make(const std::string& scene_text,
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
                                          double symbol_interval_s)
{
    check_snr(snr_db);
    frame_settings fs;
    fs.n_symbols = n_symbols;
    fs.n_subcarriers = n_subcarriers;
    fs.bandwidth_hz = bandwidth_hz;
    fs.carrier_hz = carrier_hz;
    fs.symbol_interval_s = symbol_interval_s;
    fs.cp_len = 0; // the frequency-domain emulator has no cyclic prefix (ofdm_tx/rx add it)
    fs.validate();
    auto sc = build_scene(scene_text, classes, n_targets, paths_per_target, micro_doppler, clutter_paths,
                          clutter_csr_db);
    return gnuradio::make_block_sptr<target_channel_impl>(channel_model(fs, sc, seed), snr_db);
}

target_channel_impl::target_channel_impl(channel_model model, double snr_db)
    : gr::sync_block(who,
                     gr::io_signature::make(1, 1, sizeof(gr_complex) * model.settings().n_subcarriers),
                     gr::io_signature::make(1, 1, sizeof(gr_complex) * model.settings().n_subcarriers)),
      d_model(std::move(model)),
      d_n(d_model.settings().n_symbols),
      d_m(d_model.settings().n_subcarriers),
      d_snr_db(snr_db),
      d_frame_snr_db(snr_db),
      d_frame_key(pmt::intern(keys::frame_tag)),
      d_truth_key(pmt::intern(keys::truth_tag)),
      d_k_frame(pmt::intern(keys::frame)),
      d_k_class(pmt::intern(keys::class_id)),
      d_k_class_name(pmt::intern(keys::class_name)),
      d_k_delay_s(pmt::intern(keys::delay_s)),
      d_k_delay_index(pmt::intern(keys::delay_index)),
      d_k_range_m(pmt::intern(keys::range_m)),
      d_k_velocity_mps(pmt::intern(keys::velocity_mps)),
      d_k_snr_db(pmt::intern(keys::snr_db)),
      d_k_n_paths(pmt::intern(keys::n_paths))
{
    d_tags.reserve(16);
}

void target_channel_impl::set_snr_db(double snr_db)
{
    check_snr(snr_db);
    d_snr_db = snr_db; // latched at the next frame start
}

double target_channel_impl::snr_db() const { return d_snr_db; }

void target_channel_impl::start_frame(uint64_t frame, uint64_t out_offset)
{
    d_frame_snr_db = d_snr_db.load();
    auto r = d_model.draw(frame);
    const uint64_t first_symbol = frame * static_cast<uint64_t>(d_n);
    if (d_channel)
        d_channel->update(r.paths, first_symbol); // reuses the buffers
    else
        d_channel.emplace(d_model.factors(r, first_symbol));
    d_frame = frame;
    d_row = 0;
    d_started = true;
    ++d_frames;

    const auto& t = r.truth;
    pmt::pmt_t dict = pmt::make_dict();
    dict = pmt::dict_add(dict, d_k_frame, pmt::from_uint64(frame));
    dict = pmt::dict_add(dict, d_k_class, pmt::from_long(t.class_id));
    dict = pmt::dict_add(dict, d_k_class_name, pmt::string_to_symbol(t.class_name));
    dict = pmt::dict_add(dict, d_k_delay_s, pmt::from_double(t.delay_s));
    dict = pmt::dict_add(dict, d_k_delay_index, pmt::from_double(t.delay_index));
    dict = pmt::dict_add(dict, d_k_range_m, pmt::from_double(t.range_m));
    dict = pmt::dict_add(dict, d_k_velocity_mps, pmt::from_double(t.velocity_mps));
    dict = pmt::dict_add(dict, d_k_snr_db, pmt::from_double(d_frame_snr_db));
    dict = pmt::dict_add(dict, d_k_n_paths, pmt::from_long(t.n_paths));
    add_item_tag(0, out_offset, d_truth_key, dict, alias_pmt());
}

int target_channel_impl::work(int noutput_items,
                              gr_vector_const_void_star& input_items,
                              gr_vector_void_star& output_items)
{
    const auto* in = static_cast<const gr_complex*>(input_items[0]);
    auto* out = static_cast<gr_complex*>(output_items[0]);
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
        if (tagged)
            start_frame(tagged_frame, nwritten + i);
        else if (!d_started || d_row == d_n)
            start_frame(d_started ? d_frame + 1 : 0, nwritten + i);

        const gr_complex* x = in + static_cast<size_t>(i) * d_m;
        gr_complex* y = out + static_cast<size_t>(i) * d_m;
        if (!detail::all_finite(x, d_m))
            ++d_nonfinite;
        d_channel->apply_row(d_row, x, y);
        d_model.add_noise(y, static_cast<size_t>(d_m), d_frame_snr_db);
        ++d_row;
    }
    return noutput_items;
}

} // namespace sems
} // namespace gr
