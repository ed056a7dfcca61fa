// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the walking human against the published Boulic–Thalmann model (cycle duration,
 * trajectory control points and formulas, the stance/swing kinematics they imply, the gait
 * boundaries), the peak-speed bound the channel models plan with, the ellipsoid RCS closed
 * forms, the geometry conventions and bad input. */
#include <gnuradio/sems/core/scene/walker_model.h>
#include "core/scene/walker_scatterers.h"
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace gr::sems::walker;
using gr::sems::qa::assert_error;

namespace {

constexpr double deg = M_PI / 180.0;

walker_params params(double height, double speed, double heading = 0.0, double phase = 0.0,
                     double elevation = 0.0)
{
    walker_params p;
    p.height_m = height;
    p.speed_mps = speed;
    p.heading_rad = heading;
    p.phase_rad = phase;
    p.elevation_rad = elevation;
    return p;
}

struct sample {
    std::array<double, n_segments> r, a;
};

sample at(const walker_model& w, double t)
{
    sample s;
    w.scatterers(t, s.r.data(), s.a.data());
    return s;
}

// Radial velocity towards the radar in the world (bulk + micro-motion), m/s.
double towards(const walker_model& w, int seg, double t)
{
    const double dt = 1e-5;
    const auto& p = w.params();
    const double bulk = p.speed_mps * std::cos(p.heading_rad) * std::cos(p.elevation_rad);
    return bulk - (at(w, t + dt).r[seg] - at(w, t - dt).r[seg]) / (2.0 * dt);
}

double angle_between(const vec3& a, const vec3& b)
{
    const double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const double na = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    const double nb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    return std::acos(std::max(-1.0, std::min(1.0, d / (na * nb))));
}

double correlation(const std::vector<double>& x, const std::vector<double>& y)
{
    const double n = x.size();
    double mx = 0, my = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        mx += x[i] / n;
        my += y[i] / n;
    }
    double sxy = 0, sxx = 0, syy = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
        syy += (y[i] - my) * (y[i] - my);
    }
    return sxy / std::sqrt(sxx * syy);
}

// The radial displacement of one segment over one cycle, n samples.
std::vector<double> track(const walker_model& w, int seg, int n = 400)
{
    std::vector<double> r(n);
    for (int j = 0; j < n; ++j)
        r[j] = at(w, (j + 0.5) / n * w.cycle_duration_s()).r[seg];
    return r;
}

double peak_to_peak(const std::vector<double>& x)
{
    const auto mm = std::minmax_element(x.begin(), x.end());
    return *mm.second - *mm.first;
}

// Σ_s of the cycle mean of a_s².
double mean_power(const walker_model& w, int n = 4096)
{
    double sum = 0.0;
    for (int j = 0; j < n; ++j) {
        const auto s = at(w, (j + 0.25) / n * w.cycle_duration_s());
        for (double a : s.a)
            sum += a * a / n;
    }
    return sum;
}

// The published ellipsoid RCS, σ = π a²b²c² / (a² sin²θ cos²φ + b² sin²θ sin²φ + c² cos²θ)².
double ellipsoid_rcs(double a, double b, double c, double theta, double phi)
{
    const double st = std::sin(theta), ct = std::cos(theta);
    const double den = a * a * st * st * std::cos(phi) * std::cos(phi) +
                       b * b * st * st * std::sin(phi) * std::sin(phi) + c * c * ct * ct;
    return M_PI * a * a * b * b * c * c / (den * den);
}

// The largest speed of any segment centre relative to the body (the norm of its velocity in
// the body frame, by central differences) over n instants of one cycle, m/s.
double peak_segment_speed(const walker_model& w, int n)
{
    const double dc = w.cycle_duration_s(), dt = 1e-5 * dc;
    double peak = 0.0;
    body_pose a, b;
    for (int j = 0; j < n; ++j) {
        const double t = (j + 0.5) / n * dc;
        w.pose(t - dt, a);
        w.pose(t + dt, b);
        for (int s = 0; s < n_segments; ++s) {
            double v2 = 0.0;
            for (int k = 0; k < 3; ++k)
                v2 += std::pow((b.centre[s][k] - a.centre[s][k]) / (2.0 * dt), 2);
            peak = std::max(peak, std::sqrt(v2));
        }
    }
    return peak;
}

// Gait C's hip flexion minus gait B's as RV passes 1.3, in degrees, at cycle time u (walker.md,
// "Gait boundaries"). Gait C's first control point (0.2·sc − 0.1, 5·sc + 25) closes on its third
// (0.9, 6·sc + 25) as sc → 0, but the secant across the closing gap stays −5°/cycle; pchip's
// slope there (weights 2h₁ + h₀ and h₁ + 2h₀ with h₀ → 0, h₁ = 0.6) tends to 3/(2/d₀ + 1/d₁)
// with d₀ = −5 and d₁ = −40/0.6 °/cycle (to the point at 0.5), where gait B, whose two points
// are one, has slope 0. The piece from 0.9 to 1.5 (≡ 0.5) differs by the Hermite term h₁·m·s(1 − s)².
double hip_jump_at_1_3_deg(double u)
{
    const double m = 3.0 / (2.0 / -5.0 + 1.0 / (-40.0 / 0.6)); // −7.2289 °/cycle
    const double s = (u - 0.9 - std::floor(u - 0.9)) / 0.6;
    return s < 1.0 ? 0.6 * m * s * (1.0 - s) * (1.0 - s) : 0.0;
}

