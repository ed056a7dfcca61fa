// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a scatterer body seen by an array — every scatterer from its own direction. Each
 * element's channel of a walker against a sum over its segments written out here from the
 * walker's pose (body frame turned into the array's, each segment's exact direction); the
 * angular spread of a walker broadside and head-on against the closed form of its segments'
 * offsets, and of a swinging pole against its array factor (spread broadside, none head-on). */
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/walker_model.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <cstdio>
#include <complex>
#include <cstring>
#include <string>
#include <vector>

using namespace gr::sems;

namespace {

using cd = std::complex<double>;

// A fixed, unfaded walker at (range, azimuth, elevation) walking at `speed` with `heading`
// (0: towards the array; π/2: across the line of sight), seen by array a.
scene walker_scene(double range_m, double az, double el, double speed, double heading, const array_geometry& a)
{
    target_spec t;
    t.cls = target_class::pedestrian;
    t.range_m = range_m;
    t.speed_mps = speed;
    t.heading_rad = heading;
    t.velocity_mps = speed * std::cos(heading) * std::cos(el);
    t.azimuth_rad = az;
    t.elevation_rad = el;
    walker_motion w;
    w.height_m = 1.8;
    t.motion = w;
    return scene::fixed({ t }, std::nullopt, 0, fading_kind::none).with_array(a);
}

// The walker's channel at offset o, up to one complex constant (the path's gain and the body's
// power normalisation), from its pose: segment s at body-frame p_s sits at
// P_s = R·u + D·p_s in the array's frame, D the turn about z that takes the body's line of sight
// towards the radar, (cos ε cos θ, cos ε sin θ, sin ε) with ε = −elevation, onto −u. It returns
// a_s·exp(−jκ_m r_s) (the walker model's radial displacement and amplitude) on the body's delay
// τ and Doppler, arriving as a plane wave from its own direction u_s = P_s/|P_s|:
// exp(j2π (f_c + mΔf) u_s·o / c).
std::vector<cd> segment_sum(const frame_settings& fs, const channel_path& path, const scatterer_body& b, const position3& o)
{
    const double az = path.azimuth_rad, el = path.elevation_rad, range = 0.5 * speed_of_light_mps * path.delay_s;
    walker::walker_params p;
    p.height_m = std::get<walker_motion>(b.motion).height_m;
    p.phase_rad = std::get<walker_motion>(b.motion).phase_rad;
    p.speed_mps = b.speed_mps;
    p.heading_rad = b.heading_rad;
    p.elevation_rad = -el; // the radar seen from the pelvis: below it when the walker is above the array
    const walker::walker_model w(p);
    const double u[3] = { std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el) };
    const double psi = az + M_PI - b.heading_rad; // the body's x axis, turned onto the array's frame
    std::vector<cd> h(size_t(fs.grid_size()));
    walker::body_pose pose;
    double r[walker::n_segments], a[walker::n_segments];
    for (int n = 0; n < fs.n_symbols; ++n) {
        const double t = n * fs.symbol_interval_s;
        w.pose(t, pose);
        w.scatterers(t, r, a);
        for (int m = 0; m < fs.n_subcarriers; ++m) {
            const double f = fs.carrier_hz + m * fs.subcarrier_spacing_hz();
            cd sum = 0.0;
            for (int s = 0; s < walker::n_segments; ++s) {
                const auto& q = pose.centre[size_t(s)];
                const double d[3] = { std::cos(psi) * q[0] - std::sin(psi) * q[1],
                                      std::sin(psi) * q[0] + std::cos(psi) * q[1], q[2] };
                const double P[3] = { range * u[0] + d[0], range * u[1] + d[1], range * u[2] + d[2] };
                const double norm = std::sqrt(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]);
                const double us_o = (P[0] * o[0] + P[1] * o[1] + P[2] * o[2]) / norm;
                sum += a[s] * std::polar(1.0, -4.0 * M_PI * f / speed_of_light_mps * r[s] + 2.0 * M_PI * f * us_o / speed_of_light_mps);
            }
            const double bulk = -2.0 * M_PI * m * fs.subcarrier_spacing_hz() * path.delay_s +
                                2.0 * M_PI * path.doppler_hz * n * fs.symbol_interval_s;
            h[size_t(n) * fs.n_subcarriers + m] = sum * std::polar(1.0, bulk);
        }
    }
    return h;
}

