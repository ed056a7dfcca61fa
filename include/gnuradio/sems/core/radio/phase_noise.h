// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief A free-running oscillator's phase noise: a Wiener (random-walk) phase in double
 *        precision, specified by its datasheet point L(f) in dBc/Hz at an offset f.
 *
 * The phase is a Wiener process: φ(t + τ) − φ(t) ~ N(0, D·|τ|), D the phase diffusion in
 * rad²/s. Its oscillator exp(jφ) has the autocorrelation exp(−D|τ|/2), hence the Lorentzian
 * spectrum S(f) = D / (D²/4 + 4π² f²), which beyond its corner D/(4π) is the 1/f² skirt of
 * a free-running oscillator, L(f) = D / (4π² f²). A datasheet point L(f₀) therefore gives
 * D = 4π² f₀² · 10^(L(f₀)/10).
 *
 * Sampled at f_s: φ[0] = 0 and φ[n] = φ[n−1] + w[n], w[n] ~ N(0, D/f_s) independent, so
 * φ[n] − φ[n−k] ~ N(0, k·D/f_s) exactly, and the spectrum of exp(jφ[n]) is the discrete
 * Lorentzian (1 − r²) / (f_s·|1 − r·e^{−j2πf/f_s}|²), r = e^{−D/(2 f_s)}, which equals
 * D/(4π² f²) within 1% for D/(4π) ≪ f ≤ f_s/20.
 */
#ifndef INCLUDED_SEMS_CORE_PHASE_NOISE_H
#define INCLUDED_SEMS_CORE_PHASE_NOISE_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/api.h>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace gr {
namespace sems {

/*!
 * \brief The phase diffusion D of a free-running oscillator from its datasheet point.
 * \param dbc_hz L(f) in dBc/Hz (negative)
 * \param offset_hz the offset f in Hz at which L is quoted (positive)
 * \return D = 4π² f² · 10^(L/10) in rad²/s.
 */
SEMS_API double phase_diffusion_from_dbc(double dbc_hz, double offset_hz);

/*!
 * \brief The single-sideband phase noise of a diffusion D at an offset (the 1/f² skirt).
 * \param diffusion_rad2_per_s D in rad²/s
 * \param offset_hz f in Hz (positive)
 * \return L(f) = 10·log10(D / (4π² f²)) in dBc/Hz.
 */
SEMS_API double phase_noise_dbc(double diffusion_rad2_per_s, double offset_hz);

/*!
 * \brief A sampled Wiener phase: φ[0] = 0, φ[n] = φ[n−1] + N(0, D/f_s), seeded.
 * \details The same seed gives the same phases on every machine (the project's xoshiro256**
 * and Boost's ziggurat), whatever the sizes of the calls that draw them.
 */
class SEMS_API phase_noise_process
{
public:
    /*!
     * \brief An oscillator's phase at a sample rate.
     * \param diffusion_rad2_per_s D in rad²/s (finite, >= 0; 0 = a clean oscillator)
     * \param sample_rate_hz f_s in Hz (positive, finite)
     * \param seed seed of the increments
     * \throws std::invalid_argument naming the parameter and its value.
     */
    phase_noise_process(double diffusion_rad2_per_s, double sample_rate_hz, uint64_t seed = 0);
    ~phase_noise_process(); ///< Destructor.
    /*! \brief Move constructor. */
    phase_noise_process(phase_noise_process&&) noexcept;
    /*! \brief Move assignment. \return *this. */
    phase_noise_process& operator=(phase_noise_process&&) noexcept;

    /*! \brief The phase of the next sample (the first call returns φ[0] = 0). \return φ[n] in rad. */
    double next();
    /*!
     * \brief The oscillator's next samples, exp(jφ[n]) (phase in double, rounded to float at the end).
     * \param out where to write \param count how many samples
     */
    void generate(gr_complex* out, size_t count);
    /*! \brief The per-sample increment's variance. \return D/f_s in rad². */
    double increment_variance() const { return d_var; }
    /*! \brief The phase diffusion. \return D in rad²/s. */
    double diffusion() const { return d_diffusion; }
    /*! \brief Samples drawn so far. \return n, the index of the next sample. */
    uint64_t samples() const { return d_n; }

private:
    struct impl;
    std::unique_ptr<impl> d;
    double d_diffusion;
    double d_var;
    double d_sigma;
    double d_phase = 0.0;
    uint64_t d_n = 0;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_PHASE_NOISE_H */
