// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the Boulic–Thalmann walking human as 16 ellipsoid scatterers (walker_model.h).
 *
 * The trajectories are the published ones (Boulic et al. 1990, appendices A–D, as V. C. Chen's
 * scripts and MATLAB's backscatterPedestrian transcribe them; where those two differ, walker.md
 * says which this code follows), written here as functions of the cycle time u in [0, 1) of
 * the right side, u = 0 the right heel strike; the left side runs half a cycle later. The body
 * is backscatterPedestrian's (lengths, foot vector, scatterers at segment centres), the
 * ellipsoid radii and RCS Chen's. docs/reference/walker.md lists them.
 */
#include <gnuradio/sems/core/scene/walker_model.h>
#include "core/common/checks.h"
#include "core/common/math_constants.h"
#include "core/kernels/vector_math.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {
namespace walker {

namespace {

constexpr double deg = M_PI / 180.0;
// Chen's segment radii are absolute (m); they are taken as those of a walker this tall.
constexpr double radius_reference_height_m = 1.8;
// Knots of a trajectory closer than this (in cycles) are one knot: gait B's hip points at −0.1
// and 0.9 are one point a cycle apart, gait C's first hip point reaches its third at RV = 1.3
// (Chen's script merges them when they are equal), and pchip needs distinct knots.
constexpr double knot_merge = 1e-9;

using checks::text;

void check_height(double height_m)
{
    if (!(std::isfinite(height_m) && height_m >= min_height_m && height_m <= max_height_m))
        throw std::invalid_argument("walker: height_m must lie in [" + text(min_height_m) + ", " +
                                    text(max_height_m) + "] m (a human's height), got " +
                                    text(height_m));
}

// RV = v/H_t, refusing speeds outside [0, 3·H_t] with the speed, the height and the range.
double checked_relative_velocity(double height_m, double speed_mps)
{
    check_height(height_m);
    const double ht = leg_length_m(height_m);
    if (!(std::isfinite(speed_mps) && speed_mps >= 0.0 &&
          speed_mps <= max_relative_velocity * ht))
        throw std::invalid_argument(
            "walker: speed_mps " + text(speed_mps) + " m/s at height_m " + text(height_m) +
            " m is outside the Boulic-Thalmann walking model's valid range: the relative "
            "velocity RV = v/H_t (H_t = " + text(proportion::hip_joint_height) + " x height = " +
            text(ht) + " m) is " + text(speed_mps / ht) + ", the model holds for 0 <= RV <= " +
            text(max_relative_velocity) + ", i.e. 0 to " + text(max_relative_velocity * ht) +
            " m/s at this height");
    return std::min(speed_mps / ht, max_relative_velocity);
}

double frac(double x) { return x - std::floor(x); }

// cos and sin of the fixed phase offsets of the published harmonic trajectories.
struct phases {
    double lat_cos, lat_sin, vert_cos, vert_sin, fb_cos, fb_sin;
};
const phases& harmonic_phases()
{
    static const phases k = { std::cos(-0.2 * M_PI), std::sin(-0.2 * M_PI),  // 2π·(−0.1)
                              std::cos(-0.7 * M_PI), std::sin(-0.7 * M_PI),  // 2π·(−0.35)
                              std::cos(-0.2 * M_PI), std::sin(-0.2 * M_PI) }; // 2π·(−0.1)
    return k;
}

using mat3 = std::array<std::array<double, 3>, 3>;

inline vec3 mul(const mat3& m, const vec3& v)
{
    return { m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
             m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
             m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2] };
}

inline vec3 add(const vec3& a, const vec3& b) { return { a[0] + b[0], a[1] + b[1], a[2] + b[2] }; }
inline vec3 mid(const vec3& a, const vec3& b)
{
    return { 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2]) };
}
inline double dot(const vec3& a, const vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

} // namespace

