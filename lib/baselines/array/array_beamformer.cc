// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: an array's pilots combined into one antenna's (see array_beamformer.h). */
#include <gnuradio/sems/baselines/array_beamformer.h>
#include <gnuradio/sems/core/array/steering.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {

void beamform_pilots(const array_geometry& a, double azimuth_rad, double elevation_rad, double wavelength_m,
                     const gr_complex* y, int snapshots, gr_complex* z)
{
    if (snapshots < 1)
        throw std::invalid_argument("beamform_pilots: snapshots must be >= 1, got " + std::to_string(snapshots));
    const auto s = steering_vector(a, azimuth_rad, elevation_rad, wavelength_m);
    double norm = 0.0;
    for (const auto& x : s)
        norm += std::norm(x);
    if (!(norm > 0.0))
        throw std::invalid_argument("beamform_pilots: the array's steering vector towards azimuth " +
                                    std::to_string(azimuth_rad) + " rad, elevation " + std::to_string(elevation_rad) +
                                    " rad is zero (every element's pattern is null there)");
    const size_t k = s.size(), l = size_t(snapshots);
    for (size_t t = 0; t < l; ++t) {
        std::complex<double> acc = 0.0;
        for (size_t e = 0; e < k; ++e)
            acc += std::conj(s[e]) * std::complex<double>(y[e * l + t]);
        z[t] = gr_complex(acc / norm);
    }
}

namespace {
angle_search front_half_plane(int k)
{
    angle_search s;
    s.min_rad = -M_PI / 2;
    s.max_rad = M_PI / 2;
    s.grid = std::max(256, 8 * k);
    return s;
}
} // namespace

array_beamformer::array_beamformer(const array_geometry& a, double wavelength_m)
    : d_array(a), d_lambda(wavelength_m), d_k(a.n_receive() * a.n_transmit())
{
    if (!(std::isfinite(wavelength_m) && wavelength_m > 0.0))
        throw std::invalid_argument("array_beamformer: wavelength_m must be finite and > 0, got " +
                                    std::to_string(wavelength_m));
    if (d_k > 1)
        d_search = std::make_unique<beamforming_angle_estimator>(a, 0.0, wavelength_m, front_half_plane(d_k));
}

array_beamformer::~array_beamformer() = default;

double array_beamformer::combine(const gr_complex* y, int snapshots, gr_complex* z) const
{
    if (!d_search) {
        for (int t = 0; t < snapshots; ++t)
            if (!std::isfinite(y[t].real()) || !std::isfinite(y[t].imag()))
                throw std::invalid_argument("array_beamformer: pilot " + std::to_string(t) + " is not finite");
        beamform_pilots(d_array, 0.0, 0.0, d_lambda, y, snapshots, z);
        return std::numeric_limits<double>::quiet_NaN();
    }
    const double azimuth = d_search->estimate(y, snapshots, 1).at(0);
    beamform_pilots(d_array, azimuth, 0.0, d_lambda, y, snapshots, z);
    return azimuth;
}

} // namespace sems
} // namespace gr
