// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: prints the walker model's scatterers and kinematics as CSV for
 * docs/reference/walker_signature.py (built by hand, by no build target; walker.md gives the
 * g++ command).
 *
 *   walker_signature signature   t, then r_s and a_s of the 16 segments: 1.8 m, 1.4 m/s,
 *                                heading 0, 2 s at 4 kHz
 *   walker_signature kinematics  per speed: RV, cycle, support, the right foot's mean radial
 *                                velocity in stance and swing, its peak, the lower leg's range
 *   walker_signature bench       CPU ns per scatterers() call and per walker_model set-up
 */
#include <gnuradio/sems/core/scene/walker_model.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>

using namespace gr::sems::walker;

namespace {

double cpu_s()
{
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

double displacement(const walker_model& w, int s, double t)
{
    double r[n_segments], a[n_segments];
    w.scatterers(t, r, a);
    return r[s];
}

// Radial velocity towards the radar (heading 0: bulk v), central difference.
double towards(const walker_model& w, int s, double t)
{
    const double dt = 1e-5;
    return w.params().speed_mps - (displacement(w, s, t + dt) - displacement(w, s, t - dt)) / (2 * dt);
}

void signature()
{
    walker_params p;
    p.height_m = 1.8;
    p.speed_mps = 1.4;
    const walker_model w(p);
    std::printf("t_s");
    for (const auto& s : segment_shapes())
        std::printf(",r %s", s.name);
    for (const auto& s : segment_shapes())
        std::printf(",a %s", s.name);
    std::printf("\n");
    const double fs = 4000.0;
    for (int n = 0; n < int(2.0 * fs); ++n) {
        const double t = n / fs;
        double r[n_segments], a[n_segments];
        w.scatterers(t, r, a);
        std::printf("%.6f", t);
        for (double x : r)
            std::printf(",%.9f", x);
        for (double x : a)
            std::printf(",%.9f", x);
        std::printf("\n");
    }
}

void kinematics()
{
    std::printf("height_m,speed_mps,rv,cycle_s,support,stance_foot_mps,swing_foot_mps,"
                "stride_in_swing_mps,foot_peak_mps,lower_leg_min_mps,lower_leg_max_mps,"
                "torso_min_mps,torso_max_mps,hand_min_mps,hand_max_mps\n");
    for (double v : { 0.3, 0.5, 0.8, 1.1, 1.4, 2.0, 2.6 }) {
        walker_params p;
        p.height_m = 1.8;
        p.speed_mps = v;
        const walker_model w(p);
        const double dc = w.cycle_duration_s(), ds = w.support_fraction();
        const int n = 2000;
        double stance = 0, swing = 0, foot_peak = -1e9;
        double leg[2] = { 1e9, -1e9 }, tor[2] = { 1e9, -1e9 }, hand[2] = { 1e9, -1e9 };
        int ns = 0, nw = 0;
        for (int j = 0; j < n; ++j) {
            const double u = (j + 0.5) / n, t = u * dc;
            const double vf = towards(w, right_foot, t);
            (u < ds ? stance : swing) += vf;
            ++(u < ds ? ns : nw);
            foot_peak = std::max(foot_peak, vf);
            auto span = [&](double* m, int s) {
                const double x = towards(w, s, t);
                m[0] = std::min(m[0], x);
                m[1] = std::max(m[1], x);
            };
            span(leg, right_lower_leg);
            span(tor, torso);
            span(hand, right_lower_arm);
        }
        std::printf("%.2f,%.2f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n",
                    p.height_m, v, w.relative_velocity(), dc, ds, stance / ns, swing / nw,
                    v / (1 - ds), foot_peak, leg[0], leg[1], tor[0], tor[1], hand[0], hand[1]);
    }
}

void bench()
{
    walker_params p;
    const walker_model w(p);
    double r[n_segments], a[n_segments], sink = 0.0, best = 1e9;
    for (int rep = 0; rep < 5; ++rep) {
        const int m = 200000;
        const double t0 = cpu_s();
        for (int j = 0; j < m; ++j) {
            w.scatterers(j * 1e-3, r, a);
            sink += r[3] + a[5];
        }
        best = std::min(best, (cpu_s() - t0) / m * 1e9);
    }
    double best_setup = 1e9;
    for (int rep = 0; rep < 5; ++rep) {
        const int m = 50;
        const double t0 = cpu_s();
        for (int j = 0; j < m; ++j) {
            p.phase_rad = j;
            sink += walker_model(p).amplitude_scale();
        }
        best_setup = std::min(best_setup, (cpu_s() - t0) / m * 1e9);
    }
    std::printf("scatterers_ns,setup_ns,checksum\n%.1f,%.0f,%.6g\n", best, best_setup, sink);
}

} // namespace

int main(int argc, char** argv)
{
    const char* mode = argc > 1 ? argv[1] : "";
    if (!std::strcmp(mode, "signature"))
        signature();
    else if (!std::strcmp(mode, "kinematics"))
        kinematics();
    else if (!std::strcmp(mode, "bench"))
        bench();
    else {
        std::fprintf(stderr, "usage: walker_signature signature|kinematics|bench\n");
        return 2;
    }
    return 0;
}