const std::array<segment_shape, n_segments>& segment_shapes()
{
    namespace pr = proportion;
    constexpr double r = 1.0 / radius_reference_height_m;
    static const double foot = std::hypot(pr::foot, pr::ankle_height);
    static const std::array<segment_shape, n_segments> table = { {
        { "left foot", foot, 0.05 * r },
        { "right foot", foot, 0.05 * r },
        { "left lower leg", pr::lower_leg, 0.06 * r },
        { "right lower leg", pr::lower_leg, 0.06 * r },
        { "left upper leg", pr::upper_leg, 0.07 * r },
        { "right upper leg", pr::upper_leg, 0.07 * r },
        { "left hip", pr::hip_half_width, 0.07 * r },
        { "right hip", pr::hip_half_width, 0.07 * r },
        { "left lower arm", pr::lower_arm, 0.05 * r },
        { "right lower arm", pr::lower_arm, 0.05 * r },
        { "left upper arm", pr::upper_arm, 0.06 * r },
        { "right upper arm", pr::upper_arm, 0.06 * r },
        { "left shoulder", pr::shoulder_half_width, 0.06 * r },
        { "right shoulder", pr::shoulder_half_width, 0.06 * r },
        { "head", pr::head, 0.10 * r },
        { "torso", pr::torso, 0.15 * r },
    } };
    return table;
}

double leg_length_m(double height_m) { return proportion::hip_joint_height * height_m; }

double max_speed_mps(double height_m) { return max_relative_velocity * leg_length_m(height_m); }

double cycle_duration_s(double height_m, double speed_mps)
{
    const double rv = checked_relative_velocity(height_m, speed_mps);
    return rv > 0.0 ? 1.346 / std::sqrt(rv) : std::numeric_limits<double>::infinity();
}

namespace {

// The periodic pchip through knots (x_i, y_i) given over one cycle in any order and any
// offset: MATLAB's pchip (Fritsch–Butland slopes) on the knots repeated each cycle, the way
// the published implementations evaluate it.
template <typename P>
P make_pchip(std::initializer_list<double> xs, std::initializer_list<double> ys_deg)
{
    std::array<std::pair<double, double>, 5> k{};
    int n = 0;
    auto yi = ys_deg.begin();
    for (double x : xs)
        k[n++] = { frac(x), *yi++ * deg };
    std::sort(k.begin(), k.begin() + n);
    int m = 0; // merge knots that coincide modulo one cycle (their values agree there)
    for (int i = 0; i < n; ++i)
        if (m == 0 || k[i].first - k[m - 1].first > knot_merge)
            k[m++] = k[i];
    if (m > 1 && k[0].first + 1.0 - k[m - 1].first <= knot_merge)
        --m;
    P p;
    p.n = m;
    for (int i = 0; i < m; ++i) {
        p.x[i] = k[i].first;
        p.y[i] = k[i].second;
    }
    p.x[m] = p.x[0] + 1.0;
    auto xk = [&](int i) { return i < 0 ? p.x[i + m] - 1.0 : i >= m ? p.x[i - m] + 1.0 : p.x[i]; };
    auto yk = [&](int i) { return p.y[((i % m) + m) % m]; };
    std::array<double, 5> slope{};
    for (int i = 0; i < m; ++i) {
        const double h0 = xk(i) - xk(i - 1), h1 = xk(i + 1) - xk(i);
        const double d0 = (yk(i) - yk(i - 1)) / h0, d1 = (yk(i + 1) - yk(i)) / h1;
        if (d0 * d1 > 0.0) {
            const double w1 = 2.0 * h1 + h0, w2 = h1 + 2.0 * h0;
            slope[i] = (w1 + w2) / (w1 / d0 + w2 / d1);
        }
    }
    for (int i = 0; i < m; ++i) {
        const double h = xk(i + 1) - xk(i), delta = (yk(i + 1) - yk(i)) / h;
        const double s0 = slope[i], s1 = slope[(i + 1) % m];
        p.b[i] = s0;
        p.c[i] = (3.0 * delta - 2.0 * s0 - s1) / h;
        p.d[i] = (s0 - 2.0 * delta + s1) / (h * h);
    }
    return p;
}

} // namespace

double walker_model::periodic_pchip::operator()(double u) const
{
    const double w = u < x[0] ? u + 1.0 : u;
    int i = 0;
    while (i + 1 < n && w >= x[i + 1])
        ++i;
    const double s = w - x[i];
    return y[i] + s * (b[i] + s * (c[i] + s * d[i]));
}