// p turned by angle a (rad) about the unit axis k through the point c.
vec3 turned(const vec3& p, const vec3& c, const vec3& k, double a)
{
    const vec3 d = { p[0] - c[0], p[1] - c[1], p[2] - c[2] };
    const double kd = k[0] * d[0] + k[1] * d[1] + k[2] * d[2];
    const vec3 kxd = { k[1] * d[2] - k[2] * d[1], k[2] * d[0] - k[0] * d[2], k[0] * d[1] - k[1] * d[0] };
    vec3 r;
    for (int i = 0; i < 3; ++i)
        r[i] = c[i] + d[i] * std::cos(a) + kxd[i] * std::sin(a) + k[i] * kd * (1.0 - std::cos(a));
    return r;
}

} // namespace

class qa_walker_model : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_walker_model);
    CPPUNIT_TEST(proportions_add_up_to_the_height);
    CPPUNIT_TEST(cycle_duration_follows_boulic);
    CPPUNIT_TEST(trajectories_follow_the_published_curves);
    CPPUNIT_TEST(gaits_join_but_for_the_published_hip_jump);
    CPPUNIT_TEST(pose_carries_the_joint_angles);
    CPPUNIT_TEST(torso_line_sits_at_the_bulk_velocity);
    CPPUNIT_TEST(feet_rest_in_stance_and_cover_the_stride_in_swing);
    CPPUNIT_TEST(peak_speed_bound_holds_and_is_tight);
    CPPUNIT_TEST(class_peak_speed_covers_its_walkers);
    CPPUNIT_TEST(arms_swing_against_the_legs);
    CPPUNIT_TEST(crossing_walker_moves_only_laterally);
    CPPUNIT_TEST(speed_outside_the_model_is_refused);
    CPPUNIT_TEST(still_body_at_speed_zero);
    CPPUNIT_TEST(amplitudes_follow_the_ellipsoid_rcs);
    CPPUNIT_TEST(amplitudes_are_normalized_over_a_cycle);
    CPPUNIT_TEST(extremes_stay_finite_and_exact);
    CPPUNIT_TEST(many_instants_equal_one_at_a_time);
    CPPUNIT_TEST_SUITE_END();

