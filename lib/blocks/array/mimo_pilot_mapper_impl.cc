// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: mimo_pilot_mapper implementation (see mimo_pilot_mapper.h). */
#include "blocks/array/mimo_pilot_mapper_impl.h"
#include "blocks/common/block_mask.h"
#include "blocks/common/data_tags.h"
#include <gnuradio/io_signature.h>
#include <gnuradio/sems/core/common/tags.h>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {

mimo_pilot_mapper::sptr mimo_pilot_mapper::make(const std::string& mimo_mask_file,
                                                int n_transmit,
                                                double pilot_power,
                                                double data_power,
                                                const std::vector<int>& guard_subcarriers)
{
    const std::string who = mimo_pilot_mapper_impl::who;
    if (mimo_mask_file.empty())
        throw std::invalid_argument(who + ": mimo_mask_file: give a MIMO mask file (format sems.mimo_mask)");
    const mimo_mask mask = [&] {
        try {
            return mimo_mask::load(mimo_mask_file);
        } catch (const std::invalid_argument& e) { // the reader names the file and the problem
            throw std::invalid_argument(who + ": mimo_mask_file: " + e.what());
        }
    }();
    if (n_transmit != mask.n_transmit())
        throw std::invalid_argument(who + ": n_transmit = " + std::to_string(n_transmit) + " but mimo_mask_file '" +
                                    mimo_mask_file + "' has n_transmit = " + std::to_string(mask.n_transmit()));
    frame_settings fs;
    fs.n_symbols = mask.mask().n_symbols();
    fs.n_subcarriers = mask.mask().n_subcarriers();
    fs.cp_len = 0;
    fs.guard_subcarriers = guard_subcarriers;
    std::sort(fs.guard_subcarriers.begin(), fs.guard_subcarriers.end());
    try {
        fs.validate();
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(who + ": guard_subcarriers: " + e.what());
    }
    mask.mask().check_frame(fs, who);
    return gnuradio::make_block_sptr<mimo_pilot_mapper_impl>(mask, pilot_power, data_power, fs.guard_subcarriers);
}

mimo_pilot_mapper_impl::mimo_pilot_mapper_impl(const mimo_mask& mask,
                                               double pilot_power,
                                               double data_power,
                                               const std::vector<int>& guard_subcarriers)
    : gr::block(who,
                gr::io_signature::make(0, 1, sizeof(gr_complex)),
                gr::io_signature::make(mask.n_transmit(), mask.n_transmit(), sizeof(gr_complex) * mask.mask().n_subcarriers())),
      d_mask(mask),
      d_n(mask.mask().n_symbols()),
      d_m(mask.mask().n_subcarriers()),
      d_nt(mask.n_transmit()),
      d_pilot_cols(size_t(d_n)),
      d_pilot_index(size_t(d_n)),
      d_data_cols(size_t(d_n)),
      d_data_before_row(size_t(d_n) + 1, 0),
      d_guard_cols(guard_subcarriers),
      d_values(size_t(mask.n_transmit()) * size_t(mask.mask().size())),
      d_frame_key(pmt::intern(keys::frame_tag))
{
    check_power(who, "pilot_power", pilot_power);
    check_power(who, "data_power", data_power);
    d_pilot_power = pilot_power;
    d_data_power = data_power;
    std::vector<char> guard(size_t(d_m), 0);
    for (int m : d_guard_cols)
        guard[size_t(m)] = 1;
    std::vector<int> pilot_at(size_t(d_n) * d_m, -1);
    for (int k = 0; k < d_mask.mask().size(); ++k) {
        const auto& p = d_mask.mask().positions()[size_t(k)];
        pilot_at[size_t(p.n) * d_m + p.m] = k;
    }
    for (int n = 0; n < d_n; ++n) {
        for (int m = 0; m < d_m; ++m) {
            if (guard[size_t(m)])
                continue;
            const int k = pilot_at[size_t(n) * d_m + m];
            if (k >= 0) {
                d_pilot_cols[size_t(n)].push_back(m);
                d_pilot_index[size_t(n)].push_back(k);
            } else {
                d_data_cols[size_t(n)].push_back(m);
            }
        }
        d_data_before_row[size_t(n) + 1] = d_data_before_row[size_t(n)] + long(d_data_cols[size_t(n)].size());
    }
    d_data_per_frame = int(d_data_before_row[size_t(d_n)]);
    latch(pilot_power, data_power);
    if (d_data_per_frame > 0)
        set_relative_rate(uint64_t(d_n), uint64_t(d_data_per_frame));
    set_tag_propagation_policy(TPP_DONT); // data-symbol tags are moved by hand
    d_tags.reserve(64);
}