walker_model::walker_model(const walker_params& p) : d_params(p)
{
    d_rv = checked_relative_velocity(p.height_m, p.speed_mps);
    if (!std::isfinite(p.heading_rad))
        throw std::invalid_argument("walker: heading_rad must be finite, got " + text(p.heading_rad));
    if (!std::isfinite(p.phase_rad))
        throw std::invalid_argument("walker: phase_rad must be finite, got " + text(p.phase_rad));
    if (!(std::isfinite(p.elevation_rad) && std::fabs(p.elevation_rad) <= M_PI_2))
        throw std::invalid_argument("walker: elevation_rad must lie in [-pi/2, pi/2], got " +
                                    text(p.elevation_rad));
    d_height = p.height_m;
    const double rv = d_rv;

    // Temporal characteristics: cycle duration D_c = RL_c/RV, RL_c = 1.346·sqrt(RV), and the
    // relative duration of support (0.752·D_c − 0.143)/D_c.
    d_cycle_s = rv > 0.0 ? 1.346 / std::sqrt(rv) : std::numeric_limits<double>::infinity();
    d_inv_cycle = rv > 0.0 ? 1.0 / d_cycle_s : 0.0;
    d_support = 0.752 - 0.143 * d_inv_cycle;
    d_phase_cycles = frac(p.phase_rad / two_pi);

    // Boulic's gaits: A below RV = 0.5 (amplitudes grow from 0), B to 1.3, C to 3.
    const int gait = rv < 0.5 ? 0 : rv < 1.3 ? 1 : 2;
    const double qa = rv * (1.0 - rv);  // −RV² + RV, the slow gait's amplitude law
    const double sb = (rv - 0.5) / 0.8; // 0..1 across gait B
    const double sc = (rv - 1.3) / 1.7; // 0..1 across gait C

    // Translations of the pelvis (m). Gait A's lateral and forward amplitudes carry the sign
    // that joins them to gait B's at RV = 0.5 (see walker.md).
    d_trans_vert = 0.015 * rv;
    d_trans_lat = gait == 0 ? -0.128 * qa : -0.032;
    d_trans_fb = gait == 0 ? -0.084 * qa : -0.021;
    d_trans_fb_cos = std::cos(4.0 * M_PI * (0.625 - d_support)); // phase 2π·2φ_fb,
    d_trans_fb_sin = std::sin(4.0 * M_PI * (0.625 - d_support)); // φ_fb = 0.625 − support
    // Rotations of the pelvis and the shoulder swing (amplitudes in rad).
    d_rot_fb = (gait == 0 ? 8.0 * qa : 2.0) * deg;
    d_rot_lr = 1.66 * rv * deg;
    d_rot_tor = 4.0 * rv * deg;
    d_shoulder = 9.88 * rv * deg;

    using P = periodic_pchip;
    // Flexion at the hip, the knee, the ankle (deg at the control points). The hip keeps the
    // published points although pchip jumps with them as RV passes 1.3: gait C's first point
    // closes on its third with a secant of −5°/cycle that does not vanish with sc, so the curve
    // from 0.9 starts with slope −7.23°/cycle where gait B's has 0 (up to 0.64° less flexion at
    // u = 0.1; walker.md, "Gait boundaries"). Both published implementations jump the same way.
    if (gait == 0)
        d_hip = make_pchip<P>({ -0.1, 0.5, 0.9 }, { 50 * rv, -30 * rv, 50 * rv });
    else if (gait == 1)
        d_hip = make_pchip<P>({ -0.1, 0.5, 0.9 }, { 25, -15, 25 });
    else
        d_hip = make_pchip<P>({ 0.2 * sc - 0.1, 0.5, 0.9 }, { 5 * sc + 25, -15, 6 * sc + 25 });
    if (gait == 0)
        d_knee = make_pchip<P>({ 0.17, 0.4, 0.75, 1.0 }, { 3, 3, 140 * rv, 3 });
    else if (gait == 1)
        d_knee = make_pchip<P>({ 0.17, 0.4, 0.75, 1.0 }, { 3, 3, 70, 3 });
    else
        d_knee = make_pchip<P>({ 0.17 - 0.05 * sc, 0.4, 0.75 - 0.05 * sc, 1.0 - 0.03 * sc },
                               { 22 * sc + 3, 3, 70 - 5 * sc, 3 * sc + 3 });
    const double rds = d_support;
    if (gait == 0)
        d_ankle = make_pchip<P>({ 0, 0.08, 0.5, rds, 0.85 },
                                { -3, -30 * rv - 3, 22 * rv - 3, -34 * rv - 3, -3 });
    else if (gait == 1)
        d_ankle = make_pchip<P>({ 0, 0.08, 0.5, rds, 0.85 }, { -3, -18, 8, -20, -3 });
    else
        d_ankle = make_pchip<P>({ 0, 0.08, 0.5 - 0.1 * sc, rds, 0.85 },
                                { 5 * sc - 3, 4 * sc - 18, 8 - 3 * sc, -8 * sc - 20, 5 * sc - 3 });
    // Upper body: torsion of the thorax, flexion at the elbow (deg).
    d_thorax = make_pchip<P>({ 0.1, 0.4, 0.6, 0.9 },
                             { 4.0 / 3 * rv, -4.5 / 3 * rv, -4.0 / 3 * rv, 4.5 / 3 * rv });
    if (gait == 0)
        d_elbow = make_pchip<P>({ 0.05, 0.5, 0.9 }, { 6 * rv + 3, 34 * rv + 3, 10 * rv + 3 });
    else if (gait == 1)
        d_elbow = make_pchip<P>({ 0.05, 0.5 + 0.01 * sb, 0.9 },
                                { 8 * sb + 6, 24 * sb + 20, 9 * sb + 8 });
    else
        d_elbow = make_pchip<P>({ 0.05, 0.51 + 0.04 * sc, 0.9 - 0.1 * sc },
                                { 14 - 6 * sc, 44 + 26 * sc, 17 - 6 * sc });

    // Ellipsoids in m and the line of sight.
    const auto& shapes = segment_shapes();
    for (int s = 0; s < n_segments; ++s) {
        const double a = shapes[s].radius * d_height, c = 0.5 * shapes[s].length * d_height;
        d_a2[s] = a * a;
        d_c2[s] = c * c;
        d_sqrtpi_a2c[s] = std::sqrt(M_PI) * a * a * c;
    }
    const double ce = std::cos(p.elevation_rad);
    d_los = { ce * std::cos(p.heading_rad), ce * std::sin(p.heading_rad), std::sin(p.elevation_rad) };

    // Normalization: the cycle mean of Σ_s σ_s, by the midpoint rule (a still body: its pose).
    const int n_mean = rv > 0.0 ? 256 : 1;
    double sum = 0.0;
    body_pose bp;
    std::array<double, n_segments> r, amp;
    for (int j = 0; j < n_mean; ++j) {
        cycle_pose(rv > 0.0 ? (j + 0.5) / n_mean : d_phase_cycles, bp);
        scatter(bp, r.data(), amp.data());
        for (double x : amp)
            sum += x * x;
    }
    d_scale = 1.0 / std::sqrt(sum / n_mean);
}

