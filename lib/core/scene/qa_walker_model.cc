// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the walking human against the published Boulic–Thalmann model (cycle duration,
 * trajectory control points and formulas, the stance/swing kinematics they imply), the
 * ellipsoid RCS closed forms, the geometry conventions and bad input. */
#include <gnuradio/sems/core/scene/walker_model.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
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

} // namespace

class qa_walker_model : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_walker_model);
    CPPUNIT_TEST(proportions_add_up_to_the_height);
    CPPUNIT_TEST(cycle_duration_follows_boulic);
    CPPUNIT_TEST(trajectories_follow_the_published_curves);
    CPPUNIT_TEST(slow_gait_joins_the_normal_gait);
    CPPUNIT_TEST(pose_carries_the_joint_angles);
    CPPUNIT_TEST(torso_line_sits_at_the_bulk_velocity);
    CPPUNIT_TEST(feet_rest_in_stance_and_cover_the_stride_in_swing);
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

    void slow_gait_joins_the_normal_gait()
    {
        // The gaits meet at RV = 0.5 and 1.3: every trajectory is continuous there.
        for (double rv : { 0.5, 1.3 }) {
            const walker_model lo(params(1.8, (rv - 1e-9) * 0.954)), hi(params(1.8, (rv + 1e-9) * 0.954));
            for (int j = 0; j < 50; ++j) {
                const double u = j / 50.0;
                const auto a = lo.trajectories(u), b = hi.trajectories(u);
                const double da[] = { a.vertical_m, a.lateral_m, a.forward_m };
                const double db[] = { b.vertical_m, b.lateral_m, b.forward_m };
                for (int i = 0; i < 3; ++i)
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(da[i], db[i], 1e-6);
                const double aa[] = { a.pelvis_forward_deg, a.pelvis_list_deg, a.pelvis_torsion_deg,
                                      a.hip_deg, a.knee_deg, a.ankle_deg, a.thorax_deg,
                                      a.shoulder_deg, a.elbow_deg };
                const double ab[] = { b.pelvis_forward_deg, b.pelvis_list_deg, b.pelvis_torsion_deg,
                                      b.hip_deg, b.knee_deg, b.ankle_deg, b.thorax_deg,
                                      b.shoulder_deg, b.elbow_deg };
                for (int i = 0; i < 9; ++i)
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(aa[i], ab[i], 1e-4);
            }
        }
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
