// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: variable-projection Levenberg–Marquardt multipath fit. See multipath_fit.h. */
#include "baselines/pilot_observations.h"
#include "core/kernels/complex_mul.h"
#include <gnuradio/sems/baselines/multipath_fit.h>
#include <algorithm>
#include <numeric>

namespace gr {
namespace sems {

using namespace baseline;

namespace {
using detail::mul;
// w^e for an integer e >= 0 by squaring: log2(e) products (a few ulps), instead of a sincos
// per pilot (the table below is cheaper where the exponents are few and small).
inline cd ipow(cd w, int e)
{
    cd r(1.0, 0.0);
    for (; e > 0; e >>= 1, w = mul(w, w))
        if (e & 1)
            r = mul(r, w);
    return r;
}
} // namespace

struct multipath_fitter::impl {
    int np = 0, m_sub = 0;
    settings s;
    std::vector<double> dop; // Doppler grid of the anchored start (Hz)
    // The grid's Doppler phasors at the pilots' symbols: dop_phasor[q·N_p + k] = b(n_k; ν_q).
    // Built once (F·N_p values; a mask too large for that computes them per frame).
    std::vector<cd> dop_phasor;
    std::vector<int> mi, ni; // per pilot: subcarrier and symbol (relative to the first pilot symbol), >= 0
    int max_mi = 0, max_ni = 0;
    bool doppler = false;
    double t_sym = 1.0;
    double half_bin = 0.5; // half a Doppler bin in cycles per symbol: 1 / (2 · symbol span)

    // Φ_kl = b(n_k; ν) a(m_k; τ_l); x = ν·T (cycles per symbol). The pilots' subcarriers and
    // symbols are integers, so a(m_k; τ) = a(1; τ)^m_k and b(n_k; ν) = b(1; ν)^n_k: two
    // phasors from core/array/steering.h per path instead of 2·N_p (the fit's hot loop).
    Eigen::MatrixXcd basis(const std::vector<double>& tau, double x) const
    {
        Eigen::MatrixXcd phi;
        basis_into(phi, tau, x);
        return phi;
    }
    void basis_into(Eigen::MatrixXcd& phi, const std::vector<double>& tau, double x) const
    {
        phi.resize(np, static_cast<Eigen::Index>(tau.size())); // no reallocation at the same size
        const cd b1 = doppler ? cis_cycles(x) : cd(1.0, 0.0);
        cd b_pow[table_size], a_pow[table_size];
        const bool b_table = doppler && powers(b1, max_ni, b_pow);
        for (size_t l = 0; l < tau.size(); ++l) {
            const cd a1 = delay_phasor(1.0, tau[l], m_sub);
            const bool a_table = powers(a1, max_mi, a_pow);
            for (int k = 0; k < np; ++k) {
                const cd a = a_table ? a_pow[mi[k]] : ipow(a1, mi[k]);
                phi(k, l) = doppler ? mul(b_table ? b_pow[ni[k]] : ipow(b1, ni[k]), a) : a;
            }
        }
    }
    // w^0..w^max_e by running products when that is cheaper than a power per pilot and fits
    // the table (max_e + 1 <= table_size, a few ulps per step: ~1e-14 at 256).
    static constexpr int table_size = 256;
    bool powers(cd w, int max_e, cd* out) const
    {
        if (max_e >= table_size || max_e > 4 * np)
            return false;
        out[0] = cd(1.0, 0.0);
        for (int e = 1; e <= max_e; ++e)
            out[e] = mul(out[e - 1], w);
        return true;
    }

    struct state {
        Eigen::MatrixXcd phi;
        Eigen::ColPivHouseholderQR<Eigen::MatrixXcd> qr; // more than one path
        double norm2 = 0.0;                              // one path: ‖φ‖² (= N_p, unit phasors)
        Eigen::VectorXcd alpha, res;
        double cost = 0.0;
        // Least-squares coefficients of b's columns on span(Φ).
        Eigen::MatrixXcd ls(const Eigen::MatrixXcd& b) const
        {
            if (phi.cols() == 1)
                return (phi.adjoint() * b) / norm2;
            return qr.solve(b);
        }
    };
    state solve(const Eigen::VectorXcd& y, const std::vector<double>& tau, double x) const
    {
        state st;
        solve_into(st, y, tau, x);
        return st;
    }
    // The same into st, reusing its buffers (the LM loop's trials).
    void solve_into(state& st, const Eigen::VectorXcd& y, const std::vector<double>& tau, double x) const
    {
        basis_into(st.phi, tau, x);
        if (tau.size() == 1) { // one column: the projection in closed form, no QR
            st.norm2 = st.phi.col(0).squaredNorm();
            st.alpha.resize(1);
            st.alpha[0] = st.phi.col(0).dot(y) / st.norm2; // dot() conjugates its left side
        } else {
            st.qr.compute(st.phi);
            st.alpha = st.qr.solve(y);
        }
        st.res = y;
        st.res.noalias() -= st.phi * st.alpha;
        st.cost = st.res.squaredNorm();
    }