// The least-squares constant c of h ≈ c·ref.
cd complex_gain_fit(const std::vector<gr_complex>& h, const std::vector<cd>& ref)
{
    cd num = 0.0;
    double den = 0.0;
    for (size_t i = 0; i < h.size(); ++i) {
        num += std::conj(ref[i]) * cd(h[i]);
        den += std::norm(ref[i]);
    }
    return num / den;
}

// ‖h − c·ref‖ / ‖h‖.
double misfit(const std::vector<gr_complex>& h, const std::vector<cd>& ref, cd c)
{
    double e = 0.0, p = 0.0;
    for (size_t i = 0; i < h.size(); ++i) {
        e += std::norm(cd(h[i]) - c * ref[i]);
        p += std::norm(cd(h[i]));
    }
    return std::sqrt(e / p);
}

// The fraction of the array's power outside the plane wave from the body's direction over
// `frames` frames: 1 − Σ |s^H h[:,n,m]|² / (K Σ ‖h[:,n,m]‖²), s the steering vector.
double off_beam_fraction(const frame_settings& fs, channel_model& cm, double az, int frames)
{
    const int k_count = cm.n_elements();
    const auto s = steering_vector(*cm.scene_spec().array(), az, 0.0, fs.wavelength_m());
    std::vector<std::vector<gr_complex>> h(size_t(k_count), std::vector<gr_complex>(size_t(fs.grid_size())));
    double on = 0.0, all = 0.0;
    for (int f = 0; f < frames; ++f) {
        const auto r = cm.draw(uint64_t(f));
        for (int k = 0; k < k_count; ++k)
            cm.factors(r, uint64_t(f) * fs.n_symbols, k).fill(h[size_t(k)].data());
        for (size_t i = 0; i < size_t(fs.grid_size()); ++i) {
            cd beam = 0.0;
            for (int k = 0; k < k_count; ++k) {
                beam += std::conj(s[size_t(k)]) * cd(h[size_t(k)][i]);
                all += std::norm(cd(h[size_t(k)][i]));
            }
            on += std::norm(beam) / k_count;
        }
    }
    return 1.0 - on / all;
}

} // namespace

class qa_body_angles : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_body_angles);
    CPPUNIT_TEST(each_walker_segment_arrives_from_its_own_direction);
    CPPUNIT_TEST(a_body_spreads_over_angle_as_its_geometry_says);
    CPPUNIT_TEST(shared_bodies_give_each_elements_own_factors);
    CPPUNIT_TEST_SUITE_END();

