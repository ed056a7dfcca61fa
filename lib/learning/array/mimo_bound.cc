// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the azimuth bound of a MIMO mask over the grid's weights (see mimo_bound.h). */
#include "learning/array/mimo_bound.h"
#include <gnuradio/sems/core/array/steering.h>
#include <cmath>
#include <complex>

namespace gr {
namespace sems {
namespace nn {

mimo_steering mimo_steering_tables(const array_geometry& a, const frame_settings& fs, const std::vector<double>& az,
                                   double el)
{
    const int d = int(az.size()), nr = a.n_receive(), nt = a.n_transmit(), m = fs.n_subcarriers;
    const auto off = a.virtual_offsets();
    mimo_steering t;
    for (auto* x : { &t.ar, &t.ai, &t.dr, &t.di })
        *x = torch::empty({ d, nr, nt, m }, torch::kDouble);
    double* ar = t.ar.data_ptr<double>();
    double* ai = t.ai.data_ptr<double>();
    double* dr = t.dr.data_ptr<double>();
    double* di = t.di.data_ptr<double>();
    for (int q = 0; q < d; ++q) {
        const position3 u = direction_vector(az[size_t(q)], el);
        const position3 du{ -std::cos(el) * std::sin(az[size_t(q)]), std::cos(el) * std::cos(az[size_t(q)]), 0.0 };
        const double g = element_pattern_amplitude(a.pattern(), u);
        const double dg = a.pattern() == element_pattern::cosine && u[0] > 0.0 ? 2.0 * u[0] * du[0] : 0.0;
        for (int k = 0; k < nr; ++k)
            for (int j = 0; j < nt; ++j) {
                const auto& o = off[size_t(k) * nt + j];
                for (int mm = 0; mm < m; ++mm) {
                    const double f = fs.carrier_hz + mm * fs.subcarrier_spacing_hz();
                    const std::complex<double> p = element_phasor(u, o, speed_of_light_mps / f);
                    const std::complex<double> dp =
                        dg * p + g * p * std::complex<double>(0.0, 2.0 * M_PI * f * projection_m(du, o) / speed_of_light_mps);
                    const size_t i = ((size_t(q) * nr + k) * nt + j) * m + mm;
                    ar[i] = g * p.real();
                    ai[i] = g * p.imag();
                    dr[i] = dp.real();
                    di[i] = dp.imag();
                }
            }
    }
    return t;
}

torch::Tensor mimo_crb_of_weights(const mimo_steering& t, const torch::Tensor& w)
{
    const int64_t n = w.size(1), m = w.size(2);
    const auto s0r = torch::einsum("dkjm,jnm->dknm", { t.ar, w });
    const auto s0i = torch::einsum("dkjm,jnm->dknm", { t.ai, w });
    const auto s1r = torch::einsum("dkjm,jnm->dknm", { t.dr, w });
    const auto s1i = torch::einsum("dkjm,jnm->dknm", { t.di, w });
    const auto p0 = (s0r * s0r + s0i * s0i).sum(1);                // D x N x M
    const auto jpp = (s1r * s1r + s1i * s1i).sum({ 1, 2, 3 });      // D
    const auto x = (s1r * s0r + s1i * s0i).sum(1);                 // D x N x M
    const auto y = (s1r * s0i - s1i * s0r).sum(1);
    const auto opts = torch::TensorOptions().dtype(torch::kDouble);
    const auto cm = (2.0 * M_PI / double(m)) * torch::arange(m, opts).view({ 1, 1, m });
    const auto cn = (2.0 * M_PI / double(n)) * torch::arange(n, opts).view({ 1, n, 1 });
    auto sum = [](const torch::Tensor& v) { return v.sum({ 1, 2 }); };
    const auto b = torch::stack({ sum(cm * y), -sum(cn * y), sum(x), -sum(y) }, 1); // D x 4
    const auto s = sum(p0), sm = sum(cm * p0), sn = sum(cn * p0);
    const auto smm = sum(cm * cm * p0), snn = sum(cn * cn * p0), smn = sum(cm * cn * p0);
    const auto zero = torch::zeros_like(s);
    const auto c = torch::stack({ torch::stack({ smm, -smn, zero, -sm }, 1), torch::stack({ -smn, snn, zero, sn }, 1),
                                  torch::stack({ zero, zero, s, zero }, 1), torch::stack({ -sm, sn, zero, s }, 1) },
                                1); // D x 4 x 4
    // A ridge far below every term keeps the solve defined where a mask leaves a nuisance
    // unidentifiable (all pilots on one symbol: ν), which does not touch φ.
    const auto ridge = 1e-12 * (c.diagonal(0, 1, 2).sum(1) + 1.0).view({ -1, 1, 1 }) *
                       torch::eye(4, opts).unsqueeze(0);
    const auto sol = torch::linalg_solve(c + ridge, b.unsqueeze(2)).squeeze(2);
    const auto schur = jpp - (b * sol).sum(1);
    return 1.0 / (2.0 * schur.clamp_min(1e-300));
}

torch::Tensor mimo_weights(const mimo_mask& m)
{
    const int nt = m.n_transmit(), n = m.mask().n_symbols(), mm = m.mask().n_subcarriers();
    auto w = torch::zeros({ nt, n, mm }, torch::kDouble);
    auto acc = w.accessor<double, 3>();
    for (int i = 0; i < m.mask().size(); ++i) {
        const auto& p = m.mask().positions()[size_t(i)];
        for (int j = 0; j < nt; ++j)
            acc[j][p.n][p.m] = m.amplitude(i, j);
    }
    return w;
}

} // namespace nn
} // namespace sems
} // namespace gr
