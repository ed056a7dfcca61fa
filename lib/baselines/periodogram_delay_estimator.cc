// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: periodogram (matched-filter) delay estimator. See periodogram_delay_estimator.h. */
#include "baselines/pilot_observations.h"
#include <gnuradio/sems/baselines/periodogram_delay_estimator.h>

namespace gr {
namespace sems {

using namespace baseline;

struct periodogram_delay_estimator::impl {
    frame_settings fs;
    int np;
    settings s;
    std::vector<double> grid;
    bool full_window; // the grid covers one whole period: neighbours wrap
    symbol_groups groups;
    Eigen::MatrixXcd ac; // N_p x Q: conj delay steering at the pilots' subcarriers
    Eigen::MatrixXcd bc; // F x G: conj Doppler steering at the pilot symbols

    // P(τ) on the grid.
    Eigen::VectorXd profile(const Eigen::VectorXcd& r) const
    {
        const int g = static_cast<int>(groups.symbols.size());
        Eigen::MatrixXcd u = Eigen::MatrixXcd::Zero(g, ac.cols());
        for (int k = 0; k < np; ++k)
            u.row(groups.of_pilot[k]) += r[k] * ac.row(k);
        if (s.slow_time == slow_time_model::per_symbol)
            return u.cwiseAbs2().colwise().sum().transpose();
        const Eigen::MatrixXcd c = bc * u;
        return c.cwiseAbs2().colwise().maxCoeff().transpose();
    }
};

periodogram_delay_estimator::periodogram_delay_estimator(const frame_settings& fs, const pilot_mask& mask)
    : periodogram_delay_estimator(fs, mask, settings{})
{
}

periodogram_delay_estimator::periodogram_delay_estimator(const frame_settings& fs,
                                                         const pilot_mask& mask,
                                                         settings s)
    : d_impl(new impl)
{
    const std::string who = "periodogram delay estimator";
    check_mask(fs, mask, who);
    s.search.validate(fs, who);
    if (s.doppler_oversample < 1 || s.doppler_oversample > 64)
        throw std::invalid_argument(who + ": doppler_oversample must be in [1, 64]");
    auto& d = *d_impl;
    d.fs = fs;
    d.np = mask.size();
    d.s = s;
    d.grid = s.search.grid(fs);
    d.full_window = std::abs(d.grid.size() - double(fs.n_subcarriers) * s.search.oversample) < 0.5;
    d.groups = group_by_symbol(mask);
    const auto& pos = mask.positions();
    d.ac.resize(d.np, d.grid.size());
    for (int k = 0; k < d.np; ++k)
        for (size_t q = 0; q < d.grid.size(); ++q)
            d.ac(k, q) = std::conj(delay_phasor(pos[k].m, d.grid[q], fs.n_subcarriers));
    const auto dop = doppler_grid(fs, s.doppler_oversample);
    d.bc.resize(dop.size(), d.groups.symbols.size());
    for (size_t f = 0; f < dop.size(); ++f)
        for (size_t g = 0; g < d.groups.symbols.size(); ++g)
            d.bc(f, g) = std::conj(doppler_phasor(d.groups.symbols[g], dop[f], fs.symbol_interval_s));
}

periodogram_delay_estimator::~periodogram_delay_estimator() = default;
periodogram_delay_estimator::periodogram_delay_estimator(periodogram_delay_estimator&&) noexcept = default;

std::vector<double> periodogram_delay_estimator::profile(const gr_complex* obs) const
{
    const auto p = d_impl->profile(observations(obs, d_impl->np, "periodogram delay estimator"));
    return std::vector<double>(p.data(), p.data() + p.size());
}

const std::vector<double>& periodogram_delay_estimator::grid_index() const { return d_impl->grid; }

double periodogram_delay_estimator::estimate_index(const gr_complex* obs) const
{
    const auto& d = *d_impl;
    const Eigen::VectorXd p = d.profile(observations(obs, d.np, "periodogram delay estimator"));
    Eigen::Index q;
    p.maxCoeff(&q);
    const int n = static_cast<int>(p.size());
    double idx = d.grid[q];
    if (d.s.refine && n >= 3) {
        const bool inner = q > 0 && q < n - 1;
        if (inner || d.full_window) {
            const double off = parabolic_offset(p[(q - 1 + n) % n], p[q], p[(q + 1) % n]);
            idx += off / d.s.search.oversample;
            // Keep the answer inside the (periodic) window.
            const double lo = d.grid.front(), period = d.fs.n_subcarriers;
            if (d.full_window) {
                if (idx < lo)
                    idx += period;
                else if (idx >= lo + period)
                    idx -= period;
            }
        }
    }
    return idx;
}

int periodogram_delay_estimator::n_pilots() const { return d_impl->np; }

double periodogram_delay_estimator::estimate_delay_s(const gr_complex* obs) const
{
    return estimate_index(obs) / d_impl->fs.bandwidth_hz;
}

} // namespace sems
} // namespace gr
