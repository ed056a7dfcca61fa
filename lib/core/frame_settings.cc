// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: frame settings validation and JSON. */
#include "core/json_read.h"
#include "core/checks.h"
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
    if (n_symbols < 1)
        throw std::invalid_argument("frame settings: n_symbols must be >= 1, got " + std::to_string(n_symbols));
    if (n_subcarriers < 1)
        throw std::invalid_argument("frame settings: n_subcarriers must be >= 1, got " +
                                    std::to_string(n_subcarriers));
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
    frame_settings fs;
    auto int_field = [&](const char* key, int& out) {
        auto it = j.find(key);
        if (it != j.end())
            out = static_cast<int>(json_read::integer(*it, key, source));
    };
    int_field("n_symbols", fs.n_symbols);
    int_field("n_subcarriers", fs.n_subcarriers);
    int_field("cp_len", fs.cp_len);
    fs.bandwidth_hz = json_read::number_or(j, "bandwidth_hz", fs.bandwidth_hz, source);
    fs.carrier_hz = json_read::number_or(j, "carrier_hz", fs.carrier_hz, source);
    fs.symbol_interval_s = json_read::number_or(j, "symbol_interval_s", fs.symbol_interval_s, source);
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