walker_model::gait_state walker_model::state(double u) const
{
    gait_state g;
    // One sine and cosine of the cycle give every first- and second-harmonic term.
    const double s1 = std::sin(two_pi * u), c1 = std::cos(two_pi * u);
    const double s2 = 2.0 * s1 * c1, c2 = c1 * c1 - s1 * s1; // sin, cos of 4πu
    const auto& k = harmonic_phases();

    // Pelvis translation (forward, lateral, vertical), in m:
    // A_fb·sin(2π(2u + 2φ_fb)), A_l·sin(2π(u − 0.1)), A_v·(sin(2π(2u − 0.35)) − 1).
    g.trans = { d_trans_fb * (s2 * d_trans_fb_cos + c2 * d_trans_fb_sin),
                d_trans_lat * (s1 * k.lat_cos + c1 * k.lat_sin),
                d_trans_vert * (s2 * k.vert_cos + c2 * k.vert_sin - 1.0) };

    // Pelvis rotations: forward/backward A_1·(sin(2π(2u − 0.1)) − 1) (applied to the upper
    // body), left/right (list, piecewise) and torsion −A_3·cos(2πu) (applied to the legs).
    g.rot_fb = d_rot_fb * (s2 * k.fb_cos + c2 * k.fb_sin - 1.0);
    if (u < 0.15)
        g.rot_lr = d_rot_lr * (-1.0 + std::cos(two_pi * (10.0 / 3.0) * u));
    else if (u < 0.5)
        g.rot_lr = d_rot_lr * (-1.0 - std::cos(two_pi * (10.0 / 7.0) * (u - 0.15)));
    else if (u < 0.65)
        g.rot_lr = d_rot_lr * (1.0 - std::cos(two_pi * (10.0 / 3.0) * (u - 0.5)));
    else
        g.rot_lr = d_rot_lr * (1.0 + std::cos(two_pi * (10.0 / 7.0) * (u - 0.65)));
    g.rot_tor = -d_rot_tor * c1;
    g.thorax = d_thorax(u);

    // Limbs: [0] left, half a cycle after [1] right. Shoulder 3° − A_s/2 − A_s·cos(2πu).
    const double ul = u < 0.5 ? u + 0.5 : u - 0.5;
    for (int side = 0; side < 2; ++side) {
        const double uu = side == 0 ? ul : u;
        g.hip[side] = d_hip(uu);
        g.knee[side] = d_knee(uu);
        g.ankle[side] = d_ankle(uu);
        g.elbow[side] = d_elbow(uu);
        g.shoulder[side] = 3.0 * deg - 0.5 * d_shoulder + (side == 0 ? 1.0 : -1.0) * d_shoulder * c1;
    }
    return g;
}

