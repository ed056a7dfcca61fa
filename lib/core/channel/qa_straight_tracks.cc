// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: tracks that move along a straight line in the ground plane ("motion": "straight"):
 * every frame's range, azimuth, elevation, radial velocity and heading against the body's
 * position computed in Cartesian coordinates, the end at the range and azimuth bounds, the
 * carrier phase against the range travelled, the radial default kept, and bad motions refused
 * by name. */
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {

using vec3 = std::array<double, 3>;

// The scene of these tests: the kinematic library, any heading, tracks of `frames` frames.
scene straight_scene(const std::string& random, const std::string& motion = R"(, "motion": "straight")",
                     const std::string& top = "")
{
    return scene::parse(R"({"format": "sems.scene", "version": 1, "classes": "kinematic", )" + top +
                        R"("random": {"heading": "any", )" + random + R"("tracks": {"frames": 64)" + motion + "}}}");
}

// A position from the radar at range R, azimuth φ (from x towards y) and elevation ε.
vec3 position(double range, double azimuth, double elevation)
{
    return { range * std::cos(elevation) * std::cos(azimuth), range * std::cos(elevation) * std::sin(azimuth),
             range * std::sin(elevation) };
}

double norm(const vec3& p) { return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]); }

// The body's state at frame f from its first frame, in Cartesian coordinates: it moves at speed s
// in the ground plane, heading θ_0 from the horizontal direction towards the radar, a positive θ
// turning from that direction clockwise seen from above (towards increasing azimuth).
struct expected {
    double range, azimuth, elevation, velocity, cos_heading, sin_heading;
};

expected at_frame(double r0, double az0, double el0, double speed, double heading0, double t_s)
{
    const vec3 p0 = position(r0, az0, el0);
    const double motion_angle = az0 + M_PI - heading0; // the direction of motion in the ground plane
    const vec3 u = { std::cos(motion_angle), std::sin(motion_angle), 0.0 };
    const vec3 p = { p0[0] + speed * t_s * u[0], p0[1] + speed * t_s * u[1], p0[2] };
    expected e;
    e.range = norm(p);
    e.azimuth = std::atan2(p[1], p[0]);
    e.elevation = std::asin(p[2] / e.range);
    // Approaching is positive: the speed's projection on the direction towards the radar.
    e.velocity = -speed * (p[0] * u[0] + p[1] * u[1]) / e.range;
    // The heading to the new horizontal line of sight, as the body's (cos, sin).
    const double towards = e.azimuth + M_PI;
    e.cos_heading = std::cos(towards - motion_angle);
    e.sin_heading = std::sin(towards - motion_angle);
    return e;
}

double angle_gap(double a, double b) { return std::fabs(std::remainder(a - b, 2.0 * M_PI)); }

// Track k's frames, drawn in order.
std::vector<frame_realization> track_frames(channel_model& cm, uint64_t k)
{
    std::vector<frame_realization> frames(size_t(cm.begin_track(k)));
    for (size_t f = 0; f < frames.size(); ++f)
        cm.draw(uint64_t(f), frames[f]);
    return frames;
}

} // namespace

class qa_straight_tracks : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_straight_tracks);
    CPPUNIT_TEST(frames_follow_the_line_in_cartesian_coordinates);
    CPPUNIT_TEST(tracks_end_at_their_range_and_azimuth_bounds);
    CPPUNIT_TEST(carrier_phase_follows_the_range_travelled);
    CPPUNIT_TEST(radial_is_the_default_and_approaching_lines_agree);
    CPPUNIT_TEST(round_trip_and_bad_motions);
    CPPUNIT_TEST_SUITE_END();

