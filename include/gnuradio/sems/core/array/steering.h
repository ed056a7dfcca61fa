// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The steering phasors of the grid model and the Doppler search grid: the one place
 *        the channel model, the delay decoder's dictionary and the classical baselines take
 *        them from (docs/design.md §1).
 *
 * \details H[n,m] = Σ_l α_l · exp(-j2π m Δf τ_l) · exp(j2π ν_l n T) · ...: the first factor is
 * delay_phasor(), the second doppler_phasor(). Phases are reduced to one cycle in double
 * precision before the sine and cosine, so a phase after 10^12 symbols is as exact as after one.
 */
#ifndef INCLUDED_SEMS_CORE_STEERING_H
#define INCLUDED_SEMS_CORE_STEERING_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <cmath>
#include <complex>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief exp(j·2π·cycles), with the whole cycles removed in double precision first.
 * \param cycles the phase in cycles (any magnitude).
 * \return the unit phasor.
 */
inline std::complex<double> cis_cycles(double cycles)
{
    const double frac = cycles - std::floor(cycles);
    return { std::cos(2.0 * M_PI * frac), std::sin(2.0 * M_PI * frac) };
}

/*!
 * \brief The delay steering phasor of subcarrier m: exp(-j2π m Δf τ) = exp(-j2π m·index/M).
 * \param m subcarrier index (0..M-1).
 * \param delay_index the delay as a delay index τ·B (any real value; periodic in M).
 * \param n_subcarriers M.
 * \return the phasor.
 */
inline std::complex<double> delay_phasor(double m, double delay_index, int n_subcarriers)
{
    return cis_cycles(-m * delay_index / n_subcarriers);
}

/*!
 * \brief The Doppler phasor of symbol n: exp(j2π ν n T).
 * \param n symbol index (slow time; may be an absolute stream index).
 * \param doppler_hz ν.
 * \param symbol_interval_s T.
 * \return the phasor.
 */
inline std::complex<double> doppler_phasor(double n, double doppler_hz, double symbol_interval_s)
{
    return cis_cycles(doppler_hz * symbol_interval_s * n);
}

/*!
 * \brief The Doppler search grid over the unambiguous [-1/(2T), 1/(2T)).
 * \details oversample·N points, step 1/(oversample·N·T), point q at (q - F/2)/(F·T) with F = oversample·N.
 * \param fs the frame (N, T).
 * \param oversample grid points per Doppler resolution cell 1/(N·T); >= 1.
 * \return the grid in Hz, ascending.
 * \throws std::invalid_argument if oversample < 1.
 */
SEMS_API std::vector<double> doppler_grid(const frame_settings& fs, int oversample);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_STEERING_H */
