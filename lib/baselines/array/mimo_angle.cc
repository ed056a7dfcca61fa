// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the azimuth bound and maximum-likelihood estimator of a MIMO mask (see mimo_angle.h). */
#include <gnuradio/sems/baselines/mimo_angle.h>
#include <gnuradio/sems/core/array/steering.h>
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace gr {
namespace sems {

namespace {

using cd = std::complex<double>;

std::string mimo_num(double x) { return std::to_string(x); }

void check_mimo_counts(const char* who, const array_geometry& a, const mimo_mask& m)
{
    if (a.n_transmit() != m.n_transmit())
        throw std::invalid_argument(std::string(who) + ": the array has " + std::to_string(a.n_transmit()) +
                                    " transmit elements and the MIMO mask " + std::to_string(m.n_transmit()));
}

// Per receive element k and pilot i: s0 = g Σ_j amp(i,j) exp(j2π f_i u·(p_k + q_j)/c), f_i = f_c + m_i Δf
// the pilot's own frequency (the emulator's exact element delay: the carrier phase
// exp(j2π u·o/λ) and the delay −u·o/c on subcarrier m make the steering phasor at the
// subcarrier's own wavelength c/f_i), and, when ds is given, its derivative in
// φ (the pattern's slope included, as angle_crb_rad2 keeps it).
void mimo_model(const array_geometry& a, const mimo_mask& m, const frame_settings& fs, double az, double el,
                std::vector<cd>& s0, std::vector<cd>* ds)
{
    const int nr = a.n_receive(), nt = a.n_transmit(), np = m.mask().size();
    const auto off = a.virtual_offsets();
    const position3 u = direction_vector(az, el);
    const position3 du{ -std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), 0.0 };
    const double g = element_pattern_amplitude(a.pattern(), u);
    const double dg = a.pattern() == element_pattern::cosine && u[0] > 0.0 ? 2.0 * u[0] * du[0] : 0.0;
    s0.assign(size_t(nr) * np, 0.0);
    if (ds)
        ds->assign(s0.size(), 0.0);
    for (int i = 0; i < np; ++i) {
        const double f = fs.carrier_hz + m.mask().positions()[size_t(i)].m * fs.subcarrier_spacing_hz();
        for (int j = 0; j < nt; ++j) {
            const double w = m.amplitude(i, j);
            if (w == 0.0)
                continue;
            for (int k = 0; k < nr; ++k) {
                const auto& o = off[size_t(k) * nt + j];
                const cd p = element_phasor(u, o, speed_of_light_mps / f);
                s0[size_t(k) * np + i] += w * g * p;
                if (ds)
                    (*ds)[size_t(k) * np + i] +=
                        w * (dg * p + g * p * cd(0.0, 2.0 * M_PI * f * projection_m(du, o) / speed_of_light_mps));
            }
        }
    }
}

void check_frame(const char* who, const mimo_mask& m, const frame_settings& fs)
{
    m.mask().check_frame(fs, who);
}

} // namespace

double mimo_angle_crb_rad2(const array_geometry& a, const mimo_mask& m, const frame_settings& fs, double azimuth_rad,
                           double elevation_rad, double snr)
{
    if (!(std::isfinite(snr) && snr > 0.0))
        throw std::invalid_argument("mimo_angle_crb_rad2: snr must be > 0, got " + mimo_num(snr));
    check_mimo_counts("mimo_angle_crb_rad2", a, m);
    check_frame("mimo_angle_crb_rad2", m, fs);
    std::vector<cd> s0, s1;
    mimo_model(a, m, fs, azimuth_rad, elevation_rad, s0, &s1);
    const int nr = a.n_receive(), np = m.mask().size();
    const double big_m = m.mask().n_subcarriers(), big_n = m.mask().n_symbols();
    // Derivatives of the mean (α = 1) per observation: φ, τ, ν, Re α, Im α.
    Eigen::Matrix<double, 5, 5> j = Eigen::Matrix<double, 5, 5>::Zero();
    for (int k = 0; k < nr; ++k)
        for (int i = 0; i < np; ++i) {
            const auto& pos = m.mask().positions()[size_t(i)];
            const cd a0 = s0[size_t(k) * np + i];
            const cd d[5] = { s1[size_t(k) * np + i], a0 * cd(0.0, -2.0 * M_PI * pos.m / big_m),
                              a0 * cd(0.0, 2.0 * M_PI * pos.n / big_n), a0, a0 * cd(0.0, 1.0) };
            for (int r = 0; r < 5; ++r)
                for (int c = 0; c < 5; ++c)
                    j(r, c) += (std::conj(d[r]) * d[c]).real();
        }
    j *= 2.0 * snr;
    if (!(j(3, 3) > 0.0))
        return std::numeric_limits<double>::infinity(); // the pattern's null: nothing is seen
    // [J⁻¹]_φφ = 1/(J_φφ − J_φr J_rr⁻¹ J_rφ), the nuisances' block inverted by a rank-revealing
    // decomposition (a mask on one symbol leaves ν unidentifiable, which does not touch φ).
    const Eigen::Matrix4d jrr = j.block<4, 4>(1, 1);
    const Eigen::Vector4d jrp = j.block<4, 1>(1, 0);
    const Eigen::CompleteOrthogonalDecomposition<Eigen::Matrix4d> cod(jrr);
    const double schur = j(0, 0) - jrp.dot(cod.solve(jrp));
    if (!(schur > 1e-12 * j(0, 0)))
        return std::numeric_limits<double>::infinity();
    return 1.0 / schur;
}

// Grid tables: the steering per grid azimuth and the delay–Doppler phasors per grid point.
struct mimo_ml_angle_estimator::tables {
    int q = 0, nd = 0, nv = 0;
    Eigen::MatrixXcd steer;  // q x (N_r·N_p): conj(s0)/‖s0‖ per grid azimuth
    Eigen::MatrixXcd phasor; // N_p x (nd·nv): exp(j2π m τ/M) exp(−j2π n ν/N)
    std::vector<double> az, tau, nu;
    bool spans_subcarriers = false, spans_symbols = false; // the pilots see τ, ν
};

mimo_ml_angle_estimator::mimo_ml_angle_estimator(const array_geometry& a, const mimo_mask& m, const frame_settings& fs,
                                                 double elevation_rad, angle_search search, int oversample)
    : d_array(a), d_mask(m), d_fs(fs), d_elevation(elevation_rad), d_search(search), d_over(oversample)
{
    check_mimo_counts("mimo_ml_angle_estimator", a, m);
    check_frame("mimo_ml_angle_estimator", m, fs);
    if (!(search.min_rad >= -M_PI && search.max_rad <= M_PI && search.min_rad < search.max_rad) || search.grid < 8)
        throw std::invalid_argument("mimo_ml_angle_estimator: search needs -pi <= min_rad < max_rad <= pi and grid >= 8");
    if (oversample < 1 || oversample > 16)
        throw std::invalid_argument("mimo_ml_angle_estimator: oversample must be in [1, 16], got " +
                                    std::to_string(oversample));
    auto t = std::make_shared<tables>();
    const int np = m.mask().size(), big_m = m.mask().n_subcarriers(), big_n = m.mask().n_symbols();
    t->q = search.grid;
    t->nd = big_m * oversample;
    t->nv = big_n * oversample;
    const int kn = a.n_receive() * np;
    t->steer.resize(t->q, kn);
    for (int g = 0; g < t->q; ++g) {
        const double az = search.min_rad + (search.max_rad - search.min_rad) * g / (t->q - 1);
        t->az.push_back(az);
        const auto s = steering(az);
        double n2 = 0.0;
        for (const auto& x : s)
            n2 += std::norm(x);
        for (int i = 0; i < kn; ++i)
            t->steer(g, i) = n2 > 0.0 ? std::conj(s[size_t(i)]) / std::sqrt(n2) : cd(0.0);
    }
    for (int d = 0; d < t->nd; ++d)
        t->tau.push_back(double(d) / oversample);
    for (int v = 0; v < t->nv; ++v)
        t->nu.push_back(-0.5 * big_n + double(v) / oversample);
    for (const auto& p : m.mask().positions()) {
        t->spans_subcarriers |= p.m != m.mask().positions().front().m;
        t->spans_symbols |= p.n != m.mask().positions().front().n;
    }
    t->phasor.resize(np, Eigen::Index(t->nd) * t->nv);
    for (int i = 0; i < np; ++i) {
        const auto& p = m.mask().positions()[size_t(i)];
        for (int v = 0; v < t->nv; ++v)
            for (int d = 0; d < t->nd; ++d)
                t->phasor(i, Eigen::Index(v) * t->nd + d) =
                    cis_cycles(double(p.m) * t->tau[size_t(d)] / big_m - double(p.n) * t->nu[size_t(v)] / big_n);
    }
    d_t = t;
}

std::vector<cd> mimo_ml_angle_estimator::steering(double azimuth_rad) const
{
    std::vector<cd> s0;
    mimo_model(d_array, d_mask, d_fs, azimuth_rad, d_elevation, s0, nullptr);
    return s0;
}

double mimo_ml_angle_estimator::likelihood(const gr_complex* y, double azimuth_rad, double delay_index,
                                           double doppler_bins) const
{
    const auto s = steering(azimuth_rad);
    const int nr = d_array.n_receive(), np = d_mask.mask().size();
    const double big_m = d_mask.mask().n_subcarriers(), big_n = d_mask.mask().n_symbols();
    cd acc = 0.0;
    double n2 = 0.0;
    for (int i = 0; i < np; ++i) {
        const auto& p = d_mask.mask().positions()[size_t(i)];
        const cd ph = cis_cycles(double(p.m) * delay_index / big_m - double(p.n) * doppler_bins / big_n);
        cd z = 0.0;
        for (int k = 0; k < nr; ++k) {
            const size_t e = size_t(k) * np + size_t(i);
            z += std::conj(s[e]) * cd(y[e]);
            n2 += std::norm(s[e]);
        }
        acc += z * ph;
    }
    return n2 > 0.0 ? std::norm(acc) / n2 : 0.0;
}

mimo_ml_estimate mimo_ml_angle_estimator::estimate(const gr_complex* y) const
{
    const tables& t = *d_t;
    const int nr = d_array.n_receive(), np = d_mask.mask().size();
    Eigen::MatrixXcd z(t.q, np); // per grid azimuth and pilot: Σ_k conj(s0) y / ‖s0‖
    for (int i = 0; i < nr * np; ++i)
        if (!std::isfinite(y[i].real()) || !std::isfinite(y[i].imag()))
            throw std::invalid_argument("mimo_ml_angle_estimator: observation " + std::to_string(i) + " is not finite");
    z.setZero();
    for (int k = 0; k < nr; ++k)
        for (int i = 0; i < np; ++i) {
            const cd yi(y[size_t(k) * np + i]);
            z.col(i) += t.steer.col(Eigen::Index(k) * np + i) * yi;
        }
    const Eigen::MatrixXcd p = z * t.phasor; // q x (nd·nv)
    Eigen::Index bq = 0, bc = 0;
    p.cwiseAbs2().maxCoeff(&bq, &bc);
    mimo_ml_estimate e;
    e.azimuth_rad = t.az[size_t(bq)];
    e.delay_index = t.tau[size_t(bc % t.nd)];
    e.doppler_bins = t.nu[size_t(bc / t.nd)];
    // Polish: Nelder–Mead over (φ, τ, ν) together from a simplex of half a grid step per
    // coordinate: they are coupled (time division ties φ to ν, frequency division to τ), so a
    // search along one coordinate at a time would crawl along the ridge. A coordinate the pilots
    // cannot see (τ with every pilot on one subcarrier, ν on one symbol) is left out: the
    // likelihood is flat along it, and a simplex stretched along a flat direction stalls.
    const double steps[3] = { (d_search.max_rad - d_search.min_rad) / (t.q - 1), 1.0 / d_over, 1.0 / d_over };
    std::vector<int> dims{ 0 };
    if (t.spans_subcarriers)
        dims.push_back(1);
    if (t.spans_symbols)
        dims.push_back(2);
    const size_t nd = dims.size(), nv = nd + 1;
    using point = std::array<double, 3>;
    auto value = [&](const point& x) {
        if (x[0] < d_search.min_rad || x[0] > d_search.max_rad)
            return -1.0;
        return likelihood(y, x[0], x[1], x[2]);
    };
    std::vector<point> v(nv);
    std::vector<double> fv(nv);
    v[0] = { e.azimuth_rad, e.delay_index, e.doppler_bins };
    for (size_t i = 0; i < nd; ++i) {
        v[i + 1] = v[0];
        v[i + 1][size_t(dims[i])] += 0.5 * steps[dims[i]];
    }
    for (size_t i = 0; i < nv; ++i)
        fv[i] = value(v[i]);
    for (int it = 0; it < 600; ++it) {
        std::vector<size_t> o(nv);
        for (size_t i = 0; i < nv; ++i)
            o[i] = i;
        std::sort(o.begin(), o.end(), [&](size_t a, size_t b) { return fv[a] > fv[b]; });
        std::vector<point> sv(nv);
        std::vector<double> sf(nv);
        for (size_t i = 0; i < nv; ++i) {
            sv[i] = v[o[i]];
            sf[i] = fv[o[i]];
        }
        v = sv;
        fv = sf;
        double spread = 0.0;
        for (size_t i = 1; i < nv; ++i)
            for (int c : dims)
                spread = std::max(spread, std::fabs(v[i][size_t(c)] - v[0][size_t(c)]) / steps[c]);
        if (spread < 1e-9)
            break;
        point centroid = v[0];
        for (int c : dims) {
            centroid[size_t(c)] = 0.0;
            for (size_t i = 0; i < nd; ++i)
                centroid[size_t(c)] += v[i][size_t(c)] / double(nd);
        }
        auto along = [&](double f) {
            point x = centroid;
            for (int c : dims)
                x[size_t(c)] = centroid[size_t(c)] + f * (v[nd][size_t(c)] - centroid[size_t(c)]);
            return x;
        };
        const point r = along(-1.0);
        const double fr = value(r);
        if (fr > fv[0]) {
            const point x = along(-2.0);
            const double fx = value(x);
            v[nd] = fx > fr ? x : r;
            fv[nd] = std::max(fx, fr);
        } else if (fr > fv[nd - 1]) {
            v[nd] = r;
            fv[nd] = fr;
        } else {
            const point x = along(fr > fv[nd] ? -0.5 : 0.5);
            const double fx = value(x);
            if (fx > std::max(fr, fv[nd])) {
                v[nd] = x;
                fv[nd] = fx;
            } else {
                for (size_t i = 1; i < nv; ++i) {
                    for (int c : dims)
                        v[i][size_t(c)] = 0.5 * (v[i][size_t(c)] + v[0][size_t(c)]);
                    fv[i] = value(v[i]);
                }
            }
        }
    }
    const size_t best = size_t(std::max_element(fv.begin(), fv.end()) - fv.begin());
    e.azimuth_rad = v[best][0];
    e.delay_index = v[best][1];
    e.doppler_bins = v[best][2];
    const double big_m = d_mask.mask().n_subcarriers(), big_n = d_mask.mask().n_symbols();
    e.delay_index = std::fmod(std::fmod(e.delay_index, big_m) + big_m, big_m);
    e.doppler_bins = std::fmod(std::fmod(e.doppler_bins + 0.5 * big_n, big_n) + big_n, big_n) - 0.5 * big_n;
    return e;
}

} // namespace sems
} // namespace gr