public:
    // Walkers below the array (elevation down to −0.4 rad) and every class on the ground, seen by
    // an 8-element ULA: every frame's truth and body against the Cartesian closed form.
    void frames_follow_the_line_in_cartesian_coordinates()
    {
        const frame_settings fs;
        const double frame_s = fs.n_symbols * fs.symbol_interval_s;
        const std::string array = R"("array": "ula8_3g", )";
        int checked = 0, crossing = 0;
        double worst_turn = 0.0;
        for (const std::string random :
             { std::string(R"("classes": ["adult", "child"], "azimuth_rad": [-1.2, 1.2], "elevation_rad": [-0.4, 0], )"),
               std::string(R"("azimuth_rad": [-1.2, 1.2], "paths_per_target": 2, )") }) {
            channel_model cm(fs, straight_scene(random, R"(, "motion": "straight")", array), 5);
            for (uint64_t k = 0; k < 40; ++k) {
                const auto frames = track_frames(cm, k);
                const auto& first = frames[0];
                CPPUNIT_ASSERT(first.truth_body >= 0);
                const auto& b0 = first.bodies[size_t(first.truth_body)];
                // The body's elevation is the radar's seen from it: the target's, negated.
                const double el0 = -b0.elevation_rad;
                CPPUNIT_ASSERT_DOUBLES_EQUAL(el0, first.truth.elevation_rad, 1e-15);
                for (size_t f = 1; f < frames.size(); ++f) {
                    const auto& r = frames[f];
                    const auto e = at_frame(first.truth.range_m, first.truth.azimuth_rad, el0, b0.speed_mps,
                                            b0.heading_rad, double(f) * frame_s);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(e.range, r.truth.range_m, 1e-9);
                    CPPUNIT_ASSERT(angle_gap(e.azimuth, r.truth.azimuth_rad) < 1e-11);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(e.elevation, r.truth.elevation_rad, 1e-11);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(e.velocity, r.truth.velocity_mps, 1e-9);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(fs.delay_from_range(e.range), r.paths[0].delay_s, 1e-17);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(fs.doppler_from_velocity(e.velocity), r.paths[0].doppler_hz, 1e-7);
                    const auto& b = r.bodies[size_t(r.truth_body)];
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(b0.speed_mps, b.speed_mps, 0.0);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(e.cos_heading, std::cos(b.heading_rad), 1e-11);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(e.sin_heading, std::sin(b.heading_rad), 1e-11);
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(-r.truth.elevation_rad, b.elevation_rad, 1e-15);
                    // every path of the target arrives from its direction
                    for (const auto& p : r.paths)
                        if (p.body == r.truth_body)
                            CPPUNIT_ASSERT_EQUAL(r.truth.azimuth_rad, p.azimuth_rad);
                    worst_turn = std::max(worst_turn, angle_gap(r.truth.azimuth_rad, first.truth.azimuth_rad));
                    ++checked;
                }
                crossing += std::fabs(std::sin(b0.heading_rad)) > 0.7;
            }
        }
        CPPUNIT_ASSERT(checked > 2000);
        CPPUNIT_ASSERT(crossing > 10);
        // Crossing bodies turn the line of sight visibly over a track (a car at 20 m/s, 1 s, 5 m).
        CPPUNIT_ASSERT_MESSAGE("largest turn " + std::to_string(worst_turn), worst_turn > 0.1);
    }

    // A track ends at its last frame inside its class's range interval and the scene's azimuth
    // interval: every frame lies inside, and a track cut short would leave one on its next frame.
    void tracks_end_at_their_range_and_azimuth_bounds()
    {
        const frame_settings fs;
        const double frame_s = fs.n_symbols * fs.symbol_interval_s;
        const auto lib = class_library::find("kinematic");
        // Cars and bicyclists within 0.3 rad of broadside: many leave the sector, some the range.
        channel_model cm(fs,
                         scene::parse(R"({"format": "sems.scene", "version": 1, "classes": "kinematic", "array": "ula8_3g",
            "random": {"classes": ["car", "bicyclist"], "heading": "any", "azimuth_rad": [-0.3, 0.3],
                       "tracks": {"frames": 4000, "motion": "straight"}}})"),
                         9);
        int by_azimuth = 0, by_range = 0;
        for (uint64_t k = 0; k < 60; ++k) {
            const auto frames = track_frames(cm, k);
            const auto& first = frames[0];
            const int len = int(frames.size());
            CPPUNIT_ASSERT(len < 4000); // a car or a bicyclist leaves within 128 s
            for (const auto& r : frames) {
                const auto& cs = lib->at(r.truth.class_id);
                CPPUNIT_ASSERT(r.truth.range_m >= cs.range_min_m && r.truth.range_m <= cs.range_max_m);
                CPPUNIT_ASSERT(r.truth.azimuth_rad >= -0.3 && r.truth.azimuth_rad <= 0.3);
            }
            const auto& b0 = first.bodies[size_t(first.truth_body)];
            const auto next = at_frame(first.truth.range_m, first.truth.azimuth_rad, 0.0, b0.speed_mps, b0.heading_rad,
                                       len * frame_s);
            const auto& cs = lib->at(first.truth.class_id);
            const bool out_of_range = next.range < cs.range_min_m || next.range > cs.range_max_m;
            const bool out_of_sector = next.azimuth < -0.3 || next.azimuth > 0.3;
            CPPUNIT_ASSERT_MESSAGE("track " + std::to_string(k) + " ended inside after " + std::to_string(len) + " frames",
                                   out_of_range || out_of_sector);
            by_range += out_of_range;
            by_azimuth += out_of_sector;
        }
        CPPUNIT_ASSERT(by_range > 3);
        CPPUNIT_ASSERT(by_azimuth > 3);
    }

    // Without fading, one point target's carrier phase at each frame's first symbol is the range
    // travelled since the track began, 4π(R_0 − R_f)/λ, though its Doppler changes frame to frame;
    // within the frame the phasor turns at the frame's Doppler.
    void carrier_phase_follows_the_range_travelled()
    {
        const frame_settings fs;
        const double lambda = fs.wavelength_m(), T = fs.symbol_interval_s;
        channel_model cm(fs,
                         straight_scene(R"("classes": ["car"], "micro_doppler": false, )", R"(, "motion": "straight")",
                                        R"("fading": "none", )"),
                         3);
        std::vector<gr_complex> h(static_cast<size_t>(fs.grid_size()));
        double worst = 0.0, doppler_change = 0.0;
        int checked = 0;
        for (uint64_t k = 0; k < 20; ++k) {
            const auto frames = track_frames(cm, k);
            const auto& first = frames[0];
            for (const auto& r : frames) {
                cm.factors(r, 0).fill(h.data()); // one antenna: the carrier phase alone
                const std::complex<double> want =
                    std::polar(1.0, 4.0 * M_PI * (first.truth.range_m - r.truth.range_m) / lambda);
                const std::complex<double> got = std::complex<double>(h[0]) / std::abs(r.paths[0].gain);
                worst = std::max(worst, std::abs(got - want));
                // the frame's last symbol turned at its Doppler from its first
                const std::complex<double> last(h[size_t((fs.n_symbols - 1) * fs.n_subcarriers)]);
                const auto step = std::polar(1.0, 2.0 * M_PI * r.paths[0].doppler_hz * T * (fs.n_symbols - 1));
                worst = std::max(worst, std::abs(last / std::abs(r.paths[0].gain) - got * step));
                doppler_change = std::max(doppler_change, std::fabs(r.paths[0].doppler_hz - first.paths[0].doppler_hz));
                ++checked;
            }
        }
        CPPUNIT_ASSERT(checked > 200);
        CPPUNIT_ASSERT_MESSAGE("worst phasor error " + std::to_string(worst), worst < 1e-5);
        CPPUNIT_ASSERT_MESSAGE("largest Doppler change " + std::to_string(doppler_change), doppler_change > 5.0);
    }

    // A scene without "motion" moves radially, bit for bit as "radial" says; a body that moves
    // straight towards or away from the radar on the ground keeps its direction and follows the
    // radial closed form.
    void radial_is_the_default_and_approaching_lines_agree()
    {
        const frame_settings fs;
        channel_model plain(fs, straight_scene("", ""), 21), radial(fs, straight_scene("", R"(, "motion": "radial")"), 21);
        std::vector<gr_complex> a(size_t(fs.grid_size())), b(a.size());
        for (uint64_t f = 0; f < 150; ++f) {
            const auto ra = plain.draw(f), rb = radial.draw(f);
            plain.factors(ra, 0).fill(a.data());
            radial.factors(rb, 0).fill(b.data());
            CPPUNIT_ASSERT(a == b);
        }
        const auto on_line = [&](const std::string& motion) {
            channel_model cm(fs,
                             scene::parse(R"({"format": "sems.scene", "version": 1, "classes": "kinematic",
                "random": {"heading": "approaching", "tracks": {"frames": 50)" + motion + "}}}"),
                             8);
            std::vector<double> values; // every frame's range and radial velocity
            for (uint64_t k = 0; k < 5; ++k) {
                const int len = cm.begin_track(k);
                for (int f = 0; f < len; ++f) {
                    const auto r = cm.draw(uint64_t(f));
                    values.push_back(r.truth.range_m);
                    values.push_back(r.truth.velocity_mps);
                }
            }
            return values;
        };
        const auto x = on_line(""), y = on_line(R"(, "motion": "straight")");
        CPPUNIT_ASSERT_EQUAL(x.size(), y.size());
        for (size_t i = 0; i < x.size(); ++i)
            CPPUNIT_ASSERT_DOUBLES_EQUAL(x[i], y[i], 1e-9);
    }

    void round_trip_and_bad_motions()
    {
        const auto s = straight_scene("");
        CPPUNIT_ASSERT(s.random_settings()->tracks->motion == track_motion::straight);
        const auto back = scene::parse(s.to_json_string());
        CPPUNIT_ASSERT_EQUAL(s.to_json().dump(), back.to_json().dump());
        CPPUNIT_ASSERT_EQUAL(std::string("straight"), back.to_json()["random"]["tracks"]["motion"].get<std::string>());
        // radial is written only when named by a file that is not read back as it was: never
        CPPUNIT_ASSERT(!straight_scene("", R"(, "motion": "radial")").to_json()["random"]["tracks"].contains("motion"));
        CPPUNIT_ASSERT_EQUAL(std::string("radial"), track_motion_name(track_motion::radial));
        CPPUNIT_ASSERT(track_motion_from_name("straight") == track_motion::straight);
        assert_error([] { straight_scene("", R"(, "motion": "curved")"); }, "random.tracks.motion",
                     "unknown track motion \"curved\" (known: radial, straight)");
        assert_error([] { straight_scene("", R"(, "motion": 1)"); }, "random.tracks.motion");
        assert_error([] { track_motion_from_name("Straight"); }, "Straight", "radial, straight");
        random_spec r;
        r.tracks = track_draw_spec{};
        r.tracks->motion = static_cast<track_motion>(7);
        assert_error([&] { scene::random(r); }, "random.tracks.motion", "7");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_straight_tracks);
