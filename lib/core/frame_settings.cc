// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: frame settings validation and JSON. */
#include "core/checks.h"
#include "core/json_object.h"
#include <gnuradio/sems/core/limits.h>
#include <gnuradio/sems/core/frame_settings.h>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {
void require_positive(double v, const char* name)
{
    if (!checks::positive(v))
        throw std::invalid_argument(std::string("frame settings: ") + name +
                                    " must be a positive finite number, got " + std::to_string(v));
}
} // namespace

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
}

nlohmann::json frame_settings::to_json() const
{
    return { { "n_symbols", n_symbols },       { "n_subcarriers", n_subcarriers },
             { "bandwidth_hz", bandwidth_hz }, { "carrier_hz", carrier_hz },
             { "symbol_interval_s", symbol_interval_s }, { "cp_len", cp_len } };
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
    r.finish();
    try {
        fs.validate();
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(source + ": " + e.what());
    }
    return fs;
}

bool frame_settings::operator==(const frame_settings& o) const
{
    return n_symbols == o.n_symbols && n_subcarriers == o.n_subcarriers && bandwidth_hz == o.bandwidth_hz &&
           carrier_hz == o.carrier_hz && symbol_interval_s == o.symbol_interval_s && cp_len == o.cp_len;
}

} // namespace sems
} // namespace gr
