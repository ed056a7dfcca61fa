// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: scatterer bodies as separable terms (see scatterer_moments.h for the equations). */
#include "core/channel/scatterer_moments.h"
#include "core/common/math_constants.h"
#include "core/kernels/vector_math.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {
namespace detail {

namespace {

constexpr double golden_angle = 2.399963229728653; // wheel w's rims turn by w·this: not aligned

inline std::complex<double> cis(double rad) { return { std::cos(rad), std::sin(rad) }; }

// sinc(x) = sin x / x
inline double sinc(double x) { return std::fabs(x) < 1e-8 ? 1.0 - x * x / 6.0 : std::sin(x) / x; }

// The wheels' rim angle at t: v t / R + φ_0 + w · golden angle.
inline double wheel_angle(const wheels_motion& w, double speed, double t, int wheel)
{
    const double turns = speed * t / (two_pi * w.wheel_radius_m); // revolutions, reduced in double
    return two_pi * (turns - std::floor(turns)) + w.phase_rad + golden_angle * wheel;
}

// Hub w's position in the body frame (x forward, y left, m): axles spread over the wheelbase,
// two wheels per axle (left, right), an odd last wheel in the middle.
inline std::pair<double, double> wheel_hub(const wheels_motion& w, int wheel)
{
    const int axles = (w.wheels + 1) / 2;
    const int axle = wheel / 2;
    const double x = axles > 1 ? w.wheelbase_m * (0.5 - double(axle) / (axles - 1)) : 0.0;
    const bool alone = (w.wheels % 2 == 1) && wheel == w.wheels - 1;
    const double y = alone ? 0.0 : (wheel % 2 == 0 ? 0.5 : -0.5) * w.track_m;
    return { x, y };
}

// Hub w's radial displacement from the body's centre: r = −(x cos θ + y sin θ).
inline double wheel_hub_displacement(const wheels_motion& w, int wheel, double heading)
{
    const auto [x, y] = wheel_hub(w, wheel);
    return -(x * std::cos(heading) + y * std::sin(heading));
}

// A body-frame point's offsets across the line of sight (x forward, y left, z up; the radar
// in direction (cos ε cos θ, cos ε sin θ, sin ε)): h along e_h = (sin θ, −cos θ, 0), v along
// e_v = (−sin ε cos θ, −sin ε sin θ, cos ε). Seen from the array these are the directions of
// increasing azimuth and elevation at the body (the body's z is the array's, its line of sight
// the array's reversed).
struct cross_axes {
    double hx, hy, vx, vy, vz;
    cross_axes(double heading, double elevation)
        : hx(std::sin(heading)), hy(-std::cos(heading)), vx(-std::sin(elevation) * std::cos(heading)),
          vy(-std::sin(elevation) * std::sin(heading)), vz(std::cos(elevation))
    {
    }
    double h(double x, double y) const { return hx * x + hy * y; }
    double v(double x, double y, double z) const { return vx * x + vy * y + vz * z; }
};

} // namespace

double mean_sinc_squared(double x0)
{
    // The integrand is smooth and periodic in θ: the trapezoid rule converges geometrically.
    const int n = std::max(64, static_cast<int>(8.0 * std::fabs(x0)) + 64);
    double s = 0.0;
    for (int i = 0; i < n; ++i) {
        const double v = sinc(x0 * std::cos(two_pi * i / n));
        s += v * v;
    }
    return s / n;
}

std::pair<std::complex<double>, double> rotor_mean_moments(double x0, int blades)
{
    // One rotor at unit blade amplitude: B(θ) = Σ_k sinc(x_k) e^{-j x_k}, x_k = x0 cos(θ + 2πk/K);
    // smooth and periodic in θ, so the trapezoid rule converges geometrically.
    const int n = std::max(256, static_cast<int>(8.0 * std::fabs(x0)) + 256);
    std::complex<double> mean(0.0, 0.0);
    double power = 0.0;
    for (int i = 0; i < n; ++i) {
        std::complex<double> sum(0.0, 0.0);
        for (int k = 0; k < blades; ++k) {
            const double x = x0 * std::cos(two_pi * i / n + two_pi * k / blades);
            sum += sinc(x) * cis(-x);
        }
        mean += sum;
        power += std::norm(sum);
    }
    return { mean / double(n), power / n };
}

void line_integrals(double z, int order, std::complex<double>* out) { line_integrals(z, cis(-z), order, out); }

namespace {

constexpr int series_terms = 96; // the small-|z| series stops before this many terms

// 1/i for i < series_terms + max_order + 1: a product per term instead of a division.
const double* inverse()
{
    static const auto inv = [] {
        std::array<double, series_terms + max_order + 1> v{};
        for (size_t i = 1; i < v.size(); ++i)
            v[i] = 1.0 / double(i);
        return v;
    }();
    return inv.data();
}

} // namespace

void line_integrals(double z, std::complex<double> e, int order, std::complex<double>* out)
{
    const double az = std::fabs(z);
    const double* inv = inverse();
    if (az >= std::max(2.0, double(order))) {
        // Upward: E_0 = (1 − e^{-jz})/(jz), E_p = (e^{-jz} − p E_{p−1})/(−jz). Each step scales
        // the previous error by p/|z| ≤ 1 here, so the recurrence is stable. One instant of
        // the batched recurrence (vector_math.h), which moments() runs over all instants.
        const double cs = e.real(), sn = -e.imag();
        double re[max_order + 1], im[max_order + 1], w;
        upward_line_integrals(&z, &cs, &sn, 1, order, re, im, &w);
        for (int p = 0; p <= order; ++p)
            out[p] = { re[p], im[p] };
        return;
    }
    // |z| < max(2, order) ≤ 14: E_P(z) = Σ_k c_k / (P+k+1), c_k = (−jz)^k / k!, terms until
    // |z|^k/k! < 1e-17 (rounding ~ε·e^{|z|} ≤ 1e-10 at |z| = 14); then downward,
    // E_{p−1} = (e^{-jz} + jz E_p)/p, which scales the error by |z|/p: shrinking while p > |z|,
    // and by at most |z|^|z|/⌊|z|⌋! ≤ e^{|z|} over the steps below, the series' own bound.
    // c_k = (−j)^k t_k with t_k = z^k/k! real: the even terms are real (signs +, −, ...), the
    // odd ones imaginary (−, +, ...), so the series is two real sums of t_k/(P+k+1).
    double t[series_terms];
    int n = 0;
    double term = 1.0;
    for (; n < series_terms; ++n) {
        t[n] = term;
        if (n > az && term * term < 1e-34)
            break;
        term *= z * inv[n + 1];
    }
    double re = 0.0, im = 0.0;
    for (int k = std::min(n, series_terms - 1); k >= 0; --k) { // smallest first
        const double v = t[k] * inv[order + k + 1];
        switch (k & 3) { // (−j)^k: 1, −j, −1, j
        case 0: re += v; break;
        case 1: im -= v; break;
        case 2: re -= v; break;
        default: im += v; break;
        }
    }
    out[order] = { re, im };
    // (e + jz·E)/p = (e_r − z·E_i + j(e_i + z·E_r))/p, written out
    for (int p = order; p >= 1; --p)
        out[p - 1] = { (e.real() - z * out[p].imag()) * inv[p], (e.imag() + z * out[p].real()) * inv[p] };
}

namespace {

// The smallest plan whose remainder bound Σ_i a_i (δk_max r_i)^{P+1}/(P+1)! is within the
// tolerance, over scatterers reaching |r| ≤ r_i with amplitudes |a| ≤ a_i (reach[i] = {a_i, r_i}).
// `term` is scratch (one value per scatterer).
expansion_plan plan_for(const frame_settings& fs,
                        const std::vector<std::pair<double, double>>& reach,
                        std::vector<double>& term)
{
    expansion_plan plan;
    const int m = fs.n_subcarriers;
    const double dk_per_subcarrier = 4.0 * M_PI * fs.subcarrier_spacing_hz() / speed_of_light_mps;
    term.resize(reach.size());
    for (int s = 1; s <= m; ++s) {
        const int len = (m + s - 1) / s;
        // Within a sub-band of len subcarriers, |δk| ≤ (len − 1)/2 · dk.
        const double x = 0.5 * (len - 1) * dk_per_subcarrier;
        double bound = 0.0; // Σ a_i (x r_i)^{P+1}/(P+1)! for P = 0
        for (size_t i = 0; i < reach.size(); ++i) {
            term[i] = reach[i].first * x * reach[i].second;
            bound += term[i];
        }
        int p = 0;
        while (bound > truncation_tolerance && p < max_order) {
            ++p;
            bound = 0.0;
            for (size_t i = 0; i < reach.size(); ++i) {
                term[i] *= x * reach[i].second / double(p + 1);
                bound += term[i];
            }
        }
        if (bound <= truncation_tolerance) {
            plan.order = p;
            plan.band_len = len;
            plan.sub_bands = (m + len - 1) / len; // ceil(M/len) ≤ s bands of len
            return plan;
        }
    }
    throw std::logic_error("plan_expansion: no plan for these scatterers");
}

} // namespace

expansion_plan plan_expansion(const frame_settings& fs, double extent_m, double amplitude_sum)
{
    std::vector<double> term;
    return plan_for(fs, { { amplitude_sum, extent_m } }, term);
}

expansion_plan plan_expansion(const frame_settings& fs, const body_snapshot& s)
{
    // Each scatterer's largest amplitude and reach over the snapshot's instants (a line: its
    // farther end), so the bound is the model's own, at the scatterers this frame has.
    const size_t count = size_t(s.count);
    // Called per frame: the scratch lists keep their capacity (per thread, as blocks run in
    // their own threads), so no allocation once they have grown.
    thread_local std::vector<std::pair<double, double>> reach;
    thread_local std::vector<double> term;
    reach.clear();
    for (size_t i = 0; i < s.point_r.size() / count; ++i) {
        double a = 0.0, r = 0.0;
        for (size_t n = 0; n < count; ++n) {
            a = std::max(a, std::fabs(s.point_a[i * count + n]));
            r = std::max(r, std::fabs(s.point_r[i * count + n]));
        }
        reach.emplace_back(a, r);
    }
    for (size_t i = 0; i < s.line_e.size() / count; ++i) {
        double a = 0.0, r = 0.0;
        for (size_t n = 0; n < count; ++n) {
            const size_t k = i * count + n;
            a = std::max(a, std::fabs(s.line_a[k]));
            r = std::max({ r, std::fabs(s.line_r0[k]), std::fabs(s.line_r0[k] + s.line_e[k]) });
        }
        reach.emplace_back(a, r);
    }
    return plan_for(fs, reach, term);
}

body_model::body_model(const scatterer_body& b, const frame_settings& fs) : d_b(b)
{
    d_extent = micro_motion_extent_m(b.motion);
    const double kappa = 4.0 * M_PI / fs.wavelength_m();
    if (const auto* r = std::get_if<rotor_motion>(&b.motion)) {
        // Blade amplitude c: the target's mean power over the rotors' angles (independent per
        // rotor) is 1, the body's own share body_power: b + 2c√b Re E[B] + c² E|B|² = 1 with
        // B the blades' sum at unit amplitude, E[B] = R μ, E|B|² = R σ² + R(R−1)|μ|².
        const int n = r->rotors * r->blades;
        const double x0 = 0.5 * kappa * r->blade_length_m * std::cos(r->elevation_rad);
        const auto mom = rotor_mean_moments(x0, r->blades);
        const double R = r->rotors, b = r->body_power;
        const double m1 = R * mom.first.real();
        const double m2 = R * mom.second + R * (R - 1.0) * std::norm(mom.first);
        d_body_a = std::sqrt(b);
        d_elem_a = (-std::sqrt(b) * m1 + std::sqrt(b * m1 * m1 + m2 * (1.0 - b))) / m2;
        d_amp_sum = d_body_a + n * d_elem_a;
        for (int k = 0; k < r->rotors; ++k) {
            const double f = r->rotation_hz.size() == 1 ? r->rotation_hz[0] : r->rotation_hz[k];
            const double ph = r->phase_rad.size() == 1 ? r->phase_rad[0] : r->phase_rad[k];
            auto same = std::find_if(d_rotor_groups.begin(), d_rotor_groups.end(),
                                     [&](const rotor_group& g) { return g.rate_hz == f && g.phase_rad == ph; });
            if (same == d_rotor_groups.end())
                d_rotor_groups.push_back({ f, ph, 1 });
            else
                ++same->rotors;
        }
    } else if (const auto* w = std::get_if<wheels_motion>(&b.motion)) {
        // Each rim point and each spoke has the same mean power; the wheels share 1 − body.
        const int points = w->wheels * w->rim_points, spokes = w->wheels * w->spokes;
        const double share = (points + spokes) > 0 ? (1.0 - w->body_power) / (points + spokes) : 0.0;
        const double x0 = 0.5 * kappa * w->wheel_radius_m * std::fabs(std::cos(b.heading_rad));
        d_body_a = std::sqrt(w->body_power);
        d_elem_a = std::sqrt(share);
        d_spoke_a = spokes > 0 ? std::sqrt(share / mean_sinc_squared(x0)) : 0.0;
        if ((points + spokes) > 0) // over one revolution: every wheel turns together
            normalise_over_cycle(fs, b.speed_mps > 0.0 ? two_pi * w->wheel_radius_m / b.speed_mps : 1.0, 64);
        d_amp_sum = d_scale * (d_body_a + points * d_elem_a + spokes * d_spoke_a);
    } else if (const auto* s = std::get_if<scatterers_motion>(&b.motion)) {
        double total = 0.0;
        for (const auto& p : s->scatterers)
            total += p.power;
        double f_min = 0.0, f_max = 0.0;
        for (const auto& p : s->scatterers) {
            d_point_a.push_back(std::sqrt(p.power / total));
            for (const auto& h : p.harmonics)
                if (h.rate_hz > 0.0 && h.amplitude_m > 0.0) {
                    f_min = f_min > 0.0 ? std::min(f_min, h.rate_hz) : h.rate_hz;
                    f_max = std::max(f_max, h.rate_hz);
                }
        }
        // Over the slowest harmonic's period, sampled finely enough for the fastest (capped).
        // The ratio is computed in double: a library may pair a 1e-9 Hz harmonic with a 1e9 Hz one.
        const int samples =
            f_min > 0.0 ? static_cast<int>(std::min(512.0, 64.0 * std::ceil(f_max / f_min))) : 64;
        normalise_over_cycle(fs, f_min > 0.0 ? 1.0 / f_min : 1.0, samples);
        for (double a : d_point_a)
            d_amp_sum += d_scale * a;
    } else {
        const auto& wk = std::get<walker_motion>(b.motion);
        walker::walker_params p;
        p.height_m = wk.height_m;
        p.speed_mps = b.speed_mps;
        p.heading_rad = b.heading_rad;
        p.elevation_rad = b.elevation_rad;
        p.phase_rad = wk.phase_rad;
        d_walker.emplace(p);
        normalise_over_cycle(fs, b.speed_mps > 0.0 ? d_walker->cycle_duration_s() : 1.0, 64);
        // 16 segments with Σ mean a² = 1: Σ a ≤ 4 on average; 8 covers the aspect's swing.
        d_amp_sum = 8.0 * d_scale;
    }
}

void body_model::normalise_over_cycle(const frame_settings& fs, double period_s, int n_t)
{
    // Mean over one period and over the band (9 subcarriers, ends included) of
    // |Σ_s a_s e^{-jκ_m r_s}|² — the target's mean power per resource element, cross terms
    // included — then every amplitude scaled to make it 1.
    const int n_f = 9;
    body_snapshot snap;
    std::vector<double> times(n_t);
    for (int i = 0; i < n_t; ++i)
        times[i] = period_s * i / n_t;
    snapshots(times.data(), n_t, snap);
    const size_t points = snap.point_r.size() / n_t, lines = snap.line_e.size() / n_t;
    double power = 0.0;
    for (int i = 0; i < n_t; ++i) {
        for (int f = 0; f < n_f; ++f) {
            const double m = (fs.n_subcarriers - 1) * double(f) / (n_f - 1);
            const double kappa = 4.0 * M_PI * (fs.carrier_hz + m * fs.subcarrier_spacing_hz()) / speed_of_light_mps;
            std::complex<double> sum(0.0, 0.0);
            for (size_t k = 0; k < points; ++k)
                sum += snap.point_a[k * n_t + i] * cis(-kappa * snap.point_r[k * n_t + i]);
            for (size_t k = 0; k < lines; ++k) {
                const double x = 0.5 * kappa * snap.line_e[k * n_t + i];
                sum += snap.line_a[k * n_t + i] * sinc(x) * cis(-x - kappa * snap.line_r0[k * n_t + i]);
            }
            power += std::norm(sum);
        }
    }
    power /= n_t * n_f;
    if (power > 0.0 && std::isfinite(power))
        d_scale = 1.0 / std::sqrt(power);
}

namespace {

// out[n] = value for n < count, appended.
void append_constant(std::vector<double>& out, double value, int count) { out.insert(out.end(), size_t(count), value); }

// s.sn[n] = sin(s.arg[n]), s.cs[n] = cos(s.arg[n]) for n < count.
void sincos_args(body_snapshot& s, int count) { sincos_batch(s.arg.data(), s.sn.data(), s.cs.data(), size_t(count)); }

} // namespace

void body_model::snapshots(const double* t, int count, body_snapshot& out, bool cross_range) const
{
    out.clear();
    out.count = count;
    out.cross_range = cross_range;
    const cross_axes axes(d_b.heading_rad, d_b.elevation_rad);
    const size_t c = size_t(count);
    for (auto* v : { &out.arg, &out.sn, &out.cs, &out.x, &out.y })
        if (v->size() < c)
            v->resize(c);
    if (const auto* r = std::get_if<rotor_motion>(&d_b.motion)) {
        append_constant(out.point_r, 0.0, count);
        append_constant(out.point_a, d_body_a, count);
        // Across the line of sight (the rotor's frame: the radar along x at elevation β over the
        // blades' plane): the tip −l(cos ψ, sin ψ, 0) is offset h = l sin ψ, v = l sin β cos ψ.
        const double h_reach = r->blade_length_m, v_reach = r->blade_length_m * std::sin(r->elevation_rad);
        if (cross_range) {
            append_constant(out.point_h, 0.0, count);
            append_constant(out.point_v, 0.0, count);
        }
        // Rotors that turn alike sit on the same hub (the body's reference point): one set of
        // blades with their summed amplitude, the same return.
        const double reach = r->blade_length_m * std::cos(r->elevation_rad);
        // With an even blade count, blade b + K/2 is blade b turned by π: its extent is
        // exactly −e (cos(θ + π) = −cos θ, written so), and moments() computes the pair once.
        const int half = r->blades % 2 == 0 ? r->blades / 2 : r->blades;
        for (const auto& g : d_rotor_groups) {
            const int first = static_cast<int>(out.line_e.size() / c);
            for (int b = 0; b < r->blades; ++b) {
                append_constant(out.line_r0, 0.0, count);
                append_constant(out.line_a, d_elem_a * g.rotors, count);
                out.line_e.resize(out.line_e.size() + c); // keeps the capacity: written below
                double* e = out.line_e.data() + size_t(first + b) * c;
                double *he = nullptr, *ve = nullptr;
                if (cross_range) {
                    append_constant(out.line_h0, 0.0, count);
                    append_constant(out.line_v0, 0.0, count);
                    out.line_he.resize(out.line_e.size());
                    out.line_ve.resize(out.line_e.size());
                    he = out.line_he.data() + size_t(first + b) * c;
                    ve = out.line_ve.data() + size_t(first + b) * c;
                }
                if (b >= half) {
                    const size_t from_at = size_t(first + b - half) * c;
                    const double* from = out.line_e.data() + from_at;
                    for (int n = 0; n < count; ++n)
                        e[n] = -from[n];
                    if (cross_range)
                        for (int n = 0; n < count; ++n) {
                            he[n] = -out.line_he[from_at + size_t(n)];
                            ve[n] = -out.line_ve[from_at + size_t(n)];
                        }
                    out.line_mirror.resize(size_t(first + b + 1), -1);
                    out.line_mirror[size_t(first + b - half)] = first + b;
                    out.line_mirror[size_t(first + b)] = first + b - half;
                    continue;
                }
                turning_angles(t, g.rate_hz, g.phase_rad, two_pi * b / r->blades, out.arg.data(), c);
                sincos_args(out, count);
                for (int n = 0; n < count; ++n)
                    e[n] = reach * out.cs[n];
                if (cross_range)
                    for (int n = 0; n < count; ++n) {
                        he[n] = h_reach * out.sn[n];
                        ve[n] = v_reach * out.cs[n];
                    }
            }
        }
    } else if (const auto* w = std::get_if<wheels_motion>(&d_b.motion)) {
        append_constant(out.point_r, 0.0, count);
        append_constant(out.point_a, d_body_a, count);
        const double c = std::cos(d_b.heading_rad);
        const double radius = w->wheel_radius_m;
        if (cross_range) { // the body's own point at its reference
            append_constant(out.point_h, 0.0, count);
            append_constant(out.point_v, 0.0, count);
        }
        for (int k = 0; k < w->wheels; ++k) {
            const double hub = wheel_hub_displacement(*w, k, d_b.heading_rad);
            const auto [hub_x, hub_y] = wheel_hub(*w, k);
            // Rim point at angle φ: the hub plus (R sin φ, 0, R cos φ) in the body frame.
            for (int i = 0; i < w->rim_points; ++i) {
                for (int n = 0; n < count; ++n)
                    out.arg[n] = wheel_angle(*w, d_b.speed_mps, t[n], k) + two_pi * i / w->rim_points;
                sincos_args(out, count);
                for (int n = 0; n < count; ++n)
                    out.point_r.push_back(hub - radius * c * out.sn[n]);
                append_constant(out.point_a, d_elem_a, count);
                if (cross_range)
                    for (int n = 0; n < count; ++n) {
                        const double x = hub_x + radius * out.sn[n], z = radius * out.cs[n];
                        out.point_h.push_back(axes.h(x, hub_y));
                        out.point_v.push_back(axes.v(x, hub_y, z));
                    }
            }
            for (int i = 0; i < w->spokes; ++i) {
                for (int n = 0; n < count; ++n)
                    out.arg[n] = wheel_angle(*w, d_b.speed_mps, t[n], k) + two_pi * i / w->spokes;
                sincos_args(out, count);
                append_constant(out.line_r0, hub, count);
                for (int n = 0; n < count; ++n)
                    out.line_e.push_back(-radius * c * out.sn[n]);
                append_constant(out.line_a, d_spoke_a, count);
                if (cross_range) {
                    append_constant(out.line_h0, axes.h(hub_x, hub_y), count);
                    append_constant(out.line_v0, axes.v(hub_x, hub_y, 0.0), count);
                    for (int n = 0; n < count; ++n) {
                        const double x = radius * out.sn[n], z = radius * out.cs[n];
                        out.line_he.push_back(axes.h(x, 0.0));
                        out.line_ve.push_back(axes.v(x, 0.0, z));
                    }
                }
            }
        }
    } else if (const auto* s = std::get_if<scatterers_motion>(&d_b.motion)) {
        // The harmonics move along the body's heading, as wheels and limbs do: the line of
        // sight sees cos θ of them (head-on all, side-on none).
        const double along = std::cos(d_b.heading_rad);
        out.point_r.assign(s->scatterers.size() * c, 0.0);
        for (size_t i = 0; i < s->scatterers.size(); ++i) {
            double* r = out.point_r.data() + i * c;
            for (const auto& h : s->scatterers[i].harmonics) {
                turning_angles(t, h.rate_hz, h.phase_rad, 0.0, out.arg.data(), c);
                sincos_args(out, count);
                const double a = h.amplitude_m * along;
                for (int n = 0; n < count; ++n)
                    r[n] -= a * out.sn[n];
            }
            append_constant(out.point_a, d_point_a[i], count);
        }
        if (cross_range) { // each at (x, 0, 0) in the body frame, x = −r / cos θ: from its harmonics
            out.point_h.assign(out.point_r.size(), 0.0);
            out.point_v.assign(out.point_r.size(), 0.0);
            for (size_t i = 0; i < s->scatterers.size(); ++i)
                for (const auto& h : s->scatterers[i].harmonics) {
                    turning_angles(t, h.rate_hz, h.phase_rad, 0.0, out.arg.data(), c);
                    sincos_args(out, count);
                    for (int n = 0; n < count; ++n) {
                        const double x = h.amplitude_m * out.sn[n];
                        out.point_h[i * c + size_t(n)] += axes.h(x, 0.0);
                        out.point_v[i * c + size_t(n)] += axes.v(x, 0.0, 0.0);
                    }
                }
        }
    } else {
        out.point_r.resize(size_t(walker::n_segments) * c);
        out.point_a.resize(size_t(walker::n_segments) * c);
        if (!cross_range) {
            d_walker->scatterers(t, count, out.point_r.data(), out.point_a.data());
        } else {
            out.x.resize(size_t(3 * walker::n_segments) * c); // the segment centres
            d_walker->scatterers(t, count, out.point_r.data(), out.point_a.data(), out.x.data());
            out.point_h.resize(out.point_r.size());
            out.point_v.resize(out.point_r.size());
            for (int seg = 0; seg < walker::n_segments; ++seg) {
                const double* p = out.x.data() + size_t(3 * seg) * c;
                for (size_t n = 0; n < c; ++n) {
                    out.point_h[size_t(seg) * c + n] = axes.h(p[n], p[c + n]);
                    out.point_v[size_t(seg) * c + n] = axes.v(p[n], p[c + n], p[2 * c + n]);
                }
            }
        }
    }
    if (d_scale != 1.0) {
        for (auto& a : out.point_a)
            a *= d_scale;
        for (auto& a : out.line_a)
            a *= d_scale;
    }
}

channel_path steered_path(const channel_path& p, const array_element& element, double wavelength_m)
{
    if (element.is_origin())
        return p;
    channel_path q = p;
    const position3 u = direction_vector(p.azimuth_rad, p.elevation_rad);
    q.gain *= element_phasor(u, element.offset, wavelength_m);
    if (p.body < 0)
        q.gain *= element_pattern_amplitude(element.pattern, u);
    q.delay_s += element_delay_s(u, element.offset);
    return q;
}

body_steering make_body_steering(double range_m, double azimuth_rad, double elevation_rad, const array_element& element)
{
    body_steering g;
    g.range_m = range_m;
    g.u = direction_vector(azimuth_rad, elevation_rad);
    const double sa = std::sin(azimuth_rad), ca = std::cos(azimuth_rad);
    const double se = std::sin(elevation_rad), ce = std::cos(elevation_rad);
    g.e_h = { -sa, ca, 0.0 };
    g.e_v = { -se * ca, -se * sa, ce };
    g.offset = element.offset;
    g.pattern = element.pattern;
    return g;
}

namespace {

// One scatterer point (r, h, v) as the element sees it: its displacement moved by the plane
// wave's delay from its own direction, and its pattern amplitude.
struct steered_point {
    double r, gain;
};

class point_steering
{
public:
    explicit point_steering(const body_steering& g)
        : d_g(g), d_c0(projection_m(g.u, g.offset)), d_ch(projection_m(g.e_h, g.offset)),
          d_cv(projection_m(g.e_v, g.offset))
    {
    }
    steered_point operator()(double r, double h, double v) const
    {
        const double along = d_g.range_m + r;
        const double norm = std::sqrt(along * along + h * h + v * v);
        if (!(norm > 0.0)) // at the phase centre: the body's own direction
            return { r, element_pattern_amplitude(d_g.pattern, d_g.u) };
        const double inv = 1.0 / norm;
        const double us_o = (along * d_c0 + h * d_ch + v * d_cv) * inv;
        double gain = 1.0;
        if (d_g.pattern != element_pattern::isotropic) {
            position3 us;
            for (int i = 0; i < 3; ++i)
                us[i] = (along * d_g.u[i] + h * d_g.e_h[i] + v * d_g.e_v[i]) * inv;
            gain = element_pattern_amplitude(d_g.pattern, us);
        }
        return { r - 0.5 * (us_o - d_c0), gain };
    }

private:
    const body_steering& d_g;
    double d_c0, d_ch, d_cv; // u·o, e_h·o, e_v·o
};

} // namespace

void steer_snapshot(const body_snapshot& base, const body_steering& geometry, body_snapshot& out)
{
    if (!base.cross_range)
        throw std::logic_error("steer_snapshot: the snapshot was taken without its cross-range offsets");
    const size_t count = size_t(base.count);
    out.clear();
    out.count = base.count;
    out.cross_range = false;
    for (auto* v : { &out.arg, &out.sn, &out.cs, &out.x, &out.y })
        if (v->size() < count)
            v->resize(count);
    const point_steering steer(geometry);
    out.point_r.resize(base.point_r.size());
    out.point_a.resize(base.point_a.size());
    for (size_t k = 0; k < base.point_r.size(); ++k) {
        const steered_point p = steer(base.point_r[k], base.point_h[k], base.point_v[k]);
        out.point_r[k] = p.r;
        out.point_a[k] = base.point_a[k] * p.gain;
    }
    out.line_r0.resize(base.line_r0.size());
    out.line_e.resize(base.line_e.size());
    out.line_a.resize(base.line_a.size());
    for (size_t k = 0; k < base.line_e.size(); ++k) {
        const double r0 = base.line_r0[k], h0 = base.line_h0[k], v0 = base.line_v0[k];
        const double e = base.line_e[k], he = base.line_he[k], ve = base.line_ve[k];
        const steered_point a = steer(r0, h0, v0);
        const steered_point b = steer(r0 + e, h0 + he, v0 + ve);
        out.line_r0[k] = a.r;
        out.line_e[k] = b.r - a.r;
        const double gain = geometry.pattern == element_pattern::isotropic
                                ? 1.0
                                : steer(r0 + 0.5 * e, h0 + 0.5 * he, v0 + 0.5 * ve).gain;
        out.line_a[k] = base.line_a[k] * gain;
    }
}

double band_scale(const frame_settings& fs, const expansion_plan& plan)
{
    const double dk = 4.0 * M_PI * fs.subcarrier_spacing_hz() / speed_of_light_mps;
    return std::max(0.5 * (plan.band_len - 1) * dk, 1e-300);
}

double term_factor(const frame_settings& fs, const expansion_plan& plan, int term, int m)
{
    const int band = term / (plan.order + 1), p = term % (plan.order + 1);
    const int m0 = band * plan.band_len;
    const int len = std::min(plan.band_len, fs.n_subcarriers - m0);
    if (m < m0 || m >= m0 + len)
        return 0.0;
    const double dk = 4.0 * M_PI * fs.subcarrier_spacing_hz() / speed_of_light_mps;
    return std::pow((m - (m0 + 0.5 * (len - 1))) * dk / band_scale(fs, plan), p);
}

void body_terms(const body_model& model,
                const expansion_plan& plan,
                const frame_settings& fs,
                const double* t_s,
                int count,
                body_snapshot& snap,
                std::complex<double>* out)
{
    model.snapshots(t_s, count, snap);
    snapshot_terms(snap, plan, fs, out);
}

void snapshot_terms(body_snapshot& snap, const expansion_plan& plan, const frame_settings& fs, std::complex<double>* out)
{
    const int count = snap.count;
    const int terms = plan.order + 1;
    const size_t stride = size_t(plan.terms());
    const double scale_step = band_scale(fs, plan);
    for (int band = 0; band < plan.sub_bands; ++band) {
        const int m0 = band * plan.band_len;
        const int len = std::min(plan.band_len, fs.n_subcarriers - m0);
        const double f_ref = fs.carrier_hz + (m0 + 0.5 * (len - 1)) * fs.subcarrier_spacing_hz();
        moments(snap, 4.0 * M_PI * f_ref / speed_of_light_mps, plan.order);
        double scale = 1.0;
        for (int p = 0; p < terms; ++p, scale *= scale_step) {
            const double* re = snap.re.data() + size_t(p) * count;
            const double* im = snap.im.data() + size_t(p) * count;
            std::complex<double>* g = out + size_t(band) * terms + p;
            for (int n = 0; n < count; ++n)
                g[n * stride] = { re[n] * scale, im[n] * scale };
        }
    }
}

void moments(body_snapshot& s, double kappa_ref, int order)
{
    const size_t count = size_t(s.count);
    s.re.assign(size_t(order + 1) * count, 0.0);
    s.im.assign(size_t(order + 1) * count, 0.0);
    const size_t points = s.point_r.size() / count, lines = s.line_e.size() / count;
    for (size_t i = 0; i < points; ++i) {
        const double* r = s.point_r.data() + i * count;
        for (size_t n = 0; n < count; ++n)
            s.arg[n] = kappa_ref * r[n];
        sincos_batch(s.arg.data(), s.sn.data(), s.cs.data(), count);
        add_point_moments(r, s.point_a.data() + i * count, s.cs.data(), s.sn.data(), count, order, s.re.data(),
                          s.im.data(), s.x.data(), s.y.data());
    }
    std::complex<double> e[max_order + 1], line[max_order + 1], shift[max_order + 1];
    const double* inv = inverse();
    const size_t terms = size_t(order + 1) * count;
    for (size_t i = 0; i < lines; ++i) {
        // A line whose mirror image (−e, same amplitude, from the reference) is line j > i:
        // the mirror's L_q(−e) is conj(L_q(e)) (E_q(−z) = conj E_q(z), (je)^q = conj (−je)^q),
        // so the pair adds 2 Re L_q, and line j is skipped below: one line integral for two
        // blades of a rotor with an even blade count.
        const int mirror = i < s.line_mirror.size() ? s.line_mirror[i] : -1;
        if (mirror >= 0 && size_t(mirror) < i)
            continue;
        const double* ext = s.line_e.data() + i * count;
        const double* r0 = s.line_r0.data() + i * count;
        const double* amp = s.line_a.data() + i * count;
        for (size_t n = 0; n < count; ++n)
            s.arg[n] = kappa_ref * ext[n];
        sincos_batch(s.arg.data(), s.sn.data(), s.cs.data(), count);
        // E_q(κ e) at every instant: the upward recurrence where it is stable (in one loop over
        // the instants), line_integrals() where |z| is small.
        s.e_re.resize(terms);
        s.e_im.resize(terms);
        upward_line_integrals(s.arg.data(), s.cs.data(), s.sn.data(), count, order, s.e_re.data(), s.e_im.data(),
                              s.x.data());
        for (size_t n = 0; n < count; ++n) {
            if (std::fabs(s.arg[n]) >= std::max(2.0, double(order)))
                continue;
            line_integrals(s.arg[n], { s.cs[n], -s.sn[n] }, order, e);
            for (int q = 0; q <= order; ++q) {
                s.e_re[size_t(q) * count + n] = e[q].real();
                s.e_im[size_t(q) * count + n] = e[q].imag();
            }
        }
        // From 0 to e: L_q = a (−je)^q / q! · E_q(κ e). A line from the reference (a blade), its
        // mirror too: added as they are.
        if (std::all_of(r0, r0 + count, [](double v) { return v == 0.0; })) {
            add_line_moments(s.e_re.data(), s.e_im.data(), ext, amp, count, order, mirror >= 0, s.re.data(),
                             s.im.data(), s.x.data());
            continue;
        }
        // From r0 (a wheel's spoke from its hub): e^{−jκ r0} Σ_{p+q=n} (−j r0)^p/p! · L_q.
        s.l_re.assign(terms, 0.0);
        s.l_im.assign(terms, 0.0);
        add_line_moments(s.e_re.data(), s.e_im.data(), ext, amp, count, order, false, s.l_re.data(), s.l_im.data(),
                         s.x.data());
        for (size_t n = 0; n < count; ++n) {
            for (int q = 0; q <= order; ++q)
                line[q] = { s.l_re[size_t(q) * count + n], s.l_im[size_t(q) * count + n] };
            if (r0[n] != 0.0) {
                std::complex<double> sh = cis(-kappa_ref * r0[n]);
                for (int p = 0; p <= order; ++p) { // sh·(−j r0)/(p+1) = (r0·im − j r0·re)/(p+1)
                    shift[p] = sh;
                    const double f = r0[n] * inv[p + 1];
                    sh = { sh.imag() * f, -sh.real() * f };
                }
                for (int q = order; q >= 0; --q) { // line[q] = Σ_{p ≤ q} shift[p]·line[q − p], in place
                    std::complex<double> sum(0.0, 0.0);
                    for (int p = 0; p <= q; ++p)
                        sum += shift[p] * line[q - p];
                    line[q] = sum;
                }
            }
            for (int p = 0; p <= order; ++p) {
                s.re[size_t(p) * count + n] += line[p].real();
                s.im[size_t(p) * count + n] += line[p].imag();
            }
        }
    }
}

} // namespace detail
} // namespace sems
} // namespace gr
