// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: pilot_mapper implementation (see pilot_mapper.h). */
#include "blocks/common/block_mask.h"
#include "blocks/common/data_tags.h"
#include "blocks/pilot_mapper_impl.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/common/tags.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {

pilot_mapper::sptr pilot_mapper::make(const std::string& mask_file,
                                      const std::vector<int>& pilot_positions,
                                      int n_symbols,
                                      int n_subcarriers,
                                      gr_complex pilot_symbol,
                                      double pilot_power,
                                      double data_power,
                                      const std::vector<int>& guard_subcarriers)
{
    const char* const who = pilot_mapper_impl::who;
    auto mask = block_mask(who, n_symbols, n_subcarriers, mask_file, pilot_positions, pilot_symbol);
    frame_settings fs;
    fs.n_symbols = n_symbols;
    fs.n_subcarriers = n_subcarriers;
    fs.cp_len = 0;
    fs.guard_subcarriers = guard_subcarriers;
    std::sort(fs.guard_subcarriers.begin(), fs.guard_subcarriers.end());
    try {
        fs.validate(); // in range, each once, not every subcarrier
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(who) + ": guard_subcarriers: " + e.what());
    }
    mask.check_frame(fs, who); // names a pilot on a guard
    return gnuradio::make_block_sptr<pilot_mapper_impl>(mask, pilot_power, data_power, fs.guard_subcarriers);
}

pilot_mapper_impl::pilot_mapper_impl(const super_frame_mask& mask,
                                     double pilot_power,
                                     double data_power,
                                     const std::vector<int>& guard_subcarriers)
    : gr::block(who,
                // Optional input: a pilot-only mask (N_p = N·(M − G)) needs no data (check_topology).
                gr::io_signature::make(0, 1, sizeof(gr_complex)),
                gr::io_signature::make(1, 1, sizeof(gr_complex) * mask.n_subcarriers())),
      d_mask(mask),
      d_n(mask.n_symbols()),
      d_m(mask.n_subcarriers()),
      d_guard_cols(guard_subcarriers),
      d_pilot_values(mask.pilots_per_frame()),
      d_frame_key(pmt::intern(keys::frame_tag))
{
    check_power(who, "pilot_power", pilot_power);
    check_power(who, "data_power", data_power);
    d_pilot_power = pilot_power;
    d_data_power = data_power;
    std::vector<char> guard(static_cast<size_t>(d_m), 0);
    for (int m : d_guard_cols)
        guard[static_cast<size_t>(m)] = 1;
    for (const auto& mask_of_set : d_mask.sets()) {
        pilot_set s;
        s.pilot_cols.resize(d_n);
        s.data_cols.resize(d_n);
        s.data_before_row.assign(d_n + 1, 0);
        s.pilots_before_row.assign(d_n + 1, 0);
        const auto dense = mask_of_set.dense();
        for (int n = 0; n < d_n; ++n) {
            for (int m = 0; m < d_m; ++m)
                if (!guard[static_cast<size_t>(m)])
                    (dense[size_t(n) * d_m + m] ? s.pilot_cols : s.data_cols)[n].push_back(m);
            s.data_before_row[n + 1] = s.data_before_row[n] + static_cast<long>(s.data_cols[n].size());
            s.pilots_before_row[n + 1] = s.pilots_before_row[n] + static_cast<int>(s.pilot_cols[n].size());
        }
        d_sets.push_back(std::move(s));
    }
    // Every set has the same count on the same guards, so the same data per frame.
    d_data_per_frame = static_cast<int>(d_sets.front().data_before_row[d_n]);
    latch_pilot_values(pilot_power);
    d_data_amp = static_cast<float>(std::sqrt(data_power));
    if (d_data_per_frame > 0)
        set_relative_rate(static_cast<uint64_t>(d_n), static_cast<uint64_t>(d_data_per_frame));
    // Data-symbol tags are moved by hand onto the OFDM symbol that carries them.
    set_tag_propagation_policy(TPP_DONT);
    d_tags.reserve(64);
}

void pilot_mapper_impl::latch_pilot_values(double energy)
{
    // Pilot k of the frame's set carries sqrt(E_p)·sqrt(p_k)·s_p (pilot_mask::transmitted_pilot).
    const auto& set = d_mask.for_frame(d_frame);
    for (int k = 0; k < set.size(); ++k)
        d_pilot_values[k] = gr_complex(std::sqrt(energy)) * set.transmitted_pilot(k);
}