gait_trajectories walker_model::trajectories(double u) const
{
    if (!(std::isfinite(u) && u >= 0.0 && u < 1.0))
        throw std::invalid_argument("walker: cycle time u must lie in [0, 1), got " + text(u));
    const gait_state g = state(u);
    gait_trajectories t;
    t.forward_m = g.trans[0];
    t.lateral_m = g.trans[1];
    t.vertical_m = g.trans[2];
    t.pelvis_forward_deg = g.rot_fb / deg;
    t.pelvis_list_deg = g.rot_lr / deg;
    t.pelvis_torsion_deg = g.rot_tor / deg;
    t.hip_deg = g.hip[1] / deg;
    t.knee_deg = g.knee[1] / deg;
    t.ankle_deg = g.ankle[1] / deg;
    t.thorax_deg = g.thorax / deg;
    t.shoulder_deg = g.shoulder[1] / deg;
    t.elbow_deg = g.elbow[1] / deg;
    return t;
}

void walker_model::joint_angles(const gait_state& g, double* a)
{
    // The angles whose sines and cosines place the segments (pose_from reads them in this order).
    a[0] = g.rot_tor;
    a[1] = g.rot_lr;
    a[2] = g.thorax;
    a[3] = g.rot_fb;
    for (int side = 0; side < 2; ++side) {
        const double q_thigh = g.hip[side];
        const double q_shank = q_thigh - g.knee[side];
        a[4 + side] = q_thigh;
        a[6 + side] = q_shank;
        a[8 + side] = q_shank + g.ankle[side];                 // the foot
        a[10 + side] = g.shoulder[side];                        // the upper arm
        a[12 + side] = g.shoulder[side] + g.elbow[side];        // the lower arm
    }
}

void walker_model::cycle_pose(double u, body_pose& pose) const
{
    const gait_state g = state(u);
    double a[n_joint_angles], sn[n_joint_angles], cs[n_joint_angles];
    joint_angles(g, a);
    for (int j = 0; j < n_joint_angles; ++j) {
        sn[j] = std::sin(a[j]);
        cs[j] = std::cos(a[j]);
    }
    pose_from(g, sn, cs, 1, pose);
}

