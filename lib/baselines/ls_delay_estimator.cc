// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the oracle-order least-squares multipath delay reference. See ls_delay_estimator.h. */
#include "baselines/pilot_observations.h"
#include <gnuradio/sems/baselines/ls_delay_estimator.h>

namespace gr {
namespace sems {

using namespace baseline;

struct ls_delay_estimator::impl {
    int np = 0;
    settings s;
    std::vector<double> grid, dop;
    symbol_groups groups;
    std::vector<double> rel_symbol; // per group: symbol index relative to the first pilot symbol
    double t_sym = 1.0;
    Eigen::MatrixXcd a; // N_p x Q: a(m_k; τ_q)
    std::unique_ptr<multipath_fitter> fitter;

    // The grid delays minimising ‖P⊥ z‖² one coordinate at a time (see the header).
    multipath_fit search(const Eigen::VectorXcd& y) const
    {
        const int q_count = static_cast<int>(grid.size());
        double nu = 0.0;
        const int g_count = static_cast<int>(groups.symbols.size());
        if (g_count > 1) {
            Eigen::MatrixXcd u = Eigen::MatrixXcd::Zero(g_count, q_count);
            for (int k = 0; k < np; ++k)
                u.row(groups.of_pilot[k]) += y[k] * a.row(k).conjugate();
            double best = -1.0;
            for (double f : dop) {
                Eigen::RowVectorXcd c = Eigen::RowVectorXcd::Zero(q_count);
                for (int g = 0; g < g_count; ++g)
                    c += std::conj(doppler_phasor(rel_symbol[g], f, t_sym)) * u.row(g);
                const double v = c.cwiseAbs2().maxCoeff();
                if (v > best) {
                    best = v;
                    nu = f;
                }
            }
        }
        Eigen::VectorXcd z(np); // Doppler removed
        for (int k = 0; k < np; ++k)
            z[k] = y[k] * std::conj(doppler_phasor(rel_symbol[groups.of_pilot[k]], nu, t_sym));
        std::vector<int> chosen;
        Eigen::VectorXcd res = z;
        for (int l = 0; l < s.n_paths; ++l) {
            Eigen::Index q;
            (a.adjoint() * res).cwiseAbs2().maxCoeff(&q);
            chosen.push_back(static_cast<int>(q));
            Eigen::MatrixXcd phi(np, chosen.size());
            for (size_t i = 0; i < chosen.size(); ++i)
                phi.col(i) = a.col(chosen[i]);
            res = z - phi * phi.colPivHouseholderQr().solve(z);
        }
        for (int sw = 0; sw < s.sweeps && s.n_paths > 1; ++sw)
            for (int l = 0; l < s.n_paths; ++l) {
                Eigen::MatrixXcd ao(np, s.n_paths - 1);
                for (int i = 0, c = 0; i < s.n_paths; ++i)
                    if (i != l)
                        ao.col(c++) = a.col(chosen[i]);
                const auto qr = ao.colPivHouseholderQr();
                const Eigen::MatrixXcd pa = a - ao * qr.solve(a);
                const Eigen::VectorXcd pz = z - ao * qr.solve(z);
                const Eigen::RowVectorXd num = (pz.adjoint() * pa).cwiseAbs2();
                const Eigen::RowVectorXd den = pa.colwise().squaredNorm();
                int best = chosen[l];
                double bv = -1.0;
                for (int q = 0; q < q_count; ++q)
                    if (den[q] > 1e-9 * np && num[q] / den[q] > bv) {
                        bv = num[q] / den[q];
                        best = q;
                    }
                chosen[l] = best;
            }
        multipath_fit f;
        for (int q : chosen)
            f.delay_index.push_back(grid[q]);
        f.doppler_hz = nu;
        return f;
    }
};

ls_delay_estimator::ls_delay_estimator(const frame_settings& fs, const pilot_mask& mask)
    : ls_delay_estimator(fs, mask, settings{})
{
}

ls_delay_estimator::ls_delay_estimator(const frame_settings& fs, const pilot_mask& mask, settings s)
    : d_impl(new impl)
{
    const std::string who = "LS delay estimator";
    check_mask(fs, mask, who);
    s.search.validate(fs, who);
    if (s.doppler_oversample < 1 || s.doppler_oversample > 64)
        throw std::invalid_argument(who + ": doppler_oversample must be in [1, 64], got " +
                                    std::to_string(s.doppler_oversample));
    if (s.n_paths < 1 || s.n_paths > mask.size())
        throw std::invalid_argument(who + ": n_paths must be in [1, N_p = " + std::to_string(mask.size()) + "], got " +
                                    std::to_string(s.n_paths));
    if (s.sweeps < 0)
        throw std::invalid_argument(who + ": sweeps must be >= 0, got " + std::to_string(s.sweeps));
    auto& d = *d_impl;
    d.np = mask.size();
    d.s = s;
    d.grid = s.search.grid(fs);
    d.dop = doppler_grid(fs, s.doppler_oversample);
    d.groups = group_by_symbol(mask);
    for (int n : d.groups.symbols)
        d.rel_symbol.push_back(n - d.groups.symbols.front());
    d.t_sym = fs.symbol_interval_s;
    const auto& pos = mask.positions();
    d.a.resize(d.np, d.grid.size());
    for (int k = 0; k < d.np; ++k)
        for (size_t q = 0; q < d.grid.size(); ++q)
            d.a(k, q) = delay_phasor(pos[k].m, d.grid[q], fs.n_subcarriers);
    d.fitter = std::make_unique<multipath_fitter>(fs, mask, s.fit);
}

ls_delay_estimator::~ls_delay_estimator() = default;
ls_delay_estimator::ls_delay_estimator(ls_delay_estimator&&) noexcept = default;

int ls_delay_estimator::n_pilots() const { return d_impl->np; }

multipath_fit ls_delay_estimator::grid_search(const gr_complex* obs) const
{
    return d_impl->search(observations(obs, d_impl->np, "LS delay estimator"));
}

multipath_fit ls_delay_estimator::fit(const gr_complex* obs) const
{
    const auto start = grid_search(obs);
    return d_impl->fitter->refine(obs, start.delay_index, start.doppler_hz);
}

double ls_delay_estimator::estimate_index(const gr_complex* obs) const { return fit(obs).delay_index.front(); }

} // namespace sems
} // namespace gr