void pilot_mapper_impl::set_pilot_power(double energy)
{
    check_power(who, "pilot_power", energy);
    d_pilot_power = energy; // latched at the next frame start
}

double pilot_mapper_impl::pilot_power() const { return d_pilot_power; }

void pilot_mapper_impl::set_data_power(double energy)
{
    check_power(who, "data_power", energy);
    d_data_power = energy;
}

double pilot_mapper_impl::data_power() const { return d_data_power; }

bool pilot_mapper_impl::check_topology(int ninputs, int noutputs)
{
    if (ninputs == 0 && d_data_per_frame > 0)
        throw std::invalid_argument(std::string(who) + ": the mask leaves " + std::to_string(d_data_per_frame) +
                                    " data positions per frame, so the data input must be connected");
    return true;
}

void pilot_mapper_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    if (ninput_items_required.empty())
        return;
    // Exactly the data the next noutput_items rows take, starting at the current row: the rest
    // of this frame (its set's layout), whole frames, then the first rows of the last one.
    long rows = noutput_items;
    const long here = std::min<long>(rows, d_n - d_row);
    const auto& now = set_of(d_frame);
    long need = now.data_before_row[d_row + here] - now.data_before_row[d_row];
    rows -= here;
    need += (rows / d_n) * d_data_per_frame;
    const uint64_t last = d_frame + 1 + static_cast<uint64_t>(rows / d_n);
    need += set_of(last).data_before_row[rows % d_n];
    ninput_items_required[0] = static_cast<int>(need);
}

int pilot_mapper_impl::general_work(int noutput_items,
                                    gr_vector_int& ninput_items,
                                    gr_vector_const_void_star& input_items,
                                    gr_vector_void_star& output_items)
{
    const bool has_input = !input_items.empty();
    const auto* in = has_input ? static_cast<const gr_complex*>(input_items[0]) : nullptr;
    auto* out = static_cast<gr_complex*>(output_items[0]);
    const int avail = has_input ? ninput_items[0] : 0;
    const uint64_t nread = has_input ? nitems_read(0) : 0;
    const uint64_t nwritten = nitems_written(0);

    if (has_input)
        get_tags_in_range(d_tags, 0, nread, nread + static_cast<uint64_t>(avail));
    size_t next_tag = 0;

    int consumed = 0, produced = 0;
    while (produced < noutput_items) {
        const pilot_set& set = set_of(d_frame);
        const auto& data_cols = set.data_cols[d_row];
        const int need = static_cast<int>(data_cols.size());
        if (consumed + need > avail)
            break;

        if (d_row == 0) { // frame start: latch the powers for the whole frame, tag it
            latch_pilot_values(d_pilot_power.load());
            d_data_amp = static_cast<float>(std::sqrt(d_data_power.load()));
            add_item_tag(0, nwritten + produced, d_frame_key, pmt::from_uint64(d_frame));
            ++d_frames;
        }

        gr_complex* row = out + static_cast<size_t>(produced) * d_m;
        for (int m : d_guard_cols)
            row[m] = gr_complex(0.0f, 0.0f);
        const auto& pilot_cols = set.pilot_cols[d_row];
        const gr_complex* values = d_pilot_values.data() + set.pilots_before_row[d_row];
        for (size_t j = 0; j < pilot_cols.size(); ++j)
            row[pilot_cols[j]] = values[j];
        const gr_complex* data = in + consumed;
        for (int k = 0; k < need; ++k)
            row[data_cols[k]] = d_data_amp * data[k];

        // Tags of the data symbols just used go onto this OFDM symbol.
        const uint64_t used_end = nread + static_cast<uint64_t>(consumed + need);
        move_data_tags(d_tags, next_tag, used_end, d_frame_key, [&](const gr::tag_t& t) {
            add_item_tag(0, nwritten + produced, t.key, t.value, t.srcid);
        });

        consumed += need;
        ++produced;
        if (++d_row == d_n) {
            d_row = 0;
            ++d_frame;
        }
    }
    if (has_input)
        consume(0, consumed);
    return produced;
}

} // namespace sems
} // namespace gr
