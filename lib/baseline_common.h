/* gr-sems: helpers shared by the classical baselines (internal). */
#ifndef INCLUDED_SEMS_BASELINE_COMMON_H
#define INCLUDED_SEMS_BASELINE_COMMON_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/frame_settings.h>
#include <gnuradio/sems/pilot_mask.h>
#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace baseline {

using cd = std::complex<double>;

// The observations as a double-precision vector; a non-finite value is an error.
inline Eigen::VectorXcd observations(const gr_complex* obs, int n_pilots, const std::string& who)
{
    if (obs == nullptr)
        throw std::invalid_argument(who + ": observations: null pointer");
    Eigen::VectorXcd r(n_pilots);
    for (int k = 0; k < n_pilots; ++k) {
        if (!std::isfinite(obs[k].real()) || !std::isfinite(obs[k].imag()))
            throw std::invalid_argument(who + ": observation " + std::to_string(k) + " is not finite");
        r[k] = cd(obs[k].real(), obs[k].imag());
    }
    return r;
}

// exp(-j2π m Δf τ) with τ given as a delay index (τ·B): the phase is -2π m idx / M.
inline cd delay_phasor(int m, double index, int n_subcarriers)
{
    const double cycles = std::fmod(double(m) * index / n_subcarriers, 1.0);
    return std::polar(1.0, -2.0 * M_PI * cycles);
}

// exp(j2π ν n T).
inline cd doppler_phasor(int n, double doppler_hz, double symbol_interval_s)
{
    const double cycles = std::fmod(doppler_hz * n * symbol_interval_s, 1.0);
    return std::polar(1.0, 2.0 * M_PI * cycles);
}

// Doppler grid over [-1/(2T), 1/(2T)), step 1/(oversample·N·T).
inline std::vector<double> doppler_grid(const frame_settings& fs, int oversample)
{
    const int f = fs.n_symbols * oversample;
    std::vector<double> g(f);
    for (int q = 0; q < f; ++q)
        g[q] = (q - f / 2) / (f * fs.symbol_interval_s);
    return g;
}

// Symbols carrying pilots (sorted) and, per pilot, the index of its symbol in that list.
struct symbol_groups {
    std::vector<int> symbols;
    std::vector<int> of_pilot;
};
inline symbol_groups group_by_symbol(const pilot_mask& mask)
{
    symbol_groups g;
    for (const auto& p : mask.positions()) { // mask order: sorted by (n, m)
        if (g.symbols.empty() || g.symbols.back() != p.n)
            g.symbols.push_back(p.n);
        g.of_pilot.push_back(static_cast<int>(g.symbols.size()) - 1);
    }
    return g;
}

// Vertex of the parabola through (-1, a), (0, b), (1, c), in (-0.5, 0.5).
inline double parabolic_offset(double a, double b, double c)
{
    const double den = a - 2.0 * b + c;
    if (!(den < 0.0))
        return 0.0;
    const double off = 0.5 * (a - c) / den;
    return std::max(-0.5, std::min(0.5, off));
}

inline void check_mask(const frame_settings& fs, const pilot_mask& mask, const std::string& who)
{
    fs.validate();
    mask.check_frame(fs, who);
}

} // namespace baseline
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_BASELINE_COMMON_H */