    multipath_fit finish(const state& st, const std::vector<double>& tau, double x, int it) const
    {
        std::vector<size_t> order(tau.size());
        std::iota(order.begin(), order.end(), 0);
        std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return tau[a] < tau[b]; });
        multipath_fit f;
        for (size_t i : order) {
            f.delay_index.push_back(tau[i]);
            f.gain.push_back(gr_complex(static_cast<float>(st.alpha[i].real()), static_cast<float>(st.alpha[i].imag())));
        }
        f.doppler_hz = x / t_sym;
        f.residual = st.cost;
        f.iterations = it;
        return f;
    }

    void check(const gr_complex* obs, const std::vector<double>& tau, const std::string& who) const
    {
        if (tau.empty() || static_cast<int>(tau.size()) > np)
            throw std::invalid_argument(who + ": need 1 to N_p = " + std::to_string(np) + " start delays, got " +
                                        std::to_string(tau.size()));
        for (double t : tau)
            if (!std::isfinite(t))
                throw std::invalid_argument(who + ": a start delay is not finite");
        (void)obs;
    }
};

multipath_fitter::multipath_fitter(const frame_settings& fs, const pilot_mask& mask)
    : multipath_fitter(fs, mask, settings{})
{
}

multipath_fitter::multipath_fitter(const frame_settings& fs, const pilot_mask& mask, settings s) : d_impl(new impl)
{
    const std::string who = "multipath fitter";
    check_mask(fs, mask, who);
    if (s.max_iterations < 1)
        throw std::invalid_argument(who + ": max_iterations must be >= 1, got " + std::to_string(s.max_iterations));
    if (!(s.tolerance > 0.0) || !std::isfinite(s.tolerance))
        throw std::invalid_argument(who + ": tolerance must be finite and > 0");
    auto& d = *d_impl;
    d.np = mask.size();
    d.m_sub = fs.n_subcarriers;
    d.s = s;
    d.t_sym = fs.symbol_interval_s;
    const auto& pos = mask.positions();
    d.mi.resize(d.np);
    d.ni.resize(d.np);
    for (int k = 0; k < d.np; ++k) {
        d.mi[k] = pos[k].m;
        d.ni[k] = pos[k].n - pos.front().n; // a common phase only: keeps the Doppler phases small
        d.max_mi = std::max(d.max_mi, d.mi[k]);
        d.max_ni = std::max(d.max_ni, d.ni[k]);
    }
    d.doppler = pos.front().n != pos.back().n;
    d.half_bin = 0.5 / std::max(1, pos.back().n - pos.front().n + 1);
    d.dop = doppler_grid(fs, 2);
    if (d.doppler && d.dop.size() * size_t(d.np) <= (size_t(1) << 18)) {
        d.dop_phasor.resize(d.dop.size() * size_t(d.np));
        for (size_t q = 0; q < d.dop.size(); ++q)
            for (int k = 0; k < d.np; ++k)
                d.dop_phasor[q * d.np + k] = doppler_phasor(d.ni[k], d.dop[q], d.t_sym);
    }
}

multipath_fitter::~multipath_fitter() = default;
multipath_fitter::multipath_fitter(multipath_fitter&&) noexcept = default;

bool multipath_fitter::doppler_identifiable() const { return d_impl->doppler; }
int multipath_fitter::n_pilots() const { return d_impl->np; }

multipath_fit multipath_fitter::evaluate(const gr_complex* obs, const std::vector<double>& tau, double doppler_hz) const
{
    const auto& d = *d_impl;
    d.check(obs, tau, "multipath fitter");
    const Eigen::VectorXcd y = observations(obs, d.np, "multipath fitter");
    const double x = doppler_hz * d.t_sym;
    return d.finish(d.solve(y, tau, x), tau, x, 0);
}