void mimo_pilot_mapper_impl::latch(double pilot_energy, double data_energy)
{
    const int np = d_mask.mask().size();
    for (int j = 0; j < d_nt; ++j)
        for (int k = 0; k < np; ++k)
            d_values[size_t(j) * np + k] = float(d_mask.amplitude(k, j) * std::sqrt(pilot_energy)) *
                                           d_mask.mask().transmitted_pilot(k);
    d_data_amp = float(std::sqrt(data_energy / d_nt));
}

void mimo_pilot_mapper_impl::set_pilot_power(double energy)
{
    check_power(who, "pilot_power", energy);
    d_pilot_power = energy;
}

double mimo_pilot_mapper_impl::pilot_power() const { return d_pilot_power; }

void mimo_pilot_mapper_impl::set_data_power(double energy)
{
    check_power(who, "data_power", energy);
    d_data_power = energy;
}

double mimo_pilot_mapper_impl::data_power() const { return d_data_power; }

bool mimo_pilot_mapper_impl::check_topology(int ninputs, int)
{
    if (ninputs == 0 && d_data_per_frame > 0)
        throw std::invalid_argument(std::string(who) + ": the mask leaves " + std::to_string(d_data_per_frame) +
                                    " data positions per frame, so the data input must be connected");
    return true;
}

void mimo_pilot_mapper_impl::forecast(int noutput_items, gr_vector_int& ninput_items_required)
{
    if (ninput_items_required.empty())
        return;
    // The data the next noutput_items rows take, from the current row on.
    long rows = noutput_items;
    const long here = std::min<long>(rows, d_n - d_row);
    long need = d_data_before_row[size_t(d_row + here)] - d_data_before_row[size_t(d_row)];
    rows -= here;
    need += (rows / d_n) * d_data_per_frame + d_data_before_row[size_t(rows % d_n)];
    ninput_items_required[0] = int(need);
}

int mimo_pilot_mapper_impl::general_work(int noutput_items,
                                         gr_vector_int& ninput_items,
                                         gr_vector_const_void_star& input_items,
                                         gr_vector_void_star& output_items)
{
    const bool has_input = !input_items.empty();
    const auto* in = has_input ? static_cast<const gr_complex*>(input_items[0]) : nullptr;
    const int avail = has_input ? ninput_items[0] : 0;
    const uint64_t nread = has_input ? nitems_read(0) : 0;
    const uint64_t nwritten = nitems_written(0); // every output moves together
    const int np = d_mask.mask().size();
    if (has_input)
        get_tags_in_range(d_tags, 0, nread, nread + uint64_t(avail));
    size_t next_tag = 0;

    int consumed = 0, produced = 0;
    while (produced < noutput_items) {
        const auto& data_cols = d_data_cols[size_t(d_row)];
        const int need = int(data_cols.size());
        if (consumed + need > avail)
            break;
        if (d_row == 0) { // frame start: latch the powers for the whole frame, tag it on every element
            latch(d_pilot_power.load(), d_data_power.load());
            for (int j = 0; j < d_nt; ++j)
                add_item_tag(j, nwritten + produced, d_frame_key, pmt::from_uint64(d_frame));
            ++d_frames;
        }
        const auto& pilot_cols = d_pilot_cols[size_t(d_row)];
        const auto& pilot_index = d_pilot_index[size_t(d_row)];
        const gr_complex* data = in + consumed;
        for (int j = 0; j < d_nt; ++j) {
            gr_complex* row = static_cast<gr_complex*>(output_items[size_t(j)]) + size_t(produced) * d_m;
            for (int m : d_guard_cols)
                row[m] = gr_complex(0.0f, 0.0f);
            for (size_t i = 0; i < pilot_cols.size(); ++i)
                row[pilot_cols[i]] = d_values[size_t(j) * np + size_t(pilot_index[i])];
            for (int k = 0; k < need; ++k)
                row[data_cols[size_t(k)]] = d_data_amp * data[k];
        }
        const uint64_t used_end = nread + uint64_t(consumed + need);
        move_data_tags(d_tags, next_tag, used_end, d_frame_key, [&](const gr::tag_t& t) {
            for (int j = 0; j < d_nt; ++j)
                add_item_tag(j, nwritten + produced, t.key, t.value, t.srcid);
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
