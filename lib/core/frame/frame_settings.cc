// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: frame settings validation and JSON. */
#include "core/common/checks.h"
#include "core/common/json_object.h"
#include "core/common/named_files.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

#ifndef SEMS_SOURCE_FRAMES_DIR
#define SEMS_SOURCE_FRAMES_DIR ""
#endif
#ifndef SEMS_INSTALLED_FRAMES_DIR
#define SEMS_INSTALLED_FRAMES_DIR ""
#endif

namespace gr {
namespace sems {

namespace {
void require_positive(double v, const char* name)
{
    if (!checks::positive(v))
        throw std::invalid_argument(std::string("frame settings: ") + name +
                                    " must be a positive finite number, got " + std::to_string(v));
}

// A number as text that reads back as the same double (shortest of 15 or 17 digits).
std::string exact_text(double v)
{
    for (int digits : { 15, 17 }) {
        std::ostringstream s;
        s << std::setprecision(digits) << v;
        if (digits == 17 || std::stod(s.str()) == v)
            return s.str();
    }
    return {};
}

// Guards as written in files: single indices, runs of three or more as [first, last].
nlohmann::json guards_to_json(const std::vector<int>& g)
{
    nlohmann::json out = nlohmann::json::array();
    for (size_t i = 0; i < g.size();) {
        size_t j = i;
        while (j + 1 < g.size() && g[j + 1] == g[j] + 1)
            ++j;
        if (j - i >= 2) {
            out.push_back({ g[i], g[j] });
        } else {
            for (size_t k = i; k <= j; ++k)
                out.push_back(g[k]);
        }
        i = j + 1;
    }
    return out;
}

std::string guards_text(const std::vector<int>& g)
{
    return g.empty() ? std::string("none") : guards_to_json(g).dump();
}

} // namespace

bool frame_settings::is_guard(int m) const
{
    return std::binary_search(guard_subcarriers.begin(), guard_subcarriers.end(), m);
}

std::vector<int> frame_settings::usable_subcarriers() const
{
    std::vector<int> out;
    out.reserve(static_cast<size_t>(std::max(0, n_subcarriers)));
    for (int m = 0; m < n_subcarriers; ++m)
        if (!is_guard(m))
            out.push_back(m);
    return out;
}

long long frame_settings::usable_elements() const
{
    return static_cast<long long>(n_symbols) *
           (n_subcarriers - static_cast<long long>(guard_subcarriers.size()));
}

void frame_settings::validate() const
{
    if (n_symbols < 1 || n_symbols > limits::max_symbols)
        throw std::invalid_argument("frame settings: n_symbols must be in [1, " + std::to_string(limits::max_symbols) +
                                    "], got " + std::to_string(n_symbols));
    if (n_subcarriers < 1 || n_subcarriers > limits::max_subcarriers)
        throw std::invalid_argument("frame settings: n_subcarriers must be in [1, " +
                                    std::to_string(limits::max_subcarriers) + "], got " +
                                    std::to_string(n_subcarriers));
    const long long grid = static_cast<long long>(n_symbols) * n_subcarriers;
    if (grid > limits::max_grid)
        throw std::invalid_argument("frame settings: the grid N*M = " + std::to_string(grid) +
                                    " exceeds the limit of " + std::to_string(limits::max_grid) +
                                    " resource elements");
    if (cp_len < 0 || cp_len > n_subcarriers)
        throw std::invalid_argument("frame settings: cp_len must be in [0, n_subcarriers], got " +
                                    std::to_string(cp_len));
    require_positive(bandwidth_hz, "bandwidth_hz");
    require_positive(carrier_hz, "carrier_hz");
    require_positive(symbol_interval_s, "symbol_interval_s");
    for (size_t i = 0; i < guard_subcarriers.size(); ++i) {
        const int m = guard_subcarriers[i];
        if (m < 0 || m >= n_subcarriers)
            throw std::invalid_argument("frame settings: guard_subcarriers: subcarrier " + std::to_string(m) +
                                        " is outside [0, n_subcarriers - 1 = " + std::to_string(n_subcarriers - 1) +
                                        "]");
        if (i > 0 && m == guard_subcarriers[i - 1])
            throw std::invalid_argument("frame settings: guard_subcarriers: subcarrier " + std::to_string(m) +
                                        " is listed twice");
        if (i > 0 && m < guard_subcarriers[i - 1])
            throw std::invalid_argument("frame settings: guard_subcarriers must be ascending, got " +
                                        std::to_string(guard_subcarriers[i - 1]) + " before " + std::to_string(m));
    }
    if (static_cast<int>(guard_subcarriers.size()) >= n_subcarriers)
        throw std::invalid_argument("frame settings: guard_subcarriers: all " + std::to_string(n_subcarriers) +
                                    " subcarriers are guards, none is left for pilots");
}

nlohmann::json frame_settings::to_json() const
{
    nlohmann::json j = { { "n_symbols", n_symbols },       { "n_subcarriers", n_subcarriers },
             { "bandwidth_hz", bandwidth_hz }, { "carrier_hz", carrier_hz },
             { "symbol_interval_s", symbol_interval_s }, { "cp_len", cp_len } };
    // Written only when there are guards: a frame without them reads and writes as before.
    if (!guard_subcarriers.empty())
        j["guard_subcarriers"] = guards_to_json(guard_subcarriers);
    return j;
}

frame_settings frame_settings::from_json(const nlohmann::json& j, const std::string& source)
{
    if (!j.is_object())
        json_read::fail(source, "frame", "expected a JSON object");
    json_read::object_reader r(j, source);
    frame_settings fs;
    fs.n_symbols = r.int_or("n_symbols", fs.n_symbols, 1, limits::max_symbols);
    fs.n_subcarriers = r.int_or("n_subcarriers", fs.n_subcarriers, 1, limits::max_subcarriers);
    fs.cp_len = r.int_or("cp_len", fs.cp_len, 0, limits::max_subcarriers);
    fs.bandwidth_hz = r.number_or("bandwidth_hz", fs.bandwidth_hz);
    fs.carrier_hz = r.number_or("carrier_hz", fs.carrier_hz);
    fs.symbol_interval_s = r.number_or("symbol_interval_s", fs.symbol_interval_s);
    if (const auto* g = r.find("guard_subcarriers")) {
        // Each element: a subcarrier m, or an inclusive run [first, last].
        const std::string field = r.field("guard_subcarriers");
        if (!g->is_array())
            json_read::fail(source, field, "expected a list of subcarriers m and runs [first, last]");
        std::vector<char> seen(static_cast<size_t>(fs.n_subcarriers), 0);
        for (size_t i = 0; i < g->size(); ++i) {
            const auto& e = (*g)[i];
            const std::string where = field + "[" + std::to_string(i) + "]";
            long long lo, hi;
            if (e.is_array()) {
                if (e.size() != 2)
                    json_read::fail(source, where, "a run is [first, last], got " + e.dump());
                lo = json_read::integer_in(e[0], where, source, 0, fs.n_subcarriers - 1);
                hi = json_read::integer_in(e[1], where, source, 0, fs.n_subcarriers - 1);
                if (hi < lo)
                    json_read::fail(source, where, "a run [first, last] needs first <= last, got " + e.dump());
            } else {
                lo = hi = json_read::integer_in(e, where, source, 0, fs.n_subcarriers - 1);
            }
            for (long long m = lo; m <= hi; ++m) {
                if (seen[static_cast<size_t>(m)])
                    json_read::fail(source, where, "subcarrier " + std::to_string(m) + " is listed twice");
                seen[static_cast<size_t>(m)] = 1;
                fs.guard_subcarriers.push_back(static_cast<int>(m));
            }
        }
        std::sort(fs.guard_subcarriers.begin(), fs.guard_subcarriers.end());
    }
    r.finish();
    try {
        fs.validate();
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(source + ": " + e.what());
    }
    return fs;
}

std::optional<frame_difference> frame_settings::first_difference(const frame_settings& o) const
{
    auto num = [](double v) { return exact_text(v); };
    if (n_symbols != o.n_symbols)
        return frame_difference{ "n_symbols", std::to_string(n_symbols), std::to_string(o.n_symbols) };
    if (n_subcarriers != o.n_subcarriers)
        return frame_difference{ "n_subcarriers", std::to_string(n_subcarriers), std::to_string(o.n_subcarriers) };
    if (bandwidth_hz != o.bandwidth_hz)
        return frame_difference{ "bandwidth_hz", num(bandwidth_hz), num(o.bandwidth_hz) };
    if (carrier_hz != o.carrier_hz)
        return frame_difference{ "carrier_hz", num(carrier_hz), num(o.carrier_hz) };
    if (symbol_interval_s != o.symbol_interval_s)
        return frame_difference{ "symbol_interval_s", num(symbol_interval_s), num(o.symbol_interval_s) };
    if (cp_len != o.cp_len)
        return frame_difference{ "cp_len", std::to_string(cp_len), std::to_string(o.cp_len) };
    if (guard_subcarriers != o.guard_subcarriers)
        return frame_difference{ "guard_subcarriers", guards_text(guard_subcarriers),
                                 guards_text(o.guard_subcarriers) };
    return std::nullopt;
}

void frame_settings::require_same(const frame_settings& other,
                                  const std::string& who,
                                  const std::string& mine,
                                  const std::string& theirs) const
{
    if (const auto d = first_difference(other))
        throw std::invalid_argument(who + ": frame field " + d->field + " differs: " + mine + " has " + d->first +
                                    ", " + theirs + " has " + d->second);
}

bool frame_settings::operator==(const frame_settings& o) const { return !first_difference(o).has_value(); }

frame_file frame_file::find(const std::string& name_or_path)
{
    if (name_or_path.empty() || name_or_path == "paper") {
        const std::string builtin_name = "paper";
        // A paper.json on the search path is the same frame; the built-in one needs no file.
        frame_file f;
        f.name = builtin_name;
        f.description = "The paper's frame: 32 symbols x 64 subcarriers, 30 MHz at 3 GHz, T = 1 ms";
        f.classes = "paper";
        f.array = "ula8_3g";
        return f;
    }
    std::string searched;
    const std::string path = detail::find_named_file(name_or_path, "SEMS_FRAMES_PATH", "frames",
                                                     { SEMS_SOURCE_FRAMES_DIR, SEMS_INSTALLED_FRAMES_DIR }, searched);
    if (!path.empty())
        return load(path);
    throw std::invalid_argument("frame \"" + name_or_path + "\": not built in (paper) and no such file (searched " +
                                searched + "; SEMS_FRAMES_PATH adds folders)");
}

frame_file frame_file::load(const std::string& path) { return from_json(json_read::parse_file(path), path); }

frame_file frame_file::from_json(const nlohmann::json& j, const std::string& source)
{
    json_read::check_format(j, format_name, format_version, source);
    json_read::object_reader r(j, source);
    r.allow("format");
    r.allow("version");
    frame_file f;
    f.name = r.string_or("name", "");
    f.description = r.string_or("description", "");
    f.classes = r.string_or("classes", "");
    f.array = r.string_or("array", "");
    f.frame = frame_settings::from_json(r.require("frame"), source + ": frame");
    r.finish();
    return f;
}

nlohmann::json frame_file::to_json() const
{
    nlohmann::json j = { { "format", format_name }, { "version", format_version }, { "name", name } };
    if (!description.empty())
        j["description"] = description;
    if (!classes.empty())
        j["classes"] = classes;
    if (!array.empty())
        j["array"] = array;
    j["frame"] = frame.to_json();
    return j;
}

} // namespace sems
} // namespace gr