void walker_model::pose_from(const gait_state& g, const double* sn, const double* cs, int stride, body_pose& pose) const
{
    namespace pr = proportion;
    const double h = d_height;
    const vec3& trans = g.trans;
    auto sin_of = [&](int j) { return sn[j * stride]; };
    auto cos_of = [&](int j) { return cs[j * stride]; };
    // A limb of length 1 at joint angle j from straight down, swung forward (towards +x).
    auto limb_of = [&](int j) { return vec3{ sin_of(j), 0.0, -cos_of(j) }; };

    // Lower body: P = Rz(−torsion)·Rx(list); upper body: U = Rz(−thorax)·Ry(−forward/backward).
    const double ct = cos_of(0), st = sin_of(0);
    const double cl = cos_of(1), sl = sin_of(1);
    const mat3 P = { { { ct, st * cl, -st * sl }, { -st, ct * cl, -ct * sl }, { 0.0, sl, cl } } };
    const double ch = cos_of(2), sh = sin_of(2);
    const double cf = cos_of(3), sf = sin_of(3);
    const mat3 U = { { { ch * cf, sh, -ch * sf }, { -sh * cf, ch, sh * sf }, { sf, 0.0, cf } } };

    auto& cen = pose.centre;
    auto& ax = pose.axis;
    const vec3 y_axis = { 0.0, 1.0, 0.0 }, z_axis = { 0.0, 0.0, 1.0 };

    // Legs: the left one half a cycle after the right one. The foot vector (foot, 0,
    // −ankle_height)·H from the ankle to the toe is backscatterPedestrian's (Chen's is horizontal).
    const double lu = pr::upper_leg * h, ll = pr::lower_leg * h;
    const double lf = pr::foot * h, la = pr::ankle_height * h;
    const double foot_len = std::hypot(lf, la);
    for (int side = 0; side < 2; ++side) { // 0 left, 1 right
        const double sy = side == 0 ? 1.0 : -1.0;
        const vec3 hip = { 0.0, sy * pr::hip_half_width * h, 0.0 };
        const vec3 thigh = limb_of(4 + side), shank = limb_of(6 + side);
        const vec3 knee = { hip[0] + lu * thigh[0], hip[1], lu * thigh[2] };
        const vec3 ankle = { knee[0] + ll * shank[0], hip[1], knee[2] + ll * shank[2] };
        const double cq = cos_of(8 + side), sq = sin_of(8 + side);
        const vec3 foot = { (lf * cq + la * sq) / foot_len, 0.0, (lf * sq - la * cq) / foot_len };
        const vec3 toe = { ankle[0] + foot_len * foot[0], hip[1], ankle[2] + foot_len * foot[2] };
        const vec3 hip_r = mul(P, hip), knee_r = mul(P, knee), ankle_r = mul(P, ankle),
                   toe_r = mul(P, toe);
        cen[left_foot + side] = add(mid(ankle_r, toe_r), trans);
        cen[left_lower_leg + side] = add(mid(knee_r, ankle_r), trans);
        cen[left_upper_leg + side] = add(mid(hip_r, knee_r), trans);
        cen[left_hip + side] = add({ 0.5 * hip_r[0], 0.5 * hip_r[1], 0.5 * hip_r[2] }, trans);
        ax[left_foot + side] = mul(P, foot);
        ax[left_lower_leg + side] = mul(P, shank);
        ax[left_upper_leg + side] = mul(P, thigh);
        ax[left_hip + side] = mul(P, y_axis);
    }

    // Arms: the shoulder swings the upper arm, the elbow the lower arm, both forward.
    const double lt = pr::torso * h, lua = pr::upper_arm * h, lla = pr::lower_arm * h;
    for (int side = 0; side < 2; ++side) {
        const double sy = side == 0 ? 1.0 : -1.0;
        const vec3 shoulder = { 0.0, sy * pr::shoulder_half_width * h, lt };
        const vec3 upper = limb_of(10 + side), lower = limb_of(12 + side);
        const vec3 elbow = { lua * upper[0], shoulder[1], lt + lua * upper[2] };
        const vec3 hand = { elbow[0] + lla * lower[0], shoulder[1], elbow[2] + lla * lower[2] };
        const vec3 shoulder_r = mul(U, shoulder), elbow_r = mul(U, elbow), hand_r = mul(U, hand);
        cen[left_lower_arm + side] = add(mid(elbow_r, hand_r), trans);
        cen[left_upper_arm + side] = add(mid(shoulder_r, elbow_r), trans);
        cen[left_shoulder + side] = add(mul(U, { 0.0, 0.5 * shoulder[1], lt }), trans);
        ax[left_lower_arm + side] = mul(U, lower);
        ax[left_upper_arm + side] = mul(U, upper);
        ax[left_shoulder + side] = mul(U, y_axis);
    }
    const vec3 up = mul(U, z_axis);
    // The head above the neck, as the chain of lengths that sums to the height has it
    // (backscatterPedestrian's standing pose; its walking trajectories and Chen's drop the neck).
    const double head_z = lt + (pr::neck + 0.5 * pr::head) * h;
    cen[head] = add({ head_z * up[0], head_z * up[1], head_z * up[2] }, trans);
    cen[torso] = add({ 0.5 * lt * up[0], 0.5 * lt * up[1], 0.5 * lt * up[2] }, trans);
    ax[head] = up;
    ax[torso] = up;
}

