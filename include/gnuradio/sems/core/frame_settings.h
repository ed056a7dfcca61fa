// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: OFDM frame settings (DESIGN §1) and the quantities derived from them.
 *
 * The defaults here are the project's only copy of the frame defaults.
 */
#ifndef INCLUDED_SEMS_FRAME_SETTINGS_H
#define INCLUDED_SEMS_FRAME_SETTINGS_H

#include <gnuradio/sems/api.h>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

constexpr double speed_of_light_mps = 3e8; // DESIGN §1 uses c = 3e8 m/s exactly

struct SEMS_API frame_settings {
    int n_symbols = 32;             // N, slow time
    int n_subcarriers = 64;         // M
    double bandwidth_hz = 30e6;     // B
    double carrier_hz = 3e9;        // f_c
    double symbol_interval_s = 1e-3; // T
    int cp_len = 16;                // time-domain path only

    double subcarrier_spacing_hz() const { return bandwidth_hz / n_subcarriers; }
    double wavelength_m() const { return speed_of_light_mps / carrier_hz; }
    // N*M; validate() bounds it by limits::max_grid, and it never overflows: an
    // unvalidated product beyond the int range throws std::invalid_argument.
    int grid_size() const
    {
        const long long g = static_cast<long long>(n_symbols) * n_subcarriers;
        if (g < 0 || g > 2147483647LL)
            throw std::invalid_argument("frame settings: grid N*M = " + std::to_string(g) + " is out of range");
        return static_cast<int>(g);
    }
    // One delay index = 1/B seconds = c/(2B) metres of range.
    double delay_resolution_s() const { return 1.0 / bandwidth_hz; }
    double range_per_delay_index_m() const { return speed_of_light_mps / (2.0 * bandwidth_hz); }
    double max_delay_s() const { return 1.0 / subcarrier_spacing_hz(); } // unambiguous
    double max_range_m() const { return speed_of_light_mps * max_delay_s() / 2.0; }
    double doppler_resolution_hz() const { return 1.0 / (n_symbols * symbol_interval_s); }
    double max_doppler_hz() const { return 1.0 / (2.0 * symbol_interval_s); } // ±, unambiguous
    double max_speed_mps() const { return max_doppler_hz() * wavelength_m() / 2.0; }

    double delay_from_range(double range_m) const { return 2.0 * range_m / speed_of_light_mps; }
    double range_from_delay(double delay_s) const { return delay_s * speed_of_light_mps / 2.0; }
    double delay_index(double delay_s) const { return delay_s * bandwidth_hz; }
    double doppler_from_velocity(double v_mps) const { return 2.0 * v_mps / wavelength_m(); }

    // Throws std::invalid_argument naming the parameter that is out of range.
    void validate() const;

    nlohmann::json to_json() const;
    // Missing keys keep their defaults; `source` names the file or context in errors.
    static frame_settings from_json(const nlohmann::json& j, const std::string& source);

    bool operator==(const frame_settings& o) const;
    bool operator!=(const frame_settings& o) const { return !(*this == o); }
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_FRAME_SETTINGS_H */
