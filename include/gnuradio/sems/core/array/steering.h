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
 *
 * With an array (array_geometry.h) the path in direction u reaches element k (receive element at
 * p_k, transmit element at q_j; o = p_k + q_j) as a plane wave: its carrier phase gains
 * element_phasor(u, o, λ) = exp(j2π u·o/λ) and its delay element_delay_s(u, o) = −u·o/c, which the
 * emulator applies to every subcarrier (the exact plane-wave delay). A decoder or baseline that
 * uses the narrowband steering_vector() alone ignores the second term; its phase error across the
 * band is at most narrowband_phase_error_rad().
 */
#ifndef INCLUDED_SEMS_CORE_STEERING_H
#define INCLUDED_SEMS_CORE_STEERING_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
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

/*!
 * \brief The unit vector of a direction (array_geometry.h's frame: x boresight, y left, z up).
 * \param azimuth_rad φ, from x towards y. \param elevation_rad θ, from the x–y plane towards z.
 * \return (cos θ cos φ, cos θ sin φ, sin θ).
 */
inline position3 direction_vector(double azimuth_rad, double elevation_rad)
{
    const double ce = std::cos(elevation_rad);
    return { ce * std::cos(azimuth_rad), ce * std::sin(azimuth_rad), std::sin(elevation_rad) };
}

/*! \brief u·p. \param u a direction. \param p a position. \return the projection in m. */
inline double projection_m(const position3& u, const position3& p) { return u[0] * p[0] + u[1] * p[1] + u[2] * p[2]; }

/*!
 * \brief THE steering phasor of one element: exp(j2π u·o/λ), the carrier phase a plane wave from
 *        direction u gains at offset o (receive plus transmit element position) over the origin.
 * \param u the direction's unit vector. \param offset o in m. \param wavelength_m λ.
 * \return the phasor.
 */
inline std::complex<double> element_phasor(const position3& u, const position3& offset, double wavelength_m)
{
    return cis_cycles(projection_m(u, offset) / wavelength_m);
}

/*!
 * \brief The plane wave's delay at offset o over the origin: −u·o/c (negative: the element is nearer).
 * \param u the direction's unit vector. \param offset o in m.
 * \return the delay in s.
 */
inline double element_delay_s(const position3& u, const position3& offset)
{
    return -projection_m(u, offset) / speed_of_light_mps;
}

/*!
 * \brief The two-way amplitude of the element pattern (the transmit element's times the receive
 *        element's): 1 for isotropic elements; (u_x)² in front of a cosine element (u_x > 0), 0 behind.
 * \param p the pattern. \param u the direction's unit vector.
 * \return the amplitude.
 */
SEMS_API double element_pattern_amplitude(element_pattern p, const position3& u);

/*!
 * \brief The narrowband steering vector over an array's virtual elements: a[k·N_t + j] =
 *        element_pattern_amplitude · element_phasor(u, p_k + q_j, λ) (receive-element-major).
 * \param a the array. \param azimuth_rad φ. \param elevation_rad θ. \param wavelength_m λ.
 * \return N_r·N_t values.
 */
SEMS_API std::vector<std::complex<double>>
steering_vector(const array_geometry& a, double azimuth_rad, double elevation_rad, double wavelength_m);

/*!
 * \brief The largest phase error of the narrowband steering vector on a frame: the plane-wave
 *        delay −u·o/c that it leaves out turns subcarrier m by 2π m Δf u·o/c, at most
 *        2π (M − 1) Δf · max|o|/c over the band and the virtual elements o = p_k + q_j (reached
 *        at the last subcarrier, by the farthest element, from the direction along it).
 * \param a the array. \param fs the frame.
 * \return the bound in rad (0 for the single-antenna model).
 */
SEMS_API double narrowband_phase_error_rad(const array_geometry& a, const frame_settings& fs);

/*!
 * \brief The wavelength a narrowband steering vector is best taken at for a mask's pilots: at
 *        their mean frequency f_c + m̄Δf (subcarrier m sits at f_c + mΔf). At f_c itself every
 *        angle estimate from those pilots would be off by the band's offset (0.5 % on the paper's
 *        frame). The angle references, the learned position decoder and experiment 9 use it.
 * \param fs the frame. \param mask the pilots.
 * \return c / (f_c + m̄Δf) in m.
 */
SEMS_API double pilot_wavelength_m(const frame_settings& fs, const pilot_mask& mask);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_STEERING_H */
