// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the Wiener phase of a free-running oscillator (see phase_noise.h). */
#include "core/common/checks.h"
#include "core/common/math_constants.h"
#include "core/kernels/rng.h"
#include <gnuradio/sems/core/radio/phase_noise.h>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

namespace {
using checks::text;
} // namespace

double phase_diffusion_from_dbc(double dbc_hz, double offset_hz)
{
    if (!checks::finite(dbc_hz))
        throw std::invalid_argument("phase noise: dbc_hz must be finite, got " + text(dbc_hz));
    if (!checks::positive(offset_hz))
        throw std::invalid_argument("phase noise: offset_hz must be positive and finite, got " + text(offset_hz));
    return 4.0 * pi * pi * offset_hz * offset_hz * std::pow(10.0, dbc_hz / 10.0);
}

double phase_noise_dbc(double diffusion_rad2_per_s, double offset_hz)
{
    if (!checks::positive(offset_hz))
        throw std::invalid_argument("phase noise: offset_hz must be positive and finite, got " + text(offset_hz));
    return 10.0 * std::log10(diffusion_rad2_per_s / (4.0 * pi * pi * offset_hz * offset_hz));
}

struct phase_noise_process::impl {
    explicit impl(uint64_t seed) : r(seed) {}
    rng r;
};

phase_noise_process::phase_noise_process(double diffusion_rad2_per_s, double sample_rate_hz, uint64_t seed)
    : d_diffusion(diffusion_rad2_per_s)
{
    if (!checks::non_negative(diffusion_rad2_per_s))
        throw std::invalid_argument("phase noise: diffusion_rad2_per_s must be finite and >= 0, got " +
                                    text(diffusion_rad2_per_s));
    if (!checks::positive(sample_rate_hz))
        throw std::invalid_argument("phase noise: sample_rate_hz must be positive and finite, got " +
                                    text(sample_rate_hz));
    d_var = diffusion_rad2_per_s / sample_rate_hz;
    d_sigma = std::sqrt(d_var);
    d = std::make_unique<impl>(seed);
}

phase_noise_process::~phase_noise_process() = default;
phase_noise_process::phase_noise_process(phase_noise_process&&) noexcept = default;
phase_noise_process& phase_noise_process::operator=(phase_noise_process&&) noexcept = default;

double phase_noise_process::next()
{
    if (d_n++ > 0) // φ[0] = 0
        d_phase += d_sigma * d->r.normal();
    return d_phase;
}

void phase_noise_process::generate(gr_complex* out, size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        const double p = next();
        out[i] = gr_complex(static_cast<float>(std::cos(p)), static_cast<float>(std::sin(p)));
    }
}

} // namespace sems
} // namespace gr
