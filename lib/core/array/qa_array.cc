// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: arrays — their files, the steering vector and each element's channel against
 * closed forms written out here from the geometry (not from steering.h), and bad input. */
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include "qa/qa_assert.h"
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;

namespace {

using cd = std::complex<double>;
const double lambda = 0.1;                           // the default frame's λ at 3 GHz

// A fixed point target of known gain (no fading), with an optional array.
scene point_target(double range_m, double velocity_mps, double az, double el)
{
    target_spec t;
    t.cls = target_class::car;
    t.range_m = range_m;
    t.velocity_mps = velocity_mps;
    t.azimuth_rad = az;
    t.elevation_rad = el;
    return scene::fixed({ t }, std::nullopt, 0, fading_kind::none);
}

// H_k[n,m] of a unit point target at (R, v, φ, θ) on element o, from the geometry: the plane
// wave's delay at the element is τ − (u·o)/c; the carrier adds 2π f_c of it, subcarrier m
// 2π m Δf of it; Doppler 2v/λ over slow time.
cd closed_form(const frame_settings& fs, double range_m, double v, double az, double el, const position3& o, int n, int m)
{
    const double ux = std::cos(el) * std::cos(az), uy = std::cos(el) * std::sin(az), uz = std::sin(el);
    const double along = ux * o[0] + uy * o[1] + uz * o[2];
    const double tau = 2.0 * range_m / speed_of_light_mps, tau_k = tau - along / speed_of_light_mps;
    const double carrier = 2.0 * M_PI * fs.carrier_hz * (tau - tau_k); // the element's advance over the origin
    const double sub = -2.0 * M_PI * m * fs.subcarrier_spacing_hz() * tau_k;
    const double dop = 2.0 * M_PI * (2.0 * v / (speed_of_light_mps / fs.carrier_hz)) * n * fs.symbol_interval_s;
    return std::polar(1.0, carrier + sub + dop);
}

void check_element_channels(const frame_settings& fs, const array_geometry& a, double az, double el)
{
    const double range = 73.4, v = 6.3;
    channel_model cm(fs, point_target(range, v, az, el).with_array(a), 5);
    const auto r = cm.draw(0);
    CPPUNIT_ASSERT_EQUAL(a.n_receive() * a.n_transmit(), cm.n_elements());
    const auto elements = virtual_elements(a);
    std::vector<gr_complex> h(size_t(fs.grid_size()));
    double worst = 0.0;
    for (int k = 0; k < cm.n_elements(); ++k) {
        cm.factors(r, 0, k).fill(h.data());
        for (int n = 0; n < fs.n_symbols; ++n)
            for (int m = 0; m < fs.n_subcarriers; ++m) {
                const cd want = closed_form(fs, range, v, az, el, elements[size_t(k)].offset, n, m);
                worst = std::max(worst, std::abs(cd(h[size_t(n) * fs.n_subcarriers + m]) - want));
            }
    }
    CPPUNIT_ASSERT_MESSAGE("worst |H_k - closed form| = " + std::to_string(worst) + " at az " + std::to_string(az) +
                               " el " + std::to_string(el),
                           worst < 1e-6);
}

} // namespace

class qa_array : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_array);
    CPPUNIT_TEST(ula_and_ura_are_centred_on_the_origin);
    CPPUNIT_TEST(steering_vector_is_the_plane_wave);
    CPPUNIT_TEST(each_element_channel_equals_the_closed_form);
    CPPUNIT_TEST(mimo_virtual_elements_add_transmit_and_receive_positions);
    CPPUNIT_TEST(the_origin_element_gives_the_single_antenna_bits);
    CPPUNIT_TEST(narrowband_phase_error_reaches_its_bound_and_no_more);
    CPPUNIT_TEST(cosine_elements_see_nothing_behind);
    CPPUNIT_TEST(clutter_scatterers_come_from_their_own_azimuths);
    CPPUNIT_TEST(random_targets_draw_their_azimuths_and_tracks_keep_them);
    CPPUNIT_TEST(random_targets_draw_their_elevations);
    CPPUNIT_TEST(class_libraries_give_their_own_angles);
    CPPUNIT_TEST(array_files_round_trip);
    CPPUNIT_TEST(bad_arrays_are_refused_by_name);
    CPPUNIT_TEST(bad_angles_are_refused_by_name);
    CPPUNIT_TEST_SUITE_END();

