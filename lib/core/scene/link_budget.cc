// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a scene's link budget — the radar equation per resource element (link_budget.h). */
#include "core/common/checks.h"
#include "core/common/json_object.h"
#include <gnuradio/sems/core/scene/link_budget.h>
#include <cmath>
#include <tuple>

namespace gr {
namespace sems {

using json = nlohmann::json;
using json_read::fail;
using json_read::object_reader;

double link_budget::snr_db(const frame_settings& fs, double range_m, double rcs_dbsm) const
{
    const double lambda = fs.wavelength_m();
    const double four_pi = 4.0 * M_PI;
    // dB terms of P_t G_t G_r λ² σ / ((4π)³ R⁴ k T_0 F B L), P_t from dBm to dBW
    return (tx_power_dbm - 30.0) + tx_gain_dbi + rx_gain_dbi + 20.0 * std::log10(lambda) + rcs_dbsm -
           30.0 * std::log10(four_pi) - 40.0 * std::log10(range_m) -
           10.0 * std::log10(boltzmann_j_per_k * noise_temperature_k) - noise_figure_db -
           10.0 * std::log10(fs.bandwidth_hz) - system_loss_db;
}

void link_budget::validate(const std::string& source, const std::string& field) const
{
    auto finite = [&](double v, const char* key) {
        if (!checks::finite(v))
            fail(source, field + "." + key, "must be a finite number, got " + std::to_string(v));
    };
    finite(tx_power_dbm, "tx_power_dbm");
    finite(tx_gain_dbi, "tx_gain_dbi");
    finite(rx_gain_dbi, "rx_gain_dbi");
    if (!checks::non_negative(noise_figure_db))
        fail(source, field + ".noise_figure_db", "must be >= 0 dB (a receiver adds noise), got " + std::to_string(noise_figure_db));
    if (!checks::non_negative(system_loss_db))
        fail(source, field + ".system_loss_db", "must be >= 0 dB (a loss), got " + std::to_string(system_loss_db));
    if (!checks::positive(noise_temperature_k))
        fail(source, field + ".noise_temperature_k", "must be > 0 K, got " + std::to_string(noise_temperature_k));
}

json link_budget::to_json() const
{
    return { { "tx_power_dbm", tx_power_dbm },       { "tx_gain_dbi", tx_gain_dbi },
             { "rx_gain_dbi", rx_gain_dbi },         { "noise_figure_db", noise_figure_db },
             { "system_loss_db", system_loss_db },   { "noise_temperature_k", noise_temperature_k } };
}

link_budget link_budget::from_json(const json& j, const std::string& source, const std::string& field)
{
    object_reader r(j, source, field);
    const link_budget d;
    link_budget b;
    b.tx_power_dbm = r.number_or("tx_power_dbm", d.tx_power_dbm);
    b.tx_gain_dbi = r.number_or("tx_gain_dbi", d.tx_gain_dbi);
    b.rx_gain_dbi = r.number_or("rx_gain_dbi", d.rx_gain_dbi);
    b.noise_figure_db = r.number_or("noise_figure_db", d.noise_figure_db);
    b.system_loss_db = r.number_or("system_loss_db", d.system_loss_db);
    b.noise_temperature_k = r.number_or("noise_temperature_k", d.noise_temperature_k);
    r.finish();
    b.validate(source, field);
    return b;
}

bool operator==(const link_budget& a, const link_budget& b)
{
    return std::tie(a.tx_power_dbm, a.tx_gain_dbi, a.rx_gain_dbi, a.noise_figure_db, a.system_loss_db, a.noise_temperature_k) ==
           std::tie(b.tx_power_dbm, b.tx_gain_dbi, b.rx_gain_dbi, b.noise_figure_db, b.system_loss_db, b.noise_temperature_k);
}

} // namespace sems
} // namespace gr