public:
    void each_walker_segment_arrives_from_its_own_direction()
    {
        // Close (5 m) and broadside, where the segments spread over ±6°, on ULA and URA elements
        // and at an elevation (the walker then seen from above): each element's channel equals
        // the segment sum to float precision, while the body's direction alone misses it.
        const frame_settings fs;
        const auto ula = array_geometry::ula(8, 0.05);
        const auto ura = array_geometry::ura(4, 3, 0.05, 0.05);
        struct pose_case {
            const array_geometry* a;
            double az, el, heading;
        };
        for (const auto& pc : { pose_case{ &ula, 0.3, 0.0, M_PI / 2 }, pose_case{ &ula, -0.9, 0.0, 2.0 },
                                pose_case{ &ura, 0.2, -0.25, 1.2 } }) {
            channel_model cm(fs, walker_scene(5.0, pc.az, pc.el, 1.4, pc.heading, *pc.a), 3);
            const auto r = cm.draw(0);
            CPPUNIT_ASSERT_EQUAL(size_t(1), r.bodies.size());
            std::vector<gr_complex> h0(size_t(fs.grid_size())), hk(h0.size());
            frame_channel(fs, r, 0).fill(h0.data()); // the single antenna: the constant
            const cd c = complex_gain_fit(h0, segment_sum(fs, r.paths[0], r.bodies[0], { 0.0, 0.0, 0.0 }));
            CPPUNIT_ASSERT_LESS(2e-6, misfit(h0, segment_sum(fs, r.paths[0], r.bodies[0], { 0.0, 0.0, 0.0 }), c));
            double body_direction_misfit = 0.0;
            for (int k = 0; k < cm.n_elements(); ++k) {
                const position3 o = cm.elements()[size_t(k)].offset;
                cm.factors(r, 0, k).fill(hk.data());
                const auto expected = segment_sum(fs, r.paths[0], r.bodies[0], o);
                CPPUNIT_ASSERT_LESS(2e-6, misfit(hk, expected, c));
                // The body's direction for every segment: the origin's channel turned by the
                // element's plane wave.
                const auto u = direction_vector(pc.az, pc.el);
                std::vector<cd> narrow(h0.size());
                for (int n = 0; n < fs.n_symbols; ++n)
                    for (int m = 0; m < fs.n_subcarriers; ++m) {
                        const size_t i = size_t(n) * fs.n_subcarriers + m;
                        const double f = fs.carrier_hz + m * fs.subcarrier_spacing_hz();
                        narrow[i] = cd(h0[i]) * std::polar(1.0, 2.0 * M_PI * f * projection_m(u, o) / speed_of_light_mps);
                    }
                body_direction_misfit = std::max(body_direction_misfit, misfit(hk, narrow, 1.0));
            }
            CPPUNIT_ASSERT_GREATER(0.05, body_direction_misfit);
        }
    }

    void a_body_spreads_over_angle_as_its_geometry_says()
    {
        // A 16-element λ/2 ULA sees a walker at 10 m on boresight, over a gait cycle. Its power off the body's
        // plane wave is, for small offsets δφ_s = h_s/R of the segments (h_s across the line of
        // sight) and segments whose phases decorrelate over the frame, κ²·var(y)·E[δφ²] with
        // κ = 2π/λ and var(y) the elements' spread along y (E weighted by each segment's power
        // a_s², over the frames). Broadside the limbs swing across the line of sight; head-on
        // they swing along it and the body's width is what spreads.
        const frame_settings fs;
        const double lambda = fs.wavelength_m(), range = 10.0;
        const auto a = array_geometry::ula(16, 0.5 * lambda);
        double var_y = 0.0;
        for (int k = 0; k < 16; ++k)
            var_y += std::pow((k - 7.5) * 0.5 * lambda, 2) / 16.0;
        double fraction[2], predicted[2];
        const int frames = 36; // 1.15 s: about one gait cycle at 1.4 m/s
        const double headings[2] = { M_PI / 2, 0.0 };
        for (int i = 0; i < 2; ++i) {
            channel_model cm(fs, walker_scene(range, 0.0, 0.0, 1.4, headings[i], a), 3);
            fraction[i] = off_beam_fraction(fs, cm, 0.0, frames);
            walker::walker_params p;
            p.height_m = 1.8;
            p.speed_mps = 1.4;
            p.heading_rad = headings[i];
            const walker::walker_model w(p);
            walker::body_pose pose;
            double rr[walker::n_segments], amp[walker::n_segments], num = 0.0, den = 0.0;
            for (int n = 0; n < frames * fs.n_symbols; ++n) {
                w.pose(n * fs.symbol_interval_s, pose);
                w.scatterers(n * fs.symbol_interval_s, rr, amp);
                for (int s = 0; s < walker::n_segments; ++s) {
                    // across the line of sight at heading θ: h = x sin θ − y cos θ
                    const double h = pose.centre[size_t(s)][0] * std::sin(headings[i]) -
                                     pose.centre[size_t(s)][1] * std::cos(headings[i]);
                    num += amp[s] * amp[s] * std::pow(h / range, 2);
                    den += amp[s] * amp[s];
                }
            }
            predicted[i] = std::pow(2.0 * M_PI / lambda, 2) * var_y * num / den;
        }
        std::printf("off-beam fraction: broadside %.4g (closed form %.4g), head-on %.4g (closed form %.4g)\n",
                    fraction[0], predicted[0], fraction[1], predicted[1]);
        // Both within a factor of two of their closed forms: the segments share one range cell
        // on this frame, so their cross terms average out only partly over a gait cycle.
        for (int i = 0; i < 2; ++i) {
            CPPUNIT_ASSERT_GREATER(0.5 * predicted[i], fraction[i]);
            CPPUNIT_ASSERT_LESS(2.0 * predicted[i], fraction[i]);
        }
        // Where the spread comes from: broadside the forward offsets (the limbs' swing, which
        // moves with the gait), head-on the sideways ones (the body's width: shoulders, hips),
        // which the swing leaves where they are. A body without width (a pole swinging in the
        // walking direction: one harmonic scatterer) shows it plainly: spread broadside, none
        // head-on.
        double pole_fraction[2];
        for (int i = 0; i < 2; ++i) {
            const std::string text = R"({"format": "sems.scene", "version": 1, "fading": "none", "targets": [
                {"class": "pedestrian", "range_m": 10, "speed_mps": 1.4, "heading_rad": )" +
                                     std::to_string(headings[i]) + R"(, "micro_motion": {"model": "scatterers",
                 "scatterers": [{"power": 1, "harmonics": [{"amplitude_m": 0.5, "rate_hz": 1.0}]}]}}]})";
            channel_model cm(fs, scene::parse(text).with_array(a), 3);
            pole_fraction[i] = off_beam_fraction(fs, cm, 0.0, frames);
        }
        // The pole's exact closed form broadside: one scatterer at x(t) = 0.5 sin(2π t) m across
        // the line of sight, direction u_y = x/sqrt(R² + x²); off the beam 1 − |AF|²/K², AF the
        // array factor Σ_k exp(j2π y_k u_y/λ), averaged over the frames' symbols (at the
        // carrier: the band's 1 % spread of wavelengths is the tolerance).
        double pole_predicted = 0.0;
        for (int n = 0; n < frames * fs.n_symbols; ++n) {
            const double x = 0.5 * std::sin(2.0 * M_PI * n * fs.symbol_interval_s);
            const double uy = x / std::sqrt(range * range + x * x);
            cd af = 0.0;
            for (int k = 0; k < 16; ++k)
                af += std::polar(1.0, 2.0 * M_PI / lambda * (k - 7.5) * 0.5 * lambda * uy);
            pole_predicted += (1.0 - std::norm(af) / 256.0) / (frames * fs.n_symbols);
        }
        std::printf("a swinging pole: broadside %.4g (closed form %.4g), head-on %.4g\n", pole_fraction[0],
                    pole_predicted, pole_fraction[1]);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(pole_predicted, pole_fraction[0], 0.03 * pole_predicted);
        CPPUNIT_ASSERT_LESS(1e-9, pole_fraction[1]);
    }

    void shared_bodies_give_each_elements_own_factors()
    {
        // array_channel takes the bodies once per frame for all elements: every element's
        // factors are frame_channel's for that element, bit for bit, frame after frame (a
        // walker, a rotor, wheels and user scatterers, on a URA with a cosine pattern).
        const auto sc = scene::parse(R"({"format": "sems.scene", "version": 1,
            "array": {
                      "receive": {"ura": {"columns": 3, "rows": 2, "spacing_m": 0.05}}, "pattern": "cosine"},
            "targets": [
            {"class": "pedestrian", "range_m": 12, "speed_mps": 1.4, "heading_rad": 1.1, "azimuth_rad": 0.3,
             "elevation_rad": -0.1, "micro_motion": {"model": "walker", "height_m": 1.7}},
            {"class": "drone", "range_m": 30, "velocity_mps": 2, "azimuth_rad": -0.5,
             "micro_motion": {"model": "rotor", "blade_length_m": 0.15, "rotation_hz": 60, "elevation_rad": 0.3}},
            {"class": "car", "range_m": 40, "speed_mps": 8, "heading_rad": 0.6, "azimuth_rad": 1.0,
             "micro_motion": {"model": "wheels", "wheel_radius_m": 0.3}}]})");
        const frame_settings fs;
        channel_model cm(fs, sc, 4);
        array_channel all(fs, cm.elements());
        std::vector<gr_complex> h1(size_t(fs.grid_size())), h2(h1.size());
        for (uint64_t f = 0; f < 3; ++f) {
            const auto r = cm.draw(f);
            all.update(r, f * fs.n_symbols);
            CPPUNIT_ASSERT_EQUAL(cm.n_elements(), all.n_elements());
            for (int k = 0; k < cm.n_elements(); ++k) {
                all.element(k).fill(h1.data());
                cm.factors(r, f * fs.n_symbols, k).fill(h2.data());
                CPPUNIT_ASSERT(std::memcmp(h1.data(), h2.data(), h1.size() * sizeof(gr_complex)) == 0);
            }
        }
        gr::sems::qa::assert_error([&] { all.element(6); }, "stream 6", "6");
        gr::sems::qa::assert_error([&] { array_channel(fs, {}); }, "at least one stream", "none");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_body_angles);
