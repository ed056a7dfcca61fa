// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: MIMO pilot masks (see mimo_mask.h): the hand forms and the file format. */
#include "core/common/json_object.h"
#include <gnuradio/sems/core/array/mimo_mask.h>
#include <gnuradio/sems/core/common/limits.h>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace gr {
namespace sems {

namespace {

[[noreturn]] void refuse(const std::string& source, const std::string& field, const std::string& problem)
{
    json_read::fail(source, field, problem);
}

// Elements 0, 1, … N_t−1, 0, … over the distinct values of key(pilot), in increasing order.
template <typename Key>
mimo_mask divided(const pilot_mask& mask, int n_transmit, Key key, const char* what, const char* form)
{
    std::map<int, int> rank;
    for (const auto& p : mask.positions())
        rank.emplace(key(p), 0);
    if (n_transmit < 1)
        throw std::invalid_argument(std::string(form) + ": n_transmit must be >= 1, got " + std::to_string(n_transmit));
    if (int(rank.size()) < n_transmit)
        throw std::invalid_argument(std::string(form) + ": the mask's pilots sit on " + std::to_string(rank.size()) + " " +
                                    what + ", fewer than the " + std::to_string(n_transmit) +
                                    " transmit elements (one would send no pilot)");
    int r = 0;
    for (auto& kv : rank)
        kv.second = r++ % n_transmit;
    std::vector<int> tx;
    for (const auto& p : mask.positions())
        tx.push_back(rank[key(p)]);
    return mimo_mask(mask, n_transmit, std::move(tx), form);
}

} // namespace

mimo_mask::mimo_mask(pilot_mask mask, int n_transmit, std::vector<int> transmit, const std::string& source)
    : d_mask(std::move(mask)), d_n_transmit(n_transmit), d_transmit(std::move(transmit))
{
    if (n_transmit < 1 || n_transmit > limits::max_array_elements)
        refuse(source, "n_transmit",
               "must be in [1, " + std::to_string(limits::max_array_elements) + "], got " + std::to_string(n_transmit));
    if (int(d_transmit.size()) != d_mask.size())
        refuse(source, "transmit",
               "has " + std::to_string(d_transmit.size()) + " entries for the mask's " + std::to_string(d_mask.size()) +
                   " pilots (one per pilot, in mask order)");
    for (size_t i = 0; i < d_transmit.size(); ++i)
        if (d_transmit[i] != every_element && (d_transmit[i] < 0 || d_transmit[i] >= n_transmit))
            refuse(source, "transmit[" + std::to_string(i) + "]",
                   "must be a transmit element 0.." + std::to_string(n_transmit - 1) + " or " +
                       std::to_string(every_element) + " (every element), got " + std::to_string(d_transmit[i]));
    if (!d_mask.equal_power())
        refuse(source, "mask.power",
               "a MIMO mask's pilots carry equal energies (each pilot's energy is shared among the elements that send it)");
}

mimo_mask mimo_mask::same_pilots(const pilot_mask& mask, int n_transmit)
{
    return mimo_mask(mask, n_transmit, std::vector<int>(size_t(mask.size()), every_element), "same pilots");
}

mimo_mask mimo_mask::time_division(const pilot_mask& mask, int n_transmit)
{
    return divided(mask, n_transmit, [](const pilot_position& p) { return p.n; }, "symbols", "time division");
}

mimo_mask mimo_mask::frequency_division(const pilot_mask& mask, int n_transmit)
{
    return divided(mask, n_transmit, [](const pilot_position& p) { return p.m; }, "subcarriers", "frequency division");
}

double mimo_mask::amplitude(int k, int j) const
{
    const int t = d_transmit.at(size_t(k));
    if (t == every_element)
        return 1.0 / std::sqrt(double(d_n_transmit));
    return t == j ? 1.0 : 0.0;
}

std::vector<int> mimo_mask::pilots_per_element() const
{
    std::vector<int> out(size_t(d_n_transmit), 0);
    for (int t : d_transmit)
        if (t != every_element)
            ++out[size_t(t)];
    return out;
}

bool mimo_mask::operator==(const mimo_mask& o) const
{
    return d_n_transmit == o.d_n_transmit && d_transmit == o.d_transmit && d_mask == o.d_mask;
}

mimo_mask mimo_mask::from_json(const nlohmann::json& j, const std::string& source)
{
    using namespace json_read;
    check_format(j, format_name, format_version, source);
    object_reader r(j, source);
    r.allow("format");
    r.allow("version");
    r.allow("description");
    const int n_t = r.int_required("n_transmit", 1, limits::max_array_elements);
    const pilot_mask mask = pilot_mask::from_json(r.require("mask"), source + ": mask");
    const auto& t = r.require("transmit");
    if (!t.is_array())
        fail(source, "transmit", "expected a list of transmit elements, one per pilot in mask order");
    std::vector<int> given;
    for (size_t i = 0; i < t.size(); ++i)
        given.push_back(int_in(t[i], "transmit[" + std::to_string(i) + "]", source, every_element, n_t - 1));
    r.finish();
    if (given.size() != size_t(mask.size()))
        fail(source, "transmit",
             "has " + std::to_string(given.size()) + " entries for the mask's " + std::to_string(mask.size()) +
                 " pilots (one per pilot, in the order of mask.pilots)");
    // transmit[i] belongs to mask.pilots[i] as the file lists them; the mask keeps its pilots
    // sorted, so the list follows them there.
    const auto& listed = r.require("mask")["pilots"];
    std::map<std::pair<int, int>, int> of_position;
    for (size_t i = 0; i < listed.size(); ++i)
        of_position[{ listed[i][0].get<int>(), listed[i][1].get<int>() }] = given[i];
    std::vector<int> tx;
    for (const auto& p : mask.positions())
        tx.push_back(of_position.at({ p.n, p.m }));
    return mimo_mask(mask, n_t, std::move(tx), source);
}

mimo_mask mimo_mask::load(const std::string& path) { return from_json(json_read::parse_file(path), path); }

mimo_mask mimo_mask::parse(const std::string& json_text, const std::string& source)
{
    return from_json(json_read::parse_text(json_text, source), source);
}

nlohmann::json mimo_mask::to_json() const
{
    return { { "format", format_name },
             { "version", format_version },
             { "n_transmit", d_n_transmit },
             { "transmit", d_transmit },
             { "mask", d_mask.to_json() } };
}

void mimo_mask::save(const std::string& path) const { json_read::write_file(path, to_json()); }

} // namespace sems
} // namespace gr