public:
    void ula_and_ura_are_centred_on_the_origin()
    {
        const auto a = array_geometry::ula(4, 0.05);
        CPPUNIT_ASSERT_EQUAL(4, a.n_receive());
        CPPUNIT_ASSERT_EQUAL(1, a.n_transmit());
        const double want[] = { -0.075, -0.025, 0.025, 0.075 };
        for (int k = 0; k < 4; ++k) {
            CPPUNIT_ASSERT_EQUAL(0.0, a.receive()[k][0]);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(want[k], a.receive()[k][1], 1e-15);
            CPPUNIT_ASSERT_EQUAL(0.0, a.receive()[k][2]);
        }
        const auto g = array_geometry::ura(3, 2, 0.05, 0.04);
        CPPUNIT_ASSERT_EQUAL(6, g.n_receive());
        // element row·columns + column: column along y, row along z
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.05, g.receive()[5][1], 1e-15);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.02, g.receive()[5][2], 1e-15);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-0.05, g.receive()[0][1], 1e-15);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-0.02, g.receive()[0][2], 1e-15);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::hypot(0.05, 0.02), g.reach_m(), 1e-15);
        CPPUNIT_ASSERT(array_geometry().is_single_antenna());
        CPPUNIT_ASSERT(array_geometry::ula(1, 0.05).is_single_antenna());
        CPPUNIT_ASSERT(!a.is_single_antenna());
    }

    void steering_vector_is_the_plane_wave()
    {
        // ULA along y, spacing d: a_k = exp(j 2π/λ · y_k · sin φ cos θ) (the textbook ULA phase).
        const double d = 0.05;
        const auto a = array_geometry::ula(8, d);
        for (double az : { 0.0, 0.3, -1.2, M_PI / 2 })
            for (double el : { 0.0, 0.4 }) {
                const auto s = steering_vector(a, az, el, lambda);
                CPPUNIT_ASSERT_EQUAL(size_t(8), s.size());
                for (int k = 0; k < 8; ++k) {
                    const double y = (k - 3.5) * d;
                    const cd want = std::polar(1.0, 2.0 * M_PI / lambda * y * std::sin(az) * std::cos(el));
                    CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(s[size_t(k)] - want), 1e-12);
                }
            }
        // Broadside: every element in phase. Endfire at λ/2: neighbours π apart.
        for (const auto& x : steering_vector(a, 0.0, 0.0, lambda))
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(x - 1.0), 1e-15);
        const auto e = steering_vector(a, M_PI / 2, 0.0, lambda);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(e[1] / e[0] + 1.0), 1e-12);
        // URA: z-spacing phases follow sin θ.
        const auto g = array_geometry::ura(2, 2, 0.05, 0.05);
        const auto s = steering_vector(g, 0.0, 0.5, lambda);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(s[2] / s[0] - std::polar(1.0, 2.0 * M_PI / lambda * 0.05 * std::sin(0.5))),
                                     1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(s[1] / s[0] - 1.0), 1e-12); // az 0: no y phase
    }

    void each_element_channel_equals_the_closed_form()
    {
        const frame_settings fs;
        const auto ula = array_geometry::ula(8, lambda / 2);
        for (double az : { 0.0, 0.35, -0.9, 1.4 })
            check_element_channels(fs, ula, az, 0.0);
        const auto ura = array_geometry::ura(4, 4, lambda / 2, lambda / 2);
        for (double az : { 0.0, 0.6, -0.25 })
            for (double el : { 0.0, 0.3, -0.7 })
                check_element_channels(fs, ura, az, el);
        // A wide aperture on a wide band, where the per-element delay matters (see the bound).
        frame_settings wide;
        wide.bandwidth_hz = 400e6;
        wide.n_subcarriers = 1024; // Δf 390.625 kHz: 384 m unambiguous
        check_element_channels(wide, array_geometry::ula(32, 0.2), 1.1, 0.0);
        // Any positions: a 3-D cloud with elements in front of and behind the origin.
        const auto cloud = array_geometry::from_positions({ { 0.1, 0.0, 0.0 }, { -0.2, 0.3, 0.1 }, { 0.0, -0.4, 0.25 } });
        check_element_channels(fs, cloud, 0.5, 0.2);
    }

    void mimo_virtual_elements_add_transmit_and_receive_positions()
    {
        const auto a = array_geometry::from_positions({ { 0, 0, 0 }, { 0, 0.05, 0 } }, { { 0, 0, 0 }, { 0, 0.1, 0 } });
        const auto v = virtual_elements(a);
        CPPUNIT_ASSERT_EQUAL(size_t(4), v.size()); // receive-major: (0,0) (0,1) (1,0) (1,1)
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, v[0].offset[1], 0.0);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.1, v[1].offset[1], 1e-15);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.05, v[2].offset[1], 1e-15);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.15, v[3].offset[1], 1e-15);
        check_element_channels(frame_settings{}, a, 0.4, 0.1);
        const auto s = steering_vector(a, 0.4, 0.1, lambda);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(0.0, std::abs(s[3] - std::polar(1.0, 2 * M_PI / lambda * 0.15 * std::sin(0.4) * std::cos(0.1))),
                                     1e-12);
    }

    void the_origin_element_gives_the_single_antenna_bits()
    {
        // A scene with a walker, a multipath car and moving targets off boresight: the origin
        // element's factors are the same bits as the single-antenna factors, and a
        // single-antenna array in the scene (no clutter to draw azimuths for) draws the same
        // frames, whatever the targets' directions.
        const auto sc = scene::parse(R"({"format": "sems.scene", "version": 1, "targets": [
            {"class": "pedestrian", "range_m": 40, "speed_mps": 1.4, "heading_rad": 0.7,
             "azimuth_rad": 0.6, "elevation_rad": 0.2, "micro_motion": {"model": "walker", "height_m": 1.7}},
            {"class": "car", "range_m": 90, "velocity_mps": 12, "azimuth_rad": -1.1,
             "paths": [{}, {"excess_range_m": 9, "power": 0.3}]}]})");
        const frame_settings fs;
        channel_model plain(fs, sc, 11), with(fs, sc.with_array(array_geometry()), 11);
        for (uint64_t f = 0; f < 3; ++f) {
            const auto a = plain.draw(f), b = with.draw(f);
            std::vector<gr_complex> h0(size_t(fs.grid_size())), h1(h0.size()), h2(h0.size());
            plain.factors(a, f * fs.n_symbols).fill(h0.data());
            frame_channel(fs, a, f * fs.n_symbols, array_element{}).fill(h1.data());
            with.factors(b, f * fs.n_symbols, 0).fill(h2.data());
            CPPUNIT_ASSERT(std::memcmp(h0.data(), h1.data(), h0.size() * sizeof(gr_complex)) == 0);
            CPPUNIT_ASSERT(std::memcmp(h0.data(), h2.data(), h0.size() * sizeof(gr_complex)) == 0);
        }
    }

    void narrowband_phase_error_reaches_its_bound_and_no_more()
    {
        // The narrowband model (the origin's channel turned by the steering phasor) against the
        // emulator's exact plane-wave delay: its phase error is at most the stated bound, and
        // the outermost element at endfire reaches it on the last subcarrier.
        // 100 MHz over 256 subcarriers and a 1.5 m ULA: the bound, 1.57 rad, stays below π, so
        // the measured phase does not wrap.
        frame_settings fs;
        fs.bandwidth_hz = 100e6;
        fs.n_subcarriers = 256;
        const auto a = array_geometry::ula(16, 0.1);
        const double bound = narrowband_phase_error_rad(a, fs);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(2 * M_PI * 255 * (100e6 / 256) * 0.75 / 3e8, bound, 1e-12);
        double worst = 0.0;
        for (double az : { 0.0, 0.7, M_PI / 2 }) {
            channel_model cm(fs, point_target(50.0, 0.0, az, 0.0).with_array(a), 1);
            const auto r = cm.draw(0);
            const auto s = steering_vector(a, az, 0.0, fs.wavelength_m());
            std::vector<gr_complex> h0(size_t(fs.grid_size())), hk(h0.size());
            frame_channel(fs, r, 0).fill(h0.data());
            for (int k = 0; k < cm.n_elements(); ++k) {
                cm.factors(r, 0, k).fill(hk.data());
                for (int m = 0; m < fs.n_subcarriers; ++m) {
                    const double e = std::abs(std::arg(cd(hk[size_t(m)]) / (cd(h0[size_t(m)]) * s[size_t(k)])));
                    CPPUNIT_ASSERT_MESSAGE("error " + std::to_string(e) + " above the bound " + std::to_string(bound),
                                           e <= bound + 1e-6);
                    worst = std::max(worst, e);
                }
            }
        }
        CPPUNIT_ASSERT_DOUBLES_EQUAL(bound, worst, 1e-5);
        CPPUNIT_ASSERT_EQUAL(0.0, narrowband_phase_error_rad(array_geometry(), fs));
    }

    void cosine_elements_see_nothing_behind()
    {
        CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, element_pattern_amplitude(element_pattern::cosine, direction_vector(0, 0)), 0.0);
        const double c = std::cos(0.6) * std::cos(0.2);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(c * c, element_pattern_amplitude(element_pattern::cosine, direction_vector(0.6, 0.2)),
                                     1e-15);
        CPPUNIT_ASSERT_EQUAL(0.0, element_pattern_amplitude(element_pattern::cosine, direction_vector(2.5, 0)));
        const auto a = array_geometry::ula(4, 0.05, element_pattern::cosine);
        const frame_settings fs;
        channel_model front(fs, point_target(30, 2, 0.6, 0).with_array(a), 1), back(fs, point_target(30, 2, 2.5, 0).with_array(a), 1);
        std::vector<gr_complex> h(size_t(fs.grid_size()));
        const auto rf = front.draw(0);
        front.factors(rf, 0, 2).fill(h.data());
        CPPUNIT_ASSERT_DOUBLES_EQUAL(std::cos(0.6) * std::cos(0.6), std::abs(cd(h[7])), 1e-6);
        const auto rb = back.draw(0);
        back.factors(rb, 0, 2).fill(h.data());
        for (const auto& x : h)
            CPPUNIT_ASSERT_EQUAL(0.0f, std::abs(x));
    }

    void clutter_scatterers_come_from_their_own_azimuths()
    {
        auto sc = scene::parse(R"({"format": "sems.scene", "version": 1,
            "targets": [{"class": "car", "range_m": 60, "velocity_mps": 10}],
            "clutter": {"csr_db": 10, "paths": 6}})");
        channel_model plain(frame_settings{}, sc, 3);
        for (const auto& p : plain.draw(0).paths)
            CPPUNIT_ASSERT_EQUAL(0.0, p.azimuth_rad);
        channel_model seen(frame_settings{}, sc.with_array(array_geometry::ula(4, 0.05)), 3);
        const auto r = seen.draw(0);
        int distinct = 0;
        for (size_t l = 1; l < r.paths.size(); ++l) {
            CPPUNIT_ASSERT(std::fabs(r.paths[l].azimuth_rad) <= M_PI / 2);
            distinct += r.paths[l].azimuth_rad != r.paths[1].azimuth_rad;
        }
        CPPUNIT_ASSERT_EQUAL(5, distinct);
        // Fixed scatterers sit where the scene says; a track's drawn ones keep their azimuths.
        channel_model fixed(frame_settings{}, scene::parse(R"({"format": "sems.scene", "version": 1,
            "targets": [{"class": "car", "range_m": 60, "velocity_mps": 10}],
            "clutter": {"csr_db": 0, "ranges_m": [20, 30], "azimuths_rad": [0.3, -1.2]}})").with_array(array_geometry::ula(2, 0.05)), 3);
        const auto rf = fixed.draw(0);
        CPPUNIT_ASSERT_EQUAL(0.3, rf.paths[1].azimuth_rad);
        CPPUNIT_ASSERT_EQUAL(-1.2, rf.paths[2].azimuth_rad);
        channel_model tracked(frame_settings{}, scene::parse(R"({"format": "sems.scene", "version": 1,
            "random": {"tracks": {"frames": 4}}, "clutter": {"csr_db": 0, "paths": 3}})").with_array(array_geometry::ula(2, 0.05)), 3);
        const auto t0 = tracked.draw(0), t1 = tracked.draw(1);
        for (size_t l = 1; l < t0.paths.size(); ++l)
            CPPUNIT_ASSERT_EQUAL(t0.paths[l].azimuth_rad, t1.paths[l].azimuth_rad);
        CPPUNIT_ASSERT(t0.paths[1].azimuth_rad != t0.paths[2].azimuth_rad);
        assert_error([] { scene::parse(R"({"format": "sems.scene", "version": 1, "targets": [{"class": "car",
            "range_m": 60, "velocity_mps": 10}], "clutter": {"csr_db": 0, "ranges_m": [20, 30], "azimuths_rad": [0.3]}})", "s.json"); },
                     "clutter.azimuths_rad", "2 to 2");
    }

    void random_targets_draw_their_azimuths_and_tracks_keep_them()
    {
        const auto per_frame = scene::parse(R"({"format": "sems.scene", "version": 1,
            "random": {"azimuth_rad": [-0.8, 0.5]}})");
        channel_model cm(frame_settings{}, per_frame, 4);
        double lo = 1.0, hi = -1.0;
        for (uint64_t f = 0; f < 200; ++f) {
            const auto r = cm.draw(f);
            const double az = r.paths[0].azimuth_rad;
            CPPUNIT_ASSERT(az >= -0.8 && az <= 0.5);
            lo = std::min(lo, az);
            hi = std::max(hi, az);
        }
        CPPUNIT_ASSERT(lo < -0.7 && hi > 0.4); // spread over the interval
        // A single value is every target's; a track keeps the azimuth it drew.
        channel_model fixed_az(frame_settings{}, scene::parse(R"({"format": "sems.scene", "version": 1,
            "random": {"azimuth_rad": 0.25}})"), 4);
        CPPUNIT_ASSERT_EQUAL(0.25, fixed_az.draw(0).paths[0].azimuth_rad);
        channel_model tracked(frame_settings{}, scene::parse(R"({"format": "sems.scene", "version": 1,
            "random": {"azimuth_rad": [-1, 1], "tracks": {"frames": 8}}})"), 4);
        const double first = tracked.draw(0).paths[0].azimuth_rad;
        for (uint64_t f = 1; f < 8; ++f)
            CPPUNIT_ASSERT_EQUAL(first, tracked.draw(f).paths[0].azimuth_rad);
        CPPUNIT_ASSERT(tracked.draw(8).paths[0].azimuth_rad != first); // the next track draws again
    }

    // random.elevation_rad: drawn last, so the first frame is the ground-plane one's with its
    // radial velocity projected (v·cos ε); every frame's radial velocity is its body's speed
    // projected, speed·cos(heading)·cos ε, its walker seen from −ε, its truth at ε; a track keeps it.
    void random_targets_draw_their_elevations()
    {
        const std::string walkers = R"({"format": "sems.scene", "version": 1, "classes": "kinematic",
            "array": {"receive": {"ula": {"elements": 2, "spacing_m": 0.05}}},
            "random": {"classes": ["adult", "child"], "heading": "any", )";
        const auto ground = scene::parse(walkers + R"("azimuth_rad": [-1, 1]}})");
        const auto raised = scene::parse(walkers + R"("azimuth_rad": [-1, 1], "elevation_rad": [-0.6, -0.1]}})");
        CPPUNIT_ASSERT(scene::parse(raised.to_json_string()).to_json_string() == raised.to_json_string());
        channel_model flat(frame_settings{}, ground, 9), tilted(frame_settings{}, raised, 9);
        double lo = 0.0, hi = -1.0;
        {
            const auto a = flat.draw(0), b = tilted.draw(0);
            CPPUNIT_ASSERT_EQUAL(a.truth.azimuth_rad, b.truth.azimuth_rad);
            CPPUNIT_ASSERT_EQUAL(a.truth.range_m, b.truth.range_m);
            CPPUNIT_ASSERT_DOUBLES_EQUAL(a.truth.velocity_mps * std::cos(b.truth.elevation_rad), b.truth.velocity_mps, 1e-12);
        }
        for (uint64_t f = 0; f < 100; ++f) {
            const auto b = tilted.draw(f);
            const double e = b.truth.elevation_rad;
            CPPUNIT_ASSERT(e >= -0.6 && e <= -0.1);
            lo = std::min(lo, e);
            hi = std::max(hi, e);
            const auto& body = b.bodies.at(static_cast<size_t>(b.truth_body));
            CPPUNIT_ASSERT_DOUBLES_EQUAL(body.speed_mps * std::cos(body.heading_rad) * std::cos(e), b.truth.velocity_mps, 1e-9);
            CPPUNIT_ASSERT_EQUAL(e, b.paths[0].elevation_rad);
            CPPUNIT_ASSERT_EQUAL(-e, body.elevation_rad);
        }
        CPPUNIT_ASSERT(lo < -0.55 && hi > -0.15); // spread over the interval
        channel_model tracked(frame_settings{}, scene::parse(walkers + R"("elevation_rad": [-1, 0],
            "tracks": {"frames": 8}}})"), 4);
        const double first = tracked.draw(0).truth.elevation_rad;
        for (uint64_t f = 1; f < 8; ++f)
            CPPUNIT_ASSERT_EQUAL(first, tracked.draw(f).truth.elevation_rad);
        CPPUNIT_ASSERT(tracked.draw(8).truth.elevation_rad != first);
        // A rotor or wheels is modelled from the ground plane: refused by name, unless drawn
        // without micro-motion; the interval is checked like the azimuth's.
        assert_error([] {
            scene::parse(R"({"format": "sems.scene", "version": 1, "classes": "kinematic",
                "random": {"classes": ["adult", "quadcopter"], "elevation_rad": 0.2}})", "s.json");
        }, "random.elevation_rad", "quadcopter");
        scene::parse(R"({"format": "sems.scene", "version": 1, "classes": "kinematic",
            "random": {"classes": ["adult", "quadcopter"], "elevation_rad": 0.2, "micro_doppler": false}})");
        assert_error([] {
            scene::parse(R"({"format": "sems.scene", "version": 1, "random": {"elevation_rad": [-2, 0]}})", "s.json");
        }, "random.elevation_rad", "[-pi/2, pi/2]");
        assert_error([] {
            scene::parse(R"({"format": "sems.scene", "version": 1, "random": {"elevation_rad": [0.3, 0.2]}})", "s.json");
        }, "random.elevation_rad", "min exceeds max");
        // Without an array the truth names no direction.
        channel_model single(frame_settings{}, scene::parse(R"({"format": "sems.scene", "version": 1,
            "random": {"elevation_rad": 0.3}})"), 4);
        CPPUNIT_ASSERT(std::isnan(single.draw(0).truth.elevation_rad));
        CPPUNIT_ASSERT(std::isnan(single.draw(0).truth.azimuth_rad));
    }

    // A class of a library may give its own azimuth and elevation (values or intervals): its
    // targets draw from them in place of the scene's intervals, the other classes' from the
    // scene's; the library writes them back; bad ones are refused naming the class and field.
    void class_libraries_give_their_own_angles()
    {
        const auto lib_json = nlohmann::json::parse(R"({"format": "sems.classes", "version": 1, "name": "sides",
            "classes": [{"name": "left", "range_m": [5, 50], "speed_mps": [0.5, 1.5], "azimuth_rad": [0.2, 0.3],
                         "elevation_rad": [-0.2, -0.1], "micro_motion": {"model": "walker", "height_m": [1.6, 1.9]}},
                        {"name": "ahead", "range_m": [5, 50], "speed_mps": [0.5, 1.5], "azimuth_rad": 0.05},
                        {"name": "any", "range_m": [5, 50], "speed_mps": [0.5, 1.5]}]})");
        const auto lib = class_library::from_json(lib_json, "sides.json");
        CPPUNIT_ASSERT(class_library::from_json(lib->to_json(), "again.json")->to_json() == lib->to_json());
        CPPUNIT_ASSERT(!lib->at(2).has_azimuth() && !lib->at(2).has_elevation());
        random_spec r;
        r.classes.clear();
        r.azimuth_min_rad = -1.0;
        r.azimuth_max_rad = -0.5;
        r.heading = heading_kind::any;
        const auto ula = array_geometry::ula(4, 0.05);
        channel_model cm(frame_settings{}, scene::random(r, std::nullopt, fading_kind::none, lib).with_array(ula), 3);
        int seen[3] = { 0, 0, 0 };
        for (uint64_t f = 0; f < 300; ++f) {
            const auto d = cm.draw(f);
            const double az = d.truth.azimuth_rad, el = d.truth.elevation_rad;
            if (d.truth.class_name == "left") {
                CPPUNIT_ASSERT(az >= 0.2 && az <= 0.3 && el >= -0.2 && el <= -0.1);
                const auto& body = d.bodies.at(static_cast<size_t>(d.truth_body));
                CPPUNIT_ASSERT_DOUBLES_EQUAL(body.speed_mps * std::cos(body.heading_rad) * std::cos(el),
                                             d.truth.velocity_mps, 1e-9);
                ++seen[0];
            } else if (d.truth.class_name == "ahead") {
                CPPUNIT_ASSERT_EQUAL(0.05, az);
                CPPUNIT_ASSERT_EQUAL(0.0, el);
                ++seen[1];
            } else {
                CPPUNIT_ASSERT(az >= -1.0 && az <= -0.5);
                CPPUNIT_ASSERT_EQUAL(0.0, el);
                ++seen[2];
            }
        }
        CPPUNIT_ASSERT(seen[0] > 50 && seen[1] > 50 && seen[2] > 50);
        const auto with_class = [&](const std::string& extra) {
            auto j = lib_json;
            j["classes"][1].update(nlohmann::json::parse(extra));
            return j;
        };
        assert_error([&] { class_library::from_json(with_class(R"({"azimuth_rad": [-4, 0]})"), "sides.json"); },
                     "classes[1] (\"ahead\").azimuth_rad", "[-pi, pi]");
        assert_error([&] { class_library::from_json(with_class(R"({"elevation_rad": [0.3, 0.2]})"), "sides.json"); },
                     "classes[1].elevation_rad", "empty interval");
        assert_error([&] { class_library::from_json(with_class(R"({"elevation_rad": 1.7})"), "sides.json"); },
                     "classes[1] (\"ahead\").elevation_rad", "[-pi/2, pi/2]");
        assert_error([&] {
            class_library::from_json(with_class(R"({"elevation_rad": 0.2, "micro_motion": {"model": "rotor", "rotors": 4,
                "blades": 2, "blade_length_m": 0.1, "rotation_hz": 90}})"), "sides.json");
        }, "classes[1] (\"ahead\").elevation_rad", "rotor");
    }

    void array_files_round_trip()
    {
        const auto a = array_geometry::from_json(nlohmann::json::parse(R"({"format": "sems.array", "version": 1,
            "receive": {"ura": {"columns": 4, "rows": 2, "spacing_m": [0.05, 0.04]}},
            "transmit": {"positions_m": [[0, 0, 0], [0, 0.2, 0]]}, "pattern": "cosine"})"),
                                                 "test");
        CPPUNIT_ASSERT_EQUAL(8, a.n_receive());
        CPPUNIT_ASSERT_EQUAL(2, a.n_transmit());
        CPPUNIT_ASSERT(a.pattern() == element_pattern::cosine);
        CPPUNIT_ASSERT(array_geometry::from_json(a.to_json(), "again") == a);
        // A scene names its array by file, relative to the scene's folder, or inline.
        const std::string dir = "qa_array_files";
        std::remove((dir + "/ula.json").c_str());
        std::remove((dir + "/scene.json").c_str());
        ::mkdir(dir.c_str(), 0755);
        array_geometry::ula(6, 0.05).save(dir + "/ula.json");
        std::ofstream(dir + "/scene.json") << R"({"format": "sems.scene", "version": 1, "array": "ula.json",
            "targets": [{"class": "car", "range_m": 60, "velocity_mps": 10, "azimuth_rad": 0.3}]})";
        const auto sc = scene::load(dir + "/scene.json");
        CPPUNIT_ASSERT(sc.array().has_value());
        CPPUNIT_ASSERT(*sc.array() == array_geometry::ula(6, 0.05));
        CPPUNIT_ASSERT_EQUAL(0.3, sc.targets()[0].azimuth_rad);
        const auto again = scene::from_json(sc.to_json(), "round trip");
        CPPUNIT_ASSERT(*again.array() == *sc.array());
        CPPUNIT_ASSERT_EQUAL(0.3, again.targets()[0].azimuth_rad);
        std::remove((dir + "/ula.json").c_str());
        std::remove((dir + "/scene.json").c_str());
        ::rmdir(dir.c_str());
    }

    void bad_arrays_are_refused_by_name()
    {
        assert_error([] { array_geometry::ula(4, 0.0); }, "spacing_m", "> 0");
        assert_error([] { array_geometry::ula(4, -0.05); }, "spacing_m", "-0.05");
        assert_error([] { array_geometry::ula(0, 0.05); }, "elements", "got 0");
        assert_error([] { array_geometry::ula(limits::max_array_elements + 1, 0.05); }, "1025", "limits.h");
        assert_error([] { array_geometry::ura(64, 32, 0.05, 0.05); }, "2048", "limits.h");
        assert_error([] { array_geometry::from_positions({ { 0, 0.1, 0 }, { 0, 0.1, 0 } }); }, "elements 0 and 1", "coincide");
        assert_error([] { array_geometry::from_positions({ { 0, NAN, 0 } }); }, "receive[0]", "finite");
        auto parse = [](const char* text) { return array_geometry::from_json(nlohmann::json::parse(text), "a.json"); };
        assert_error([&] { parse(R"({"format": "sems.array", "version": 1, "receive": {"ula": {"elements": 4, "spacing_m": 0}}})"); },
                     "a.json: receive.ula.spacing_m", "> 0");
        assert_error([&] { parse(R"({"format": "sems.array", "version": 1, "receive": {"ula": {"elements": 2000, "spacing_m": 0.1}}})"); },
                     "receive.ula.elements", "limits.h");
        assert_error([&] { parse(R"({"format": "sems.array", "version": 1, "receive": {"positions_m": [[0,0,0],[0,0,0]]}})"); },
                     "a.json: receive", "coincide");
        assert_error([&] { parse(R"({"format": "sems.array", "version": 1, "receive": {"ula": {"elements": 2, "spacing_m": 0.1}, "positions_m": [[0,0,0]]}})"); },
                     "receive", "exactly one of");
        assert_error([&] { parse(R"({"format": "sems.array", "version": 1, "receive": {"ula": {"elements": 2, "spacing_m": 0.1}}, "pattern": "dipole"})"); },
                     "pattern", "dipole");
        assert_error([&] { parse(R"({"format": "sems.array", "version": 1, "receive": {"positions_m": [[0,0]]}})"); },
                     "receive.positions_m[0]", "3 to 3");
        assert_error([&] { parse(R"({"format": "sems.array", "version": 1, "receive": {"ula": {"elements": 2, "spacing_m": 0.1}}, "spacing": 1})"); },
                     "spacing", "unknown key");
        // The channel refuses an element beyond the array, naming both counts.
        channel_model cm(frame_settings{}, point_target(50, 1, 0, 0).with_array(array_geometry::ula(4, 0.05)), 1);
        const auto r = cm.draw(0);
        assert_error([&] { cm.factors(r, 0, 4); }, "element 4", "4 streams");
        // Nor is one stream of several taken for the scene's channel without naming it.
        assert_error([&] { cm.factors(r, 0); }, "4 streams", "element index");
        std::vector<gr_complex> h(frame_settings{}.grid_size());
        assert_error([&] { cm.generate(1, h.data()); }, "4 streams", "element index");
    }

    void bad_angles_are_refused_by_name()
    {
        auto target = [](const char* extra) {
            return std::string(R"({"format": "sems.scene", "version": 1, "targets": [{"class": "car", "range_m": 60, "velocity_mps": 10, )") +
                   extra + "}]}";
        };
        assert_error([&] { scene::parse(target(R"("azimuth_rad": 3.5)"), "s.json"); }, "targets[0].azimuth_rad", "[-pi, pi]");
        assert_error([&] { scene::parse(target(R"("elevation_rad": -1.7)"), "s.json"); }, "targets[0].elevation_rad",
                     "[-pi/2, pi/2]");
        assert_error([&] {
            scene::parse(R"({"format": "sems.scene", "version": 1, "targets": [{"class": "car", "range_m": 60,
                "velocity_mps": 10, "elevation_rad": 0.2, "micro_motion": {"model": "scatterers",
                "scatterers": [{"power": 1}]}}]})", "s.json");
        }, "targets[0].elevation_rad", "scatterers");
        assert_error([&] {
            scene::parse(R"({"format": "sems.scene", "version": 1, "random": {"azimuth_rad": [-4, 0]}})", "s.json");
        }, "random.azimuth_rad", "[-pi, pi]");
        assert_error([&] {
            scene::parse(R"({"format": "sems.scene", "version": 1, "random": {"azimuth_rad": [0.5, -0.5]}})", "s.json");
        }, "random.azimuth_rad", "min exceeds max");
        // A speed along a heading seen from above: the radial velocity is its projection.
        const auto sc = scene::parse(target("").substr(0, target("").find("\"velocity_mps\"")) +
                                         R"("speed_mps": 10, "heading_rad": 0.5, "elevation_rad": 0.4}]})",
                                     "s.json");
        CPPUNIT_ASSERT_DOUBLES_EQUAL(10 * std::cos(0.5) * std::cos(0.4), sc.targets()[0].velocity_mps, 1e-12);
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_array);
