// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: range–angle map of a frame of an array's pilots (see range_angle.h). */
#include <gnuradio/fft/fft.h>
#include <gnuradio/sems/core/array/range_angle.h>
#include <gnuradio/sems/core/array/steering.h>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace gr {
namespace sems {

struct range_angle::plans {
    gr::fft::fft_complex_rev delay; // over m: exp(+j2π m q/M)
    explicit plans(int m) : delay(m, 1) {}
};

namespace {

std::vector<float> subcarrier_window(const std::string& name, int len)
{
    std::vector<float> w(size_t(len), 1.0f);
    if (name == "rect")
        return w;
    if (name != "hann")
        throw std::invalid_argument("range_angle: window must be \"hann\" or \"rect\", got \"" + name + "\"");
    // Periodic Hann, as the range–Doppler map's: an on-bin target stays on its cell.
    for (int k = 0; k < len && len > 1; ++k)
        w[size_t(k)] = 0.5f - 0.5f * static_cast<float>(std::cos(2.0 * M_PI * k / len));
    return w;
}

} // namespace

range_angle::range_angle(const pilot_mask& mask,
                         const array_geometry& array,
                         double wavelength_m,
                         int n_angles,
                         const std::string& window)
    : d_mask(mask),
      d_n(mask.n_symbols()),
      d_m(mask.n_subcarriers()),
      d_np(mask.size()),
      d_k(array.n_receive()),
      d_a(n_angles),
      d_wm(subcarrier_window(window, d_m)),
      d_wsum(std::accumulate(d_wm.begin(), d_wm.end(), 0.0f)),
      d_profile(size_t(d_k) * d_m),
      d_power(size_t(n_angles) * d_m),
      d_plans(std::make_unique<plans>(d_m))
{
    // One transmit element: the pilot extractor's streams are the receive elements', each the
    // sum over the transmit elements (a MIMO array's virtual streams would need each transmit
    // element's pilots apart).
    if (array.n_transmit() != 1)
        throw std::invalid_argument("range_angle: the array has " + std::to_string(array.n_transmit()) +
                                    " transmit elements; the map takes an array with one (the pilot extractor's "
                                    "N_r·N_p observations)");
    if (n_angles < 2 || n_angles > 4096)
        throw std::invalid_argument("range_angle: n_angles must be in [2, 4096], got " + std::to_string(n_angles));
    if (!(std::isfinite(wavelength_m) && wavelength_m > 0.0))
        throw std::invalid_argument("range_angle: wavelength_m must be > 0, got " + std::to_string(wavelength_m));
    d_steer.resize(size_t(d_a) * d_k);
    for (int a = 0; a < d_a; ++a) {
        // w = conj(s)/(‖s‖·sqrt(K)): the pattern's direction is divided out of the weights but
        // not its power (a row where the pattern is weak is not amplified).
        const auto s = steering_vector(array, azimuth_rad(a), 0.0, wavelength_m);
        double norm = 0.0;
        for (const auto& x : s)
            norm += std::norm(x);
        const double scale = norm > 0.0 ? 1.0 / std::sqrt(norm * d_k) : 0.0;
        for (int k = 0; k < d_k; ++k)
            d_steer[size_t(a) * d_k + k] = std::complex<float>(std::conj(s[size_t(k)]) * scale);
    }
}

range_angle::~range_angle() = default;

double range_angle::azimuth_rad(int row) const { return -M_PI / 2 + M_PI * (row + 0.5) / d_a; }

void range_angle::compute(const gr_complex* observations, float* out_db)
{
    std::fill(d_power.begin(), d_power.end(), 0.0f);
    const auto& pos = d_mask.positions(); // mask order: sorted by (n, m)
    auto& fft = d_plans->delay;
    size_t first = 0;
    while (first < pos.size()) {
        const int n = pos[first].n;
        size_t last = first;
        while (last < pos.size() && pos[last].n == n)
            ++last;
        // This symbol's delay profile at every element.
        for (int k = 0; k < d_k; ++k) {
            gr_complex* in = fft.get_inbuf();
            std::fill(in, in + d_m, gr_complex(0.0f, 0.0f));
            for (size_t p = first; p < last; ++p)
                in[pos[p].m] = observations[size_t(k) * d_np + p] * (d_wm[size_t(pos[p].m)] / d_wsum);
            fft.execute();
            std::copy(fft.get_outbuf(), fft.get_outbuf() + d_m, d_profile.data() + size_t(k) * d_m);
        }
        // Beamformed over the elements, its power summed over the symbols.
        for (int a = 0; a < d_a; ++a) {
            const std::complex<float>* w = d_steer.data() + size_t(a) * d_k;
            float* row = d_power.data() + size_t(a) * d_m;
            for (int q = 0; q < d_m; ++q) {
                gr_complex beam(0.0f, 0.0f);
                for (int k = 0; k < d_k; ++k)
                    beam += w[k] * d_profile[size_t(k) * d_m + q];
                row[q] += std::norm(beam);
            }
        }
        first = last;
    }
    const float inv_n = 1.0f / static_cast<float>(d_n);
    for (size_t i = 0; i < d_power.size(); ++i) {
        const float p = d_power[i] * inv_n;
        out_db[i] = p > 0.0f ? std::max(floor_db, 10.0f * std::log10(p)) : floor_db;
    }
}

} // namespace sems
} // namespace gr