multipath_fit multipath_fitter::refine_anchored(const gr_complex* obs,
                                                double first,
                                                int n_paths,
                                                double span) const
{
    const auto& d = *d_impl;
    const std::string who = "multipath fitter (anchored)";
    if (n_paths < 1 || n_paths > d.np)
        throw std::invalid_argument(who + ": n_paths must be in [1, N_p = " + std::to_string(d.np) + "], got " +
                                    std::to_string(n_paths));
    if (!std::isfinite(first))
        throw std::invalid_argument(who + ": the first delay is not finite");
    if (!(span > 0.25) || !std::isfinite(span))
        throw std::invalid_argument(who + ": span_index must be finite and > 0.25");
    const Eigen::VectorXcd y = observations(obs, d.np, who);
    std::vector<double> tau{ first };
    double x = 0.0;
    if (d.doppler) { // the Doppler that best explains the first path alone
        const Eigen::MatrixXcd a = d.basis(tau, 0.0);
        Eigen::VectorXcd ay(d.np); // conj(a_k) y_k: the Doppler search correlates it with b(n_k; ν)
        for (int k = 0; k < d.np; ++k)
            ay[k] = std::conj(a(k, 0)) * y[k];
        double best = -1.0;
        for (size_t q = 0; q < d.dop.size(); ++q) {
            const double f = d.dop[q];
            cd c = 0.0;
            if (!d.dop_phasor.empty()) {
                const cd* b = d.dop_phasor.data() + q * d.np;
                for (int k = 0; k < d.np; ++k)
                    c += std::conj(b[k]) * ay[k];
            } else {
                for (int k = 0; k < d.np; ++k)
                    c += std::conj(doppler_phasor(d.ni[k], f, d.t_sym)) * ay[k];
            }
            if (std::norm(c) > best) {
                best = std::norm(c);
                x = f * d.t_sym;
            }
        }
    }
    if (n_paths > 1) {
        std::vector<double> cand;
        for (double t = first + 0.25 + 0.125; t <= first + span + 1e-9; t += 0.125)
            cand.push_back(t);
        const Eigen::MatrixXcd c = d.basis(cand, x); // N_p x C
        for (int l = 1; l < n_paths; ++l) {
            const auto st = d.solve(y, tau, x);
            Eigen::Index q;
            (c.adjoint() * st.res).cwiseAbs2().maxCoeff(&q);
            tau.push_back(cand[q]);
        }
    }
    return refine(obs, tau, x / d.t_sym);
}

multipath_fit multipath_fitter::refine(const gr_complex* obs, const std::vector<double>& start, double doppler_hz) const
{
    const auto& d = *d_impl;
    d.check(obs, start, "multipath fitter");
    const Eigen::VectorXcd y = observations(obs, d.np, "multipath fitter");
    const int L = static_cast<int>(start.size());
    const int P = L + (d.doppler ? 1 : 0);
    std::vector<double> tau = start;
    double x = doppler_hz * d.t_sym;
    auto st = d.solve(y, tau, x);
    // Buffers of the loop, allocated once per fit (the loop runs per frame in the decoders).
    impl::state s2;
    std::vector<double> t2(tau.size());
    Eigen::MatrixXcd dm(d.np, P), g(d.np, P);
    Eigen::VectorXcd mu(d.np);
    Eigen::MatrixXd h(P, P), a(P, P);
    Eigen::VectorXd grad(P), step(P);
    Eigen::LDLT<Eigen::MatrixXd> ldlt(P);
    double lambda = 1e-3;
    int it = 0;
    for (; it < d.s.max_iterations && st.cost > 0.0; ++it) {
        // Kaufman's Jacobian of the model: ∂(Φα)/∂θ with α held, projected off span(Φ).
        mu.noalias() = st.phi * st.alpha;
        for (int l = 0; l < L; ++l)
            for (int k = 0; k < d.np; ++k)
                dm(k, l) = st.alpha[l] * cd(0.0, -2.0 * M_PI * d.mi[k] / d.m_sub) * st.phi(k, l);
        if (d.doppler)
            for (int k = 0; k < d.np; ++k)
                dm(k, L) = cd(0.0, 2.0 * M_PI * d.ni[k]) * mu[k];
        g = dm;
        g.noalias() -= st.phi * st.ls(dm);
        h = (g.adjoint() * g).real();
        grad = (g.adjoint() * st.res).real();
        bool accepted = false;
        double moved = 0.0;
        while (lambda < 1e12) {
            a = h;
            for (int p = 0; p < P; ++p)
                a(p, p) += lambda * std::max(h(p, p), 1e-30);
            step = ldlt.compute(a).solve(grad);
            if (!step.allFinite()) {
                lambda *= 10.0;
                continue;
            }
            // A trust region per step: half a delay index, half a Doppler bin (1/(2·span) cycles per symbol).
            double shrink = 1.0;
            for (int l = 0; l < L; ++l)
                shrink = std::min(shrink, 0.5 / std::max(std::abs(step[l]), 1e-300));
            if (d.doppler)
                shrink = std::min(shrink, d.half_bin / std::max(std::abs(step[L]), 1e-300));
            step *= shrink;
            // Converged: a larger λ only shortens the step, so escalating it further (up to
            // 1e12, one solve per factor 10) would spend ~20 solves to move by less than this.
            if (step.cwiseAbs().maxCoeff() < d.s.tolerance)
                break;
            for (int l = 0; l < L; ++l)
                t2[l] = tau[l] + step[l];
            const double x2 = d.doppler ? x + step[L] : x;
            d.solve_into(s2, y, t2, x2);
            if (s2.cost < st.cost) {
                tau.swap(t2);
                x = x2;
                std::swap(st, s2); // s2 keeps the old buffers for the next trial
                lambda = std::max(lambda / 3.0, 1e-12);
                moved = step.cwiseAbs().maxCoeff();
                accepted = true;
                break;
            }
            lambda *= 10.0;
        }
        if (!accepted || moved < d.s.tolerance)
            break;
    }
    return d.finish(st, tau, x, it);
}

} // namespace sems
} // namespace gr
