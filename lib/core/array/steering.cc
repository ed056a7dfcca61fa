// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the Doppler search grid, an array's steering vector and its narrowband bound (the
   phasors themselves are inline in core/array/steering.h). */
#include <gnuradio/sems/core/array/steering.h>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

std::vector<double> doppler_grid(const frame_settings& fs, int oversample)
{
    if (oversample < 1)
        throw std::invalid_argument("doppler_grid: oversample must be >= 1, got " + std::to_string(oversample));
    const int f = fs.n_symbols * oversample;
    std::vector<double> g(f);
    for (int q = 0; q < f; ++q)
        g[q] = (q - f / 2) / (f * fs.symbol_interval_s);
    return g;
}

double element_pattern_amplitude(element_pattern p, const position3& u)
{
    if (p == element_pattern::isotropic)
        return 1.0;
    const double c = u[0] > 0.0 ? u[0] : 0.0;
    return c * c;
}

std::vector<std::complex<double>>
steering_vector(const array_geometry& a, double azimuth_rad, double elevation_rad, double wavelength_m)
{
    const position3 u = direction_vector(azimuth_rad, elevation_rad);
    const double g = element_pattern_amplitude(a.pattern(), u);
    std::vector<std::complex<double>> s;
    for (const auto& o : a.virtual_offsets())
        s.push_back(g * element_phasor(u, o, wavelength_m));
    return s;
}

double narrowband_phase_error_rad(const array_geometry& a, const frame_settings& fs)
{
    double reach = 0.0; // the farthest virtual element, max |p_k + q_j|
    for (const auto& o : a.virtual_offsets())
        reach = std::max(reach, std::hypot(o[0], o[1], o[2]));
    return 2.0 * M_PI * (fs.n_subcarriers - 1) * fs.subcarrier_spacing_hz() * reach / speed_of_light_mps;
}

double pilot_wavelength_m(const frame_settings& fs, const pilot_mask& mask)
{
    double mean_m = 0.0;
    for (const auto& p : mask.positions())
        mean_m += double(p.m) / double(mask.size());
    return speed_of_light_mps / (fs.carrier_hz + mean_m * fs.subcarrier_spacing_hz());
}

} // namespace sems
} // namespace gr