void walker_model::scatter(const body_pose& pose, double* r_m, double* amplitude) const
{
    for (int s = 0; s < n_segments; ++s) {
        r_m[s] = -dot(pose.centre[s], d_los);
        const double c = dot(pose.axis[s], d_los);
        // sqrt(σ) = sqrt(π)·a²·c / (a²·sin²ψ + c²·cos²ψ)
        amplitude[s] = d_sqrtpi_a2c[s] / (d_a2[s] + (d_c2[s] - d_a2[s]) * c * c);
    }
}

void walker_model::pose(double t_s, body_pose& pose) const
{
    if (!std::isfinite(t_s))
        throw std::invalid_argument("walker: time t_s must be finite, got " + text(t_s));
    cycle_pose(frac(t_s * d_inv_cycle + d_phase_cycles), pose);
}

void walker_model::scatterers(const double* t_s, int count, double* r_m, double* amplitude, double* centre_m) const
{
    // A chunk of instants at a time: their gait states, then the sines and cosines of all their
    // joint angles in one vectorised pass, then the poses.
    constexpr int chunk = 32;
    gait_state g[chunk];
    double a[n_joint_angles * chunk], sn[n_joint_angles * chunk], cs[n_joint_angles * chunk];
    double j_a[n_joint_angles];
    body_pose bp;
    double r[n_segments], amp[n_segments];
    for (int n0 = 0; n0 < count; n0 += chunk) {
        const int len = std::min(chunk, count - n0);
        for (int i = 0; i < len; ++i) {
            const double t = t_s[n0 + i];
            if (!std::isfinite(t))
                throw std::invalid_argument("walker: time t_s must be finite, got " + text(t));
            g[i] = state(frac(t * d_inv_cycle + d_phase_cycles));
            joint_angles(g[i], j_a);
            for (int j = 0; j < n_joint_angles; ++j)
                a[j * len + i] = j_a[j];
        }
        detail::sincos_batch(a, sn, cs, size_t(n_joint_angles) * len);
        for (int i = 0; i < len; ++i) {
            pose_from(g[i], sn + i, cs + i, len, bp);
            scatter(bp, r, amp);
            for (int s = 0; s < n_segments; ++s) {
                r_m[size_t(s) * count + n0 + i] = r[s];
                amplitude[size_t(s) * count + n0 + i] = amp[s] * d_scale;
            }
            if (centre_m)
                for (int s = 0; s < n_segments; ++s)
                    for (int k = 0; k < 3; ++k)
                        centre_m[size_t(3 * s + k) * count + n0 + i] = bp.centre[s][k];
        }
    }
}

void walker_model::scatterers(double t_s, double* r_m, double* amplitude) const
{
    body_pose bp;
    pose(t_s, bp);
    scatter(bp, r_m, amplitude);
    for (int s = 0; s < n_segments; ++s)
        amplitude[s] *= d_scale;
}

} // namespace walker
} // namespace sems
} // namespace gr
