// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: OMP delay estimator on a joint delay–Doppler grid. See omp_delay_estimator.h. */
#include "baselines/pilot_observations.h"
#include <gnuradio/sems/baselines/multipath_fit.h>
#include <gnuradio/sems/baselines/omp_delay_estimator.h>

namespace gr {
namespace sems {

using namespace baseline;

struct omp_delay_estimator::impl {
    frame_settings fs;
    int np;
    settings s;
    std::vector<double> grid, dop;
    std::vector<int> m_of, n_of;
    symbol_groups groups;
    Eigen::MatrixXcd ac; // N_p x Q
    Eigen::MatrixXcd bc; // F x G
    std::unique_ptr<multipath_fitter> fitter; // when refining

    Eigen::VectorXcd atom(int q, int f) const
    {
        Eigen::VectorXcd a(np);
        for (int k = 0; k < np; ++k)
            a[k] = std::conj(ac(k, q)) * std::conj(bc(f, groups.of_pilot[k]));
        return a;
    }
};

omp_delay_estimator::omp_delay_estimator(const frame_settings& fs, const pilot_mask& mask)
    : omp_delay_estimator(fs, mask, settings{})
{
}

omp_delay_estimator::omp_delay_estimator(const frame_settings& fs, const pilot_mask& mask, settings s)
    : d_impl(new impl)
{
    const std::string who = "OMP delay estimator";
    check_mask(fs, mask, who);
    s.search.validate(fs, who);
    if (s.doppler_oversample < 1 || s.doppler_oversample > 64)
        throw std::invalid_argument(who + ": doppler_oversample must be in [1, 64]");
    if (s.n_atoms < 1 || s.n_atoms > mask.size())
        throw std::invalid_argument(who + ": n_atoms must be in [1, N_p = " + std::to_string(mask.size()) +
                                    "], got " + std::to_string(s.n_atoms));
    if (!(s.relative_power > 0.0 && s.relative_power <= 1.0))
        throw std::invalid_argument(who + ": relative_power must be in (0, 1]");
    auto& d = *d_impl;
    d.fs = fs;
    d.np = mask.size();
    d.s = s;
    d.grid = s.search.grid(fs);
    d.dop = doppler_grid(fs, s.doppler_oversample);
    d.groups = group_by_symbol(mask);
    const auto& pos = mask.positions();
    d.ac.resize(d.np, d.grid.size());
    for (int k = 0; k < d.np; ++k)
        for (size_t q = 0; q < d.grid.size(); ++q)
            d.ac(k, q) = std::conj(delay_phasor(pos[k].m, d.grid[q], fs.n_subcarriers));
    d.bc.resize(d.dop.size(), d.groups.symbols.size());
    for (size_t f = 0; f < d.dop.size(); ++f)
        for (size_t g = 0; g < d.groups.symbols.size(); ++g)
            d.bc(f, g) = std::conj(doppler_phasor(d.groups.symbols[g], d.dop[f], fs.symbol_interval_s));
    if (s.refine)
        d.fitter = std::make_unique<multipath_fitter>(fs, mask);
}

omp_delay_estimator::~omp_delay_estimator() = default;
omp_delay_estimator::omp_delay_estimator(omp_delay_estimator&&) noexcept = default;

std::vector<omp_atom> omp_delay_estimator::decompose(const gr_complex* obs) const
{
    const auto& d = *d_impl;
    const Eigen::VectorXcd r = observations(obs, d.np, "OMP delay estimator");
    Eigen::VectorXcd res = r;
    const int g = static_cast<int>(d.groups.symbols.size());
    std::vector<std::pair<int, int>> chosen; // (q, f)
    Eigen::MatrixXcd phi(d.np, 0);
    Eigen::VectorXcd coef;
    for (int it = 0; it < d.s.n_atoms; ++it) {
        if (res.squaredNorm() <= 1e-30 * std::max(1e-300, r.squaredNorm()))
            break; // explained exactly: more atoms would only fit round-off
        // Correlations with every (τ, ν) atom, factored: per-symbol delay sums, then Doppler.
        Eigen::MatrixXcd u = Eigen::MatrixXcd::Zero(g, d.ac.cols());
        for (int k = 0; k < d.np; ++k)
            u.row(d.groups.of_pilot[k]) += res[k] * d.ac.row(k);
        const Eigen::MatrixXd c = (d.bc * u).cwiseAbs2(); // all atoms have norm √N_p
        Eigen::Index f, q;
        c.maxCoeff(&f, &q);
        chosen.emplace_back(static_cast<int>(q), static_cast<int>(f));
        phi.conservativeResize(Eigen::NoChange, phi.cols() + 1);
        phi.col(phi.cols() - 1) = d.atom(static_cast<int>(q), static_cast<int>(f));
        coef = phi.colPivHouseholderQr().solve(r);
        res = r - phi * coef;
    }
    std::vector<omp_atom> out;
    for (size_t i = 0; i < chosen.size(); ++i)
        out.push_back({ d.grid[chosen[i].first], d.dop[chosen[i].second],
                        gr_complex(static_cast<float>(coef[i].real()), static_cast<float>(coef[i].imag())) });
    return out;
}

std::vector<omp_atom> omp_delay_estimator::refined_atoms(const gr_complex* obs) const
{
    auto atoms = decompose(obs);
    if (!d_impl->fitter || atoms.empty())
        return atoms;
    std::vector<double> tau;
    const omp_atom* strongest = &atoms.front();
    for (const auto& a : atoms) {
        tau.push_back(a.delay_index);
        if (std::norm(a.gain) > std::norm(strongest->gain))
            strongest = &a;
    }
    // The fitter counts slow time from the mask's first pilot symbol, OMP from symbol 0:
    // the same ν, a different common phase (absorbed by the gains).
    const auto fit = d_impl->fitter->refine(obs, tau, strongest->doppler_hz);
    std::vector<omp_atom> out;
    for (size_t i = 0; i < fit.delay_index.size(); ++i)
        out.push_back({ fit.delay_index[i], fit.doppler_hz, fit.gain[i] });
    return out;
}

double omp_delay_estimator::estimate_index(const gr_complex* obs) const
{
    const auto atoms = refined_atoms(obs);
    if (atoms.empty())
        return d_impl->grid.front(); // an all-zero frame: nothing to find
    double pmax = 0.0;
    for (const auto& a : atoms)
        pmax = std::max(pmax, double(std::norm(a.gain)));
    double best = std::numeric_limits<double>::infinity();
    for (const auto& a : atoms)
        if (std::norm(a.gain) >= d_impl->s.relative_power * pmax)
            best = std::min(best, a.delay_index);
    return best;
}

int omp_delay_estimator::n_pilots() const { return d_impl->np; }

double omp_delay_estimator::estimate_delay_s(const gr_complex* obs) const
{
    return estimate_index(obs) / d_impl->fs.bandwidth_hz;
}

} // namespace sems
} // namespace gr