public:
    void proportions_add_up_to_the_height()
    {
        namespace pr = proportion;
        CPPUNIT_ASSERT_DOUBLES_EQUAL(
            1.0, pr::ankle_height + pr::lower_leg + pr::upper_leg + pr::torso + pr::neck + pr::head,
            1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.53, pr::hip_joint_height, 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.954, leg_length_m(1.8), 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(3.0 * 0.954, max_speed_mps(1.8), 1e-12);
        const auto& t = segment_shapes();
        std::set<std::string> names;
        for (const auto& s : t) {
            names.insert(s.name);
            CPPUNIT_ASSERT(s.length > 0.0 && s.radius > 0.0);
        }
        CPPUNIT_ASSERT_EQUAL(size_t(n_segments), names.size());
        CPPUNIT_ASSERT_EQUAL(std::string("torso"), std::string(t[torso].name));
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::hypot(0.143, 0.039), t[left_foot].length, 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.15 / 1.8, t[torso].radius, 1e-12); // Chen: 0.15 m at 1.8 m
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.288, t[torso].length, 1e-12);
    }

    void cycle_duration_follows_boulic()
    {
        // D_c = RL_c / RV with RL_c = 1.346·sqrt(RV), RV = v / (0.53·H).
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.1111, cycle_duration_s(1.8, 1.4), 1e-4);
        for (double h : { 0.5, 1.8, 2.5 })
            for (double rv : { 0.1, 0.5, 1.0, 2.0, 3.0 }) {
                const double v = rv * 0.53 * h, dc = 1.346 * std::sqrt(rv) / rv;
                CPPUNIT_ASSERT_DOUBLES_EQUAL(dc, cycle_duration_s(h, v), 1e-12 * dc);
                const walker_model w(params(h, v, 0.3, 0.7));
                CPPUNIT_ASSERT_DOUBLES_EQUAL(dc, w.cycle_duration_s(), 1e-12 * dc);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(rv, w.relative_velocity(), 1e-12);
                CPPUNIT_ASSERT_DOUBLES_EQUAL((0.752 * dc - 0.143) / dc, w.support_fraction(), 1e-12);
                for (double t : { 0.0, 0.37, 5.1 }) {
                    const auto a = at(w, t), b = at(w, t + dc), c = at(w, t + 0.5 * dc);
                    for (int s = 0; s < n_segments; ++s) {
                        CPPUNIT_ASSERT_DOUBLES_EQUAL(a.r[s], b.r[s], 1e-9);
                        CPPUNIT_ASSERT_DOUBLES_EQUAL(a.a[s], b.a[s], 1e-9);
                    }
                    // Half a cycle swaps the legs: not a period.
                    CPPUNIT_ASSERT(std::fabs(a.r[right_foot] - c.r[right_foot]) > 1e-3 * h * rv);
                }
            }
    }

    void trajectories_follow_the_published_curves()
    {
        // 1.4 m/s at 1.8 m: RV = 1.4675, Boulic's gait C; sc the position across it.
        const walker_model w(params(1.8, 1.4));
        const double rv = w.relative_velocity(), sc = (rv - 1.3) / 1.7, rds = w.support_fraction();
        // Control points (appendices C and D), as (cycle time, degrees).
        auto check = [&](double x, double want, double (*get)(const gait_trajectories&)) {
            const double u = x - std::floor(x);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(want, get(w.trajectories(u)), 1e-9);
        };
        using G = const gait_trajectories&;
        check(0.2 * sc - 0.1, 5 * sc + 25, [](G g) { return g.hip_deg; });
        check(0.5, -15, [](G g) { return g.hip_deg; });
        check(0.9, 6 * sc + 25, [](G g) { return g.hip_deg; });
        check(0.17 - 0.05 * sc, 22 * sc + 3, [](G g) { return g.knee_deg; });
        check(0.4, 3, [](G g) { return g.knee_deg; });
        check(0.75 - 0.05 * sc, 70 - 5 * sc, [](G g) { return g.knee_deg; });
        check(1.0 - 0.03 * sc, 3 * sc + 3, [](G g) { return g.knee_deg; });
        check(0.0, 5 * sc - 3, [](G g) { return g.ankle_deg; });
        check(0.08, 4 * sc - 18, [](G g) { return g.ankle_deg; });
        check(0.5 - 0.1 * sc, 8 - 3 * sc, [](G g) { return g.ankle_deg; });
        check(rds, -8 * sc - 20, [](G g) { return g.ankle_deg; });
        check(0.85, 5 * sc - 3, [](G g) { return g.ankle_deg; });
        check(0.1, 4.0 / 3 * rv, [](G g) { return g.thorax_deg; });
        check(0.4, -4.5 / 3 * rv, [](G g) { return g.thorax_deg; });
        check(0.6, -4.0 / 3 * rv, [](G g) { return g.thorax_deg; });
        check(0.9, 4.5 / 3 * rv, [](G g) { return g.thorax_deg; });
        check(0.05, 14 - 6 * sc, [](G g) { return g.elbow_deg; });
        check(0.51 + 0.04 * sc, 44 + 26 * sc, [](G g) { return g.elbow_deg; });
        check(0.9 - 0.1 * sc, 17 - 6 * sc, [](G g) { return g.elbow_deg; });
        // The knee's pchip keeps its shape: rising from 3° at 0.4 to the swing peak, no overshoot.
        double prev = -1e9, hi = -1e9;
        for (int j = 0; j < 1000; ++j) {
            const double u = j / 1000.0, k = w.trajectories(u).knee_deg;
            hi = std::max(hi, k);
            if (u > 0.4 && u < 0.75 - 0.05 * sc) {
                CPPUNIT_ASSERT(k >= prev);
                prev = k;
            }
        }
        CPPUNIT_ASSERT_DOUBLES_EQUAL(70 - 5 * sc, hi, 1e-3);
        // The closed-form trajectories (appendices A, B, D) at any cycle time.
        const double phi_fb = 0.625 - rds;
        for (double u : { 0.0, 0.1, 0.15, 0.33, 0.5, 0.65, 0.8, 0.99 }) {
            const auto g = w.trajectories(u);
            const double s = 2 * M_PI * u;
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.015 * rv * (std::sin(2 * M_PI * (2 * u - 0.35)) - 1),
                                         g.vertical_m, 1e-12);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(-0.032 * std::sin(2 * M_PI * (u - 0.1)), g.lateral_m, 1e-12);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(-0.021 * std::sin(2 * M_PI * (2 * u + 2 * phi_fb)),
                                         g.forward_m, 1e-12);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(2.0 * (std::sin(2 * M_PI * (2 * u - 0.1)) - 1),
                                         g.pelvis_forward_deg, 1e-9);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(-4.0 * rv * std::cos(s), g.pelvis_torsion_deg, 1e-9);
            const double as = 9.88 * rv;
            CPPUNIT_ASSERT_DOUBLES_EQUAL(3 - as / 2 - as * std::cos(s), g.shoulder_deg, 1e-9);
        }
        // Left/right rotation: 0 at heel strikes, −2·A_2 and +2·A_2 at 0.15 and 0.65, A_2 = 1.66·RV.
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, w.trajectories(0.0).pelvis_list_deg, 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-2 * 1.66 * rv, w.trajectories(0.15).pelvis_list_deg, 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, w.trajectories(0.5).pelvis_list_deg, 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(2 * 1.66 * rv, w.trajectories(0.65).pelvis_list_deg, 1e-9);
        for (double u : { -0.1, 1.0, std::nan("") })
            assert_error([&] { w.trajectories(u); }, "cycle time u", "[0, 1)");
        // Gait A (RV = 0.3): amplitudes grow with RV from a still body.
        const walker_model slow(params(1.8, 0.3 * 0.954));
        const double r = slow.relative_velocity();
        CPPUNIT_ASSERT_DOUBLES_EQUAL(50 * r, slow.trajectories(0.9).hip_deg, 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-30 * r, slow.trajectories(0.5).hip_deg, 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(140 * r, slow.trajectories(0.75).knee_deg, 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(34 * r + 3, slow.trajectories(0.5).elbow_deg, 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-30 * r - 3, slow.trajectories(0.08).ankle_deg, 1e-9);
        // Lateral amplitude |−0.128·RV² + 0.128·RV|, towards the stance leg (−y at u = 0.35).
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-0.128 * r * (1 - r), slow.trajectories(0.35).lateral_m, 1e-12);
    }

    void gaits_join_but_for_the_published_hip_jump()
    {
        // Walkers 1e-6 of RV either side of the gait boundaries 0.5 and 1.3 must agree in every
        // trajectory and every segment centre to within what a smooth trajectory moves over
        // 2e-6 of RV, but for the documented jump: gait C's hip flexion (both hips, the left half
        // a cycle later) and with it the legs turned about the hip joints. Tolerances = slope
        // bound × 2e-6: joint angles 500° per unit of RV (the steepest published law is gait A's
        // knee peak 140·RV; knots moving with RV and the support fraction add less) → 1e-3°;
        // translations 0.5 m per unit of RV (gait A's 0.128·RV(1 − RV)) → 1e-6 m; segment
        // centres 500° per unit of RV on a lever of at most H, plus the translations →
        // (8.73·H + 0.5)·2e-6 m. The same tolerances bound the change over 2e-6 of RV on either
        // side, so a smooth trajectory passes and any other jump above them fails.
        const double d_rv = 1e-6, tol_deg = 500.0 * 2e-6, tol_m = 0.5 * 2e-6;
        const char* names[] = { "vertical", "lateral", "forward", "pelvis forward", "pelvis list",
                                "pelvis torsion", "hip", "knee", "ankle", "thorax", "shoulder", "elbow" };
        auto fields = [](const gait_trajectories& g) {
            return std::array<double, 12>{ g.vertical_m, g.lateral_m, g.forward_m, g.pelvis_forward_deg,
                                           g.pelvis_list_deg, g.pelvis_torsion_deg, g.hip_deg, g.knee_deg,
                                           g.ankle_deg, g.thorax_deg, g.shoulder_deg, g.elbow_deg };
        };
        for (double h : { 1.0, 1.8 })
            for (double rv : { 0.5, 1.3 }) {
                const double tol_c = (500.0 * deg * h + 0.5) * 2e-6;
                const walker_model lo2(params(h, (rv - 3 * d_rv) * 0.53 * h)), lo(params(h, (rv - d_rv) * 0.53 * h)),
                    hi(params(h, (rv + d_rv) * 0.53 * h)), hi2(params(h, (rv + 3 * d_rv) * 0.53 * h));
                const int n = 1000;
                for (int j = 0; j <= n; ++j) {
                    const double u = j < n ? (j + 0.5) / n : 0.1; // and the jump's peak
                    const auto f_lo2 = fields(lo2.trajectories(u)), f_lo = fields(lo.trajectories(u));
                    const auto f_hi = fields(hi.trajectories(u)), f_hi2 = fields(hi2.trajectories(u));
                    for (int i = 0; i < 12; ++i) {
                        const double tol = i < 3 ? tol_m : tol_deg;
                        const double jump = rv == 1.3 && i == 6 ? hip_jump_at_1_3_deg(u) : 0.0;
                        if (std::fabs(f_lo[i] - f_lo2[i]) <= tol && std::fabs(f_hi2[i] - f_hi[i]) <= tol &&
                            std::fabs(f_hi[i] - f_lo[i] - jump) <= tol)
                            continue;
                        std::ostringstream what;
                        what << names[i] << " at RV " << rv << " ± 1e-6, u = " << u << ", height " << h << ": "
                             << f_lo2[i] << ", " << f_lo[i] << " below, " << f_hi[i] << ", " << f_hi2[i]
                             << " above (at ∓3e-6 and ∓1e-6), documented jump " << jump << ", tolerance " << tol;
                        CPPUNIT_FAIL(what.str());
                    }
                    // The centres: the walker below with each leg turned about its hip joint by
                    // its hip's jump (right: u, left: u + 1/2), within tol_c of the one above.
                    body_pose a, b;
                    lo.pose(u * lo.cycle_duration_s(), a);
                    hi.pose(u * hi.cycle_duration_s(), b);
                    vec3 trans;
                    for (int k = 0; k < 3; ++k)
                        trans[k] = 0.5 * (a.centre[left_hip][k] + a.centre[right_hip][k]);
                    auto want = a.centre;
                    for (int side = 0; side < 2; ++side) { // 0 left, 1 right
                        const double jump = rv == 1.3 ? hip_jump_at_1_3_deg(side == 0 ? u + 0.5 : u) : 0.0;
                        vec3 joint;
                        for (int k = 0; k < 3; ++k)
                            joint[k] = 2.0 * a.centre[left_hip + side][k] - trans[k];
                        // Flexion by +δ turns the leg by −δ about the pelvis's y axis.
                        for (int s : { left_foot + side, left_lower_leg + side, left_upper_leg + side })
                            want[s] = turned(a.centre[s], joint, a.axis[left_hip], -jump * deg);
                    }
                    for (int s = 0; s < n_segments; ++s)
                        for (int k = 0; k < 3; ++k) {
                            if (std::fabs(b.centre[s][k] - want[s][k]) <= tol_c)
                                continue;
                            std::ostringstream what;
                            what << segment_shapes()[s].name << " centre (coordinate " << k << ") at RV " << rv
                                 << " ± 1e-6, u = " << u << ", height " << h << ": " << b.centre[s][k]
                                 << " m above, " << want[s][k] << " m from below with the documented jump, tolerance "
                                 << tol_c;
                            CPPUNIT_FAIL(what.str());
                        }
                }
            }
        // The documented jump is what the model does: 0.643° at u = 0.1.
        const walker_model b(params(1.8, (1.3 - d_rv) * 0.954)), c(params(1.8, (1.3 + d_rv) * 0.954));
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-0.6426, c.trajectories(0.1).hip_deg - b.trajectories(0.1).hip_deg, 1e-4);
    }

    void pose_carries_the_joint_angles()
    {
        const walker_model w(params(1.75, 1.6, 0.4, 0.0, 0.2));
        const double rest_foot = std::acos(0.039 / std::hypot(0.143, 0.039));
        for (double u : { 0.0, 0.13, 0.42, 0.7, 0.91 }) {
            body_pose p;
            w.pose(u * w.cycle_duration_s(), p);
            const auto g = w.trajectories(u), gl = w.trajectories(u < 0.5 ? u + 0.5 : u - 0.5);
            const auto& ax = p.axis;
            CPPUNIT_ASSERT_DOUBLES_EQUAL(g.knee_deg, angle_between(ax[right_upper_leg], ax[right_lower_leg]) / deg, 1e-9);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(gl.knee_deg, angle_between(ax[left_upper_leg], ax[left_lower_leg]) / deg, 1e-9);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(g.elbow_deg, angle_between(ax[right_upper_arm], ax[right_lower_arm]) / deg, 1e-9);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(gl.elbow_deg, angle_between(ax[left_upper_arm], ax[left_lower_arm]) / deg, 1e-9);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(rest_foot / deg + g.ankle_deg, angle_between(ax[right_lower_leg], ax[right_foot]) / deg, 1e-9);
            const vec3 down = { -ax[torso][0], -ax[torso][1], -ax[torso][2] };
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::fabs(g.shoulder_deg), angle_between(down, ax[right_upper_arm]) / deg, 1e-9);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::fabs(gl.shoulder_deg), angle_between(down, ax[left_upper_arm]) / deg, 1e-9);
            for (const auto& a : ax) // unit axes
                CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), 1e-12);
            // The left hip on the left, the head above the torso above the feet.
            CPPUNIT_ASSERT(p.centre[left_hip][1] > 0.0 && p.centre[right_hip][1] < 0.0);
            CPPUNIT_ASSERT(p.centre[head][2] > p.centre[torso][2]);
            CPPUNIT_ASSERT(p.centre[torso][2] > p.centre[left_foot][2] + 0.4 * 1.75);
        }
    }

    void torso_line_sits_at_the_bulk_velocity()
    {
        const double v = 1.4;
        const walker_model w(params(1.8, v));
        const int n = 2000;
        const double dc = w.cycle_duration_s();
        std::array<double, n_segments> power{};
        double torso_v = 0.0, weighted_v = 0.0, total = 0.0;
        for (int j = 0; j < n; ++j) {
            const double t = (j + 0.5) / n * dc;
            const auto s = at(w, t);
            for (int k = 0; k < n_segments; ++k) {
                power[k] += s.a[k] * s.a[k] / n;
                const double vk = towards(w, k, t);
                weighted_v += s.a[k] * s.a[k] * vk / n;
                total += s.a[k] * s.a[k] / n;
            }
            torso_v += towards(w, torso, t) / n;
        }
        // The torso is the strongest scatterer and its line is the bulk velocity.
        CPPUNIT_ASSERT_EQUAL(long(torso), long(std::max_element(power.begin(), power.end()) - power.begin()));
        CPPUNIT_ASSERT_DOUBLES_EQUAL(v, torso_v, 1e-6);
        // Its displacement about the mean motion stays small next to the feet's.
        CPPUNIT_ASSERT(peak_to_peak(track(w, torso)) < 0.1);
        CPPUNIT_ASSERT(peak_to_peak(track(w, torso)) < 0.15 * peak_to_peak(track(w, right_foot)));
        // The power-weighted Doppler centroid of the body stays near the bulk line.
        CPPUNIT_ASSERT_DOUBLES_EQUAL(v, weighted_v / total, 0.1 * v);
    }

    void feet_rest_in_stance_and_cover_the_stride_in_swing()
    {
        // A foot at rest in stance (0 <= u < support) must cover a stride in the swing time:
        // its mean swing velocity is v / (1 − support); the lower leg's centre moves from
        // near rest in stance to a swing peak of 2 to 3 times the walking speed. The model
        // has no foot-ground constraint: over normal walking speeds (RV 1.1 to 2.1 at 1.8 m)
        // the stance foot slides by less than 0.15·v (more at slow speeds: walker.md).
        for (double v : { 1.1, 1.4, 2.0 }) {
            const walker_model w(params(1.8, v));
            const double dc = w.cycle_duration_s(), ds = w.support_fraction();
            const int n = 1000;
            double stance = 0, swing = 0, foot_peak = 0, leg_min = 1e9, leg_max = -1e9;
            int n_stance = 0, n_swing = 0;
            for (int j = 0; j < n; ++j) {
                const double u = (j + 0.5) / n;
                const double vf = towards(w, right_foot, u * dc), vl = towards(w, right_lower_leg, u * dc);
                (u < ds ? stance : swing) += vf;
                ++(u < ds ? n_stance : n_swing);
                foot_peak = std::max(foot_peak, vf);
                leg_min = std::min(leg_min, vl);
                leg_max = std::max(leg_max, vl);
            }
            const double swing_mean = v / (1.0 - ds);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, stance / n_stance, 0.15 * v);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(swing_mean, swing / n_swing, 0.1 * swing_mean);
            CPPUNIT_ASSERT(foot_peak > swing_mean);
            CPPUNIT_ASSERT(leg_min < 0.35 * v);
            CPPUNIT_ASSERT(leg_max > 2.0 * v && leg_max < 3.0 * v);
        }
    }

    void peak_speed_bound_holds_and_is_tight()
    {
        // detail::walker_peak_speed_mps bounds the speed of every segment centre relative to the
        // body (the 3-D norm, so the radial speed at any heading and elevation too), sampled at
        // 512 instants of the cycle, on heights 1 to 2 m and RV over the whole range: 0.02 apart,
        // 0.005 apart over the peak (0.2 to 0.85), near 0 and either side of the gait boundaries.
        // Tight: at most 6 % above the sampled peak for RV >= 0.05 (the table's own margin is 2 to
        // 3.1 %, sampling 512 instants misses the peak by under 0.2 %), at most 50 % above it
        // below RV 0.05, where every segment is slower than 0.08 m/s.
        std::vector<double> rvs = { 1e-4, 1e-3, 3e-3, 0.005, 0.008, 0.012, 0.015, 0.025, 0.04,
                                    0.5 - 1e-6, 0.5 + 1e-6, 1.3 - 1e-6, 1.3 + 1e-6 };
        for (int i = 1; i <= 150; ++i)
            rvs.push_back(0.02 * i);
        for (int i = 0; i <= 130; ++i)
            rvs.push_back(0.2 + 0.005 * i);
        double loose = 0.0, loose_slow = 0.0, peak_per_v = 0.0; // the last over RV 0.25 to 0.8
        for (double h : { 1.0, 1.25, 1.5, 1.75, 2.0 })
            for (double rv : rvs) {
                const double v = std::min(rv * 0.53 * h, max_speed_mps(h));
                const walker_model w(params(h, v));
                const double peak = peak_segment_speed(w, 512);
                const double bound = gr::sems::detail::walker_peak_speed_mps(h, v);
                std::ostringstream what;
                what << "height " << h << " m, RV " << rv << ": peak " << peak << " m/s, bound " << bound;
                CPPUNIT_ASSERT_MESSAGE(what.str(), peak <= bound);
                double& worst = rv >= 0.05 ? loose : loose_slow;
                worst = std::max(worst, bound / peak);
                if (rv >= 0.25 && rv <= 0.8)
                    peak_per_v = std::max(peak_per_v, peak / v);
            }
        CPPUNIT_ASSERT(loose <= 1.06);
        CPPUNIT_ASSERT(loose_slow <= 1.5);
        // The peak reaches 5.4 v at RV 0.5 (at 1 m), beyond any bound of 4.5 v.
        CPPUNIT_ASSERT(peak_per_v > 5.3);
        // A still body has no micro-motion; the sign of the speed does not matter (a walker that
        // walks away has heading π).
        CPPUNIT_ASSERT_EQUAL(0.0, gr::sems::detail::walker_peak_speed_mps(1.8, 0.0));
        CPPUNIT_ASSERT_EQUAL(gr::sems::detail::walker_peak_speed_mps(1.8, 1.4),
                             gr::sems::detail::walker_peak_speed_mps(1.8, -1.4));
        // Outside the model there is no bound.
        assert_error([] { gr::sems::detail::walker_peak_speed_mps(1.8, 3.0); }, "speed_mps 3", "0 <= RV <= 3");
        assert_error([] { gr::sems::detail::walker_peak_speed_mps(0.3, 0.5); }, "height_m");
    }

    void class_peak_speed_covers_its_walkers()
    {
        // The bound over a class (heights in an interval, speeds up to a maximum) covers the bound
        // of every walker in it, also where the class peaks inside its height interval, and
        // stays within 2 % of the largest of them.
        using gr::sems::detail::walker_peak_speed_mps;
        struct box {
            double h_min, h_max, v_max;
        };
        for (const box& c : { box{ 1.0, 2.0, 0.5 }, box{ 1.0, 3.0, 0.3 }, box{ 0.5, 3.0, 0.795 },
                              box{ 1.6, 1.9, 2.5 }, box{ 1.0, 1.3, 1.2 }, box{ 1.75, 1.75, 1.4 } }) {
            double largest = 0.0, corners = 0.0;
            for (int i = 0; i <= 200; ++i)
                for (int k = 0; k <= 200; ++k) {
                    const double h = c.h_min + (c.h_max - c.h_min) * i / 200, v = c.v_max * k / 200;
                    largest = std::max(largest, walker_peak_speed_mps(h, v));
                    if ((i == 0 || i == 200) && k == 200)
                        corners = std::max(corners, walker_peak_speed_mps(h, v));
                }
            const double b = walker_peak_speed_mps(c.h_min, c.h_max, c.v_max);
            std::ostringstream what;
            what << "heights [" << c.h_min << ", " << c.h_max << "] m, speeds up to " << c.v_max << " m/s: class bound "
                 << b << ", largest walker bound " << largest << ", at the corners " << corners;
            CPPUNIT_ASSERT_MESSAGE(what.str(), b >= largest && b <= 1.02 * largest);
            if (c.h_min == 1.0 && c.h_max == 3.0) // RV 0.19 to 0.57: the peak is inside
                CPPUNIT_ASSERT_MESSAGE(what.str(), largest > 1.03 * corners);
        }
        assert_error([] { walker_peak_speed_mps(1.0, 2.0, 1.6); }, "speed_mps 1.6", "height_m 1 m");
        assert_error([] { walker_peak_speed_mps(2.0, 1.0, 1.0); }, "height interval", "empty");
    }

    void arms_swing_against_the_legs()
    {
        const walker_model w(params(1.8, 1.4));
        const auto rl = track(w, right_lower_leg), ll = track(w, left_lower_leg);
        const auto ra = track(w, right_lower_arm), la = track(w, left_lower_arm);
        CPPUNIT_ASSERT(correlation(rl, ra) < -0.8); // right arm back as the right leg swings forward
        CPPUNIT_ASSERT(correlation(ll, la) < -0.8);
        CPPUNIT_ASSERT(correlation(rl, ll) < -0.8); // the legs in opposite phase
        CPPUNIT_ASSERT(correlation(rl, la) > 0.8);  // each arm with the opposite leg
        // The arms' swing is smaller than the legs'.
        CPPUNIT_ASSERT(peak_to_peak(ra) < peak_to_peak(track(w, right_foot)));
    }

    void crossing_walker_moves_only_laterally()
    {
        const walker_model head_on(params(1.8, 1.4, 0.0)), crossing(params(1.8, 1.4, M_PI / 2)),
            away(params(1.8, 1.4, M_PI));
        // Crossing, the radar sees the lateral sway (2·0.032 m peak to peak) and the small
        // lateral share of the pelvis and thorax torsion, not the limbs' forward swing.
        for (int s = 0; s < n_segments; ++s)
            CPPUNIT_ASSERT(peak_to_peak(track(crossing, s)) < 0.2);
        for (int s : { left_foot, right_foot, left_lower_leg, right_lower_leg, left_lower_arm, right_lower_arm })
            CPPUNIT_ASSERT(peak_to_peak(track(crossing, s)) < 0.3 * peak_to_peak(track(head_on, s)));
        CPPUNIT_ASSERT_DOUBLES_EQUAL(2 * 0.032, peak_to_peak(track(crossing, torso)), 0.006);
        for (double t : { 0.1, 0.5, 0.77 }) {
            body_pose p;
            crossing.pose(t, p);
            const auto c = at(crossing, t), h = at(head_on, t), a = at(away, t);
            for (int s = 0; s < n_segments; ++s) {
                CPPUNIT_ASSERT_DOUBLES_EQUAL(-p.centre[s][1], c.r[s], 1e-12); // radar on the left
                CPPUNIT_ASSERT_DOUBLES_EQUAL(-p.centre[s][0], h.r[s], 1e-12); // radar ahead
                CPPUNIT_ASSERT_DOUBLES_EQUAL(-h.r[s], a.r[s], 1e-12);         // radar behind
            }
        }
        // Any heading and elevation: r = −p·u, u = (cos ε cos θ, cos ε sin θ, sin ε).
        const double theta = 2.2, eps = -0.4;
        const walker_model w(params(1.8, 1.4, theta, 0.3, eps));
        const vec3 u = { std::cos(eps) * std::cos(theta), std::cos(eps) * std::sin(theta), std::sin(eps) };
        for (int k = 0; k < 3; ++k)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(u[k], w.line_of_sight()[k], 1e-15);
        body_pose p;
        w.pose(0.61, p);
        const auto s = at(w, 0.61);
        for (int k = 0; k < n_segments; ++k)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(-(p.centre[k][0] * u[0] + p.centre[k][1] * u[1] + p.centre[k][2] * u[2]),
                                         s.r[k], 1e-12);
    }

    void speed_outside_the_model_is_refused()
    {
        // RV = v / (0.53·H) must lie in [0, 3]: at 1.8 m, 0 to 2.862 m/s.
        assert_error([] { walker_model w(params(1.8, 3.5)); }, "speed_mps 3.5 m/s", "height_m 1.8 m");
        assert_error([] { walker_model w(params(1.8, 3.5)); }, "0 <= RV <= 3", "0 to 2.862 m/s");
        assert_error([] { walker_model w(params(1.8, 3.5)); }, "Boulic", "3.66876");
        assert_error([] { cycle_duration_s(1.0, 1.6); }, "speed_mps 1.6", "0 to 1.59 m/s");
        assert_error([] { walker_model w(params(1.8, -0.1)); }, "speed_mps -0.1", "0 <= RV <= 3");
        assert_error([] { walker_model w(params(1.8, std::nan(""))); }, "speed_mps nan");
        assert_error([] { walker_model w(params(0.0, 1.0)); }, "height_m", "[0.5, 3] m");
        assert_error([] { walker_model w(params(-1.7, 1.0)); }, "height_m", "-1.7");
        assert_error([] { walker_model w(params(INFINITY, 1.0)); }, "height_m", "inf");
        assert_error([] { walker_model w(params(180.0, 1.0)); }, "height_m", "got 180"); // cm
        assert_error([] { cycle_duration_s(0.4, 0.01); }, "height_m", "got 0.4");
        assert_error([] { walker_model w(params(1.8, 1.0, NAN)); }, "heading_rad", "finite");
        assert_error([] { walker_model w(params(1.8, 1.0, 0.0, INFINITY)); }, "phase_rad", "finite");
        assert_error([] { walker_model w(params(1.8, 1.0, 0.0, 0.0, 1.6)); }, "elevation_rad", "1.6");
        const walker_model w(params(1.8, 1.0));
        double r[n_segments], a[n_segments];
        assert_error([&] { w.scatterers(NAN, r, a); }, "t_s", "finite");
        body_pose p;
        assert_error([&] { w.pose(INFINITY, p); }, "t_s", "finite");
        // The limit itself is legal.
        const walker_model fastest(params(1.8, max_speed_mps(1.8)));
        CPPUNIT_ASSERT_DOUBLES_EQUAL(3.0, fastest.relative_velocity(), 1e-12);
    }

    void still_body_at_speed_zero()
    {
        const walker_model w(params(1.8, 0.0, 0.3, 1.1));
        CPPUNIT_ASSERT(std::isinf(w.cycle_duration_s()));
        const auto s0 = at(w, 0.0);
        for (double t : { 0.37, 1e3, 1e6, -5.0 }) {
            const auto s = at(w, t);
            for (int k = 0; k < n_segments; ++k) {
                CPPUNIT_ASSERT_EQUAL(s0.r[k], s.r[k]);
                CPPUNIT_ASSERT_EQUAL(s0.a[k], s.a[k]);
            }
        }
        // The limit of a walker as the speed goes to 0 (the amplitudes grow from 0 in gait A).
        // The normalization differs (one pose against a cycle of them): compare shapes.
        const walker_model creeping(params(1.8, 1e-7, 0.3, 1.1));
        const auto c = at(creeping, 0.0);
        for (int k = 0; k < n_segments; ++k) {
            CPPUNIT_ASSERT_DOUBLES_EQUAL(s0.r[k], c.r[k], 1e-5);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(s0.a[k] / s0.a[torso], c.a[k] / c.a[torso], 1e-5);
        }
        double power = 0.0; // a still body: its one pose has Σ a² = 1
        for (double a : s0.a)
            power += a * a;
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, power, 1e-12);
    }

    void amplitudes_follow_the_ellipsoid_rcs()
    {
        // A still body upright, seen from ahead: torso, head, hips and shoulders broadside.
        const double h = 1.8;
        const auto& t = segment_shapes();
        auto sigma = [&](int s, double theta) {
            const double a = t[s].radius * h, c = 0.5 * t[s].length * h;
            return ellipsoid_rcs(a, a, c, theta, 0.3);
        };
        const walker_model front(params(h, 0.0));
        const auto f = at(front, 0.0);
        for (int s : { head, left_hip, right_hip, left_shoulder, right_shoulder })
            CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(sigma(s, M_PI / 2) / sigma(torso, M_PI / 2)),
                                         f.a[s] / f.a[torso], 1e-12);
        // The upper arm hangs 3° forward of the vertical (the shoulder's rest angle).
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(sigma(right_upper_arm, M_PI / 2 - 3 * deg) / sigma(torso, M_PI / 2)),
                                     f.a[right_upper_arm] / f.a[torso], 1e-12);
        // From overhead the torso and head are seen end-on, the hips broadside.
        const walker_model top(params(h, 0.0, 0.0, 0.0, M_PI / 2));
        const auto o = at(top, 0.0);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(sigma(head, 0.0) / sigma(torso, 0.0)), o.a[head] / o.a[torso], 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::sqrt(sigma(left_hip, M_PI / 2) / sigma(torso, 0.0)), o.a[left_hip] / o.a[torso], 1e-9);
        // Amplitudes depend on the aspect only: the same at every height for the same RV.
        const walker_model small(params(1.0, 0.53 * 1.4, 0.5, 0.2, 0.1)),
            tall(params(2.0, 1.06 * 1.4, 0.5, 0.2, 0.1));
        for (double u : { 0.1, 0.6 }) {
            const auto a = at(small, u * small.cycle_duration_s()), b = at(tall, u * tall.cycle_duration_s());
            for (int s = 0; s < n_segments; ++s)
                CPPUNIT_ASSERT_DOUBLES_EQUAL(a.a[s], b.a[s], 1e-9);
        }
    }

    void amplitudes_are_normalized_over_a_cycle()
    {
        for (double h : { 0.7, 1.8 })
            for (double rv : { 0.2, 1.0, 2.9 })
                for (double heading : { 0.0, 1.0, M_PI / 2, 2.8 })
                    for (double elevation : { 0.0, -0.6 }) {
                        const walker_model w(params(h, rv * 0.53 * h, heading, 0.4, elevation));
                        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, mean_power(w), 1e-5);
                    }
    }

    void extremes_stay_finite_and_exact()
    {
        for (double h : { min_height_m, 1.0, 1.8, 2.5, max_height_m })
            for (double rv : { 0.0, 1e-9, 0.5, 3.0 })
                for (double phase : { -1e3, 0.0, 2.5, 1e6 })
                    for (double elevation : { -M_PI / 2, 0.0, M_PI / 2 }) {
                        const walker_model w(params(h, rv * 0.53 * h, 7.0, phase, elevation));
                        for (double t : { -1e6, 0.0, 0.3, 1e6 }) {
                            const auto s = at(w, t);
                            for (int k = 0; k < n_segments; ++k) {
                                CPPUNIT_ASSERT(std::isfinite(s.r[k]) && std::fabs(s.r[k]) < h);
                                CPPUNIT_ASSERT(std::isfinite(s.a[k]) && s.a[k] > 0.0);
                            }
                        }
                    }
        // t = 10⁶ s is as exact as t = 0: the same as a walker whose phase starts there.
        const walker_model w(params(1.8, 1.4));
        const double cycles = 1e6 / w.cycle_duration_s();
        const walker_model shifted(params(1.8, 1.4, 0.0, 2 * M_PI * (cycles - std::floor(cycles))));
        const auto late = at(w, 1e6), early = at(shifted, 0.0);
        for (int k = 0; k < n_segments; ++k)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(early.r[k], late.r[k], 1e-7);
    }

    // The frame-at-a-time evaluation (the channel models' path) gives each instant's
    // scatterers as the one-instant call does, across chunks (70 instants) and far times.
    void many_instants_equal_one_at_a_time()
    {
        const walker_model w(params(1.7, 1.9, 0.4, 1.1, 0.2));
        std::vector<double> t;
        for (int n = 0; n < 70; ++n)
            t.push_back(n < 35 ? 1e-3 * n : 1e6 + 0.0137 * n);
        std::vector<double> r(n_segments * t.size()), a(n_segments * t.size());
        w.scatterers(t.data(), static_cast<int>(t.size()), r.data(), a.data());
        for (size_t n = 0; n < t.size(); ++n) {
            const auto one = at(w, t[n]);
            for (int k = 0; k < n_segments; ++k) {
                CPPUNIT_ASSERT_DOUBLES_EQUAL(one.r[k], r[k * t.size() + n], 1e-12);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(one.a[k], a[k * t.size() + n], 1e-12 * one.a[k]);
            }
        }
        const double bad = std::numeric_limits<double>::infinity();
        assert_error([&] { w.scatterers(&bad, 1, r.data(), a.data()); }, "walker", "finite");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_walker_model);
