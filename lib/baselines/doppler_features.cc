// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: Doppler-spectrum features of the pilots. See doppler_features.h. */
#include "core/common/checks.h"
#include <gnuradio/sems/baselines/doppler_features.h>
#include <gnuradio/sems/core/array/steering.h>
#include <cmath>
#include <map>
#include <stdexcept>

namespace gr {
namespace sems {

std::vector<std::string> doppler_features::names()
{
    return { "mean_hz", "std_hz", "skewness", "kurtosis", "peak_hz", "entropy" };
}

doppler_features::doppler_features(const frame_settings& fs, const pilot_mask& mask, int oversample)
{
    fs.validate();
    mask.check_frame(fs, "doppler features");
    if (oversample < 1 || oversample > 64)
        throw std::invalid_argument("doppler features: oversample must be in [1, 64], got " +
                                    std::to_string(oversample));
    d_np = mask.size();
    d_freq = doppler_grid(fs, oversample);
    const int f = static_cast<int>(d_freq.size());
    std::map<int, int> group_of_m;
    for (const auto& p : mask.positions())
        group_of_m.emplace(p.m, static_cast<int>(group_of_m.size()));
    d_n_groups = static_cast<int>(group_of_m.size());
    for (const auto& p : mask.positions())
        d_group.push_back(group_of_m.at(p.m));
    d_phasor.resize(size_t(f) * d_np);
    for (int q = 0; q < f; ++q)
        for (int k = 0; k < d_np; ++k) {
            // exp(-j2π f n T): the conjugate Doppler phasor of the pilot's symbol.
            d_phasor[size_t(q) * d_np + k] =
                std::conj(doppler_phasor(mask.positions()[k].n, d_freq[q], fs.symbol_interval_s));
        }
}

std::vector<double> doppler_features::spectrum(const gr_complex* obs) const
{
    if (obs == nullptr)
        throw std::invalid_argument("doppler features: observations: null pointer");
    for (int k = 0; k < d_np; ++k)
        if (!checks::finite(obs[k]))
            throw std::invalid_argument("doppler features: observation " + std::to_string(k) + " is not finite");
    const size_t f = d_freq.size();
    std::vector<double> s(f, 0.0);
    std::vector<std::complex<double>> acc(d_n_groups);
    for (size_t q = 0; q < f; ++q) {
        std::fill(acc.begin(), acc.end(), std::complex<double>(0.0, 0.0));
        const std::complex<double>* ph = &d_phasor[q * d_np];
        for (int k = 0; k < d_np; ++k)
            acc[d_group[k]] += std::complex<double>(obs[k]) * ph[k];
        for (const auto& a : acc)
            s[q] += std::norm(a);
    }
    return s;
}

std::vector<double> doppler_features::extract(const gr_complex* obs) const
{
    const auto s = spectrum(obs);
    const size_t f = s.size();
    double total = 0.0;
    for (double v : s)
        total += v;
    std::vector<double> out(n_features, 0.0);
    if (!(total > 0.0))
        return out;
    double mean = 0.0, peak = 0.0, best = -1.0, entropy = 0.0;
    for (size_t q = 0; q < f; ++q) {
        const double p = s[q] / total;
        mean += d_freq[q] * p;
        if (s[q] > best) {
            best = s[q];
            peak = d_freq[q];
        }
        if (p > 0.0)
            entropy -= p * std::log(p);
    }
    double m2 = 0.0, m3 = 0.0, m4 = 0.0;
    for (size_t q = 0; q < f; ++q) {
        const double p = s[q] / total, x = d_freq[q] - mean;
        m2 += x * x * p;
        m3 += x * x * x * p;
        m4 += x * x * x * x * p;
    }
    const double sd = std::sqrt(m2);
    out[0] = mean;
    out[1] = sd;
    // A spectrum narrower than a thousandth of a Doppler bin is a line (what is left is
    // the single-precision leakage of the input): it has no shape, skewness and
    // kurtosis are 0 rather than ratios of round-off.
    const double bin = f > 1 ? d_freq[1] - d_freq[0] : 1.0;
    if (sd > 1e-3 * bin) {
        out[2] = m3 / (sd * sd * sd);
        out[3] = m4 / (m2 * m2);
    }
    out[4] = peak;
    out[5] = f > 1 ? entropy / std::log(double(f)) : 0.0;
    return out;
}

} // namespace sems
} // namespace gr
