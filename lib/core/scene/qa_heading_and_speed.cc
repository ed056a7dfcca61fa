// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems QA: a body's heading and speed shape its scatterers — the `scatterers` model seen
 * along the line of sight (cos θ of its motion), and class-library parameters coupled to the
 * target's speed ({"per_speed": k, "offset": c}). */
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

using namespace gr::sems;
using cd = std::complex<double>;

namespace {

const std::string heading_scene_head = R"({"format": "sems.scene", "version": 1, "fading": "none", )";

// Three scatterers: a fixed one, one on two harmonics, one offset 0.5 m ahead and turning.
const std::string three_scatterers = R"({"model": "scatterers", "scatterers": [
    {"power": 1},
    {"power": 2, "harmonics": [{"amplitude_m": 0.05, "rate_hz": 31, "phase_rad": 1},
                               {"amplitude_m": 0.02, "rate_hz": 7, "phase_rad": 2}]},
    {"power": 0.5, "harmonics": [{"amplitude_m": 0.5, "rate_hz": 0, "phase_rad": -1.5707963267948966},
                                 {"amplitude_m": 0.34, "rate_hz": 2.2, "phase_rad": 0.4}]}]})";

std::vector<gr_complex> grid(const frame_settings& fs, const scene& s)
{
    channel_model cm(fs, s, 1);
    std::vector<gr_complex> h(fs.grid_size());
    cm.generate(1, h.data());
    return h;
}

// A number in JSON, every digit kept (std::to_string keeps 6 decimals: π/2 would not be).
std::string num(double x) { return nlohmann::json(x).dump(); }

scene target_at(double speed, double heading, const std::string& motion)
{
    return scene::parse(heading_scene_head + R"("targets": [{"class": "car", "range_m": 30, "speed_mps": )" + num(speed) +
                        R"(, "heading_rad": )" + num(heading) + R"(, "micro_motion": )" + motion + "}]}");
}

// Energy of a target's slow time beyond its bulk Doppler, relative to its total: the grid's
// rows after removing the bulk phase ramp, minus their mean over the frame, per subcarrier.
double energy_beyond_bulk(const frame_settings& fs, const std::vector<gr_complex>& h, double velocity_mps)
{
    const double nu = 2.0 * velocity_mps * fs.carrier_hz / speed_of_light_mps;
    double beyond = 0.0, total = 0.0;
    for (int m = 0; m < fs.n_subcarriers; ++m) {
        std::vector<cd> x(fs.n_symbols);
        cd mean = 0.0;
        for (int n = 0; n < fs.n_symbols; ++n) {
            x[n] = cd(h[size_t(n) * fs.n_subcarriers + m]) * std::polar(1.0, -2 * M_PI * nu * n * fs.symbol_interval_s);
            mean += x[n] / double(fs.n_symbols);
        }
        for (const cd& v : x) {
            beyond += std::norm(v - mean);
            total += std::norm(v);
        }
    }
    return beyond / total;
}

} // namespace

class qa_heading_and_speed : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_heading_and_speed);
    CPPUNIT_TEST(scatterers_follow_the_line_of_sight);
    CPPUNIT_TEST(bicyclist_side_on_has_no_micro_doppler);
    CPPUNIT_TEST(coupled_parameters_follow_the_speed);
    CPPUNIT_TEST(bad_coupled_parameters_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    // The closed form: scatterer s at range R − v t + cos θ · r_s(t), r_s the harmonics' sum
    // along the heading, summed with its amplitude, at every subcarrier's wavelength.
    void scatterers_follow_the_line_of_sight()
    {
        const frame_settings fs;
        const double speed = 4.0;
        for (double theta : { 0.0, 0.7, M_PI / 2, 2.5, M_PI }) {
            const auto h = grid(fs, target_at(speed, theta, three_scatterers));
            const double c = std::cos(theta), v = speed * c, tau = fs.delay_from_range(30.0);
            const double amps[] = { std::sqrt(1 / 3.5), std::sqrt(2 / 3.5), std::sqrt(0.5 / 3.5) };
            std::vector<cd> got, want;
            for (int n = 0; n < fs.n_symbols; ++n) {
                const double t = n * fs.symbol_interval_s;
                const double r[] = { 0.0,
                                     -c * (0.05 * std::sin(2 * M_PI * 31 * t + 1) + 0.02 * std::sin(2 * M_PI * 7 * t + 2)),
                                     -c * (0.5 * std::sin(-M_PI / 2) + 0.34 * std::sin(2 * M_PI * 2.2 * t + 0.4)) };
                const cd bulk = std::polar(1.0, 2 * M_PI * (2 * v * fs.carrier_hz / speed_of_light_mps) * t);
                for (int m = 0; m < fs.n_subcarriers; ++m) {
                    const double kappa = 4 * M_PI * (fs.carrier_hz + m * fs.subcarrier_spacing_hz()) / speed_of_light_mps;
                    cd w = 0.0;
                    for (int k = 0; k < 3; ++k)
                        w += amps[k] * std::polar(1.0, -kappa * r[k]);
                    want.push_back(bulk * w * std::polar(1.0, -2 * M_PI * m * fs.subcarrier_spacing_hz() * tau));
                    got.push_back(cd(h[size_t(n) * fs.n_subcarriers + m]));
                }
            }
            // Equal up to the model's one real power normalisation, to float rounding.
            qa::assert_equal_up_to_power(got, want, 2e-6, "heading " + std::to_string(theta));
        }
    }

    // The kinematic library's bicyclist crossing the beam (θ = π/2): its pedals and rims move
    // across the line of sight, so nothing is left beyond the bulk (0 Hz) but rounding; head-on
    // the same body spreads a good part of its energy over its micro-Doppler.
    void bicyclist_side_on_has_no_micro_doppler()
    {
        const auto kin = class_library::find("kinematic");
        const std::string motion = kin->to_json()["classes"][5]["micro_motion"].dump();
        const frame_settings fs;
        CPPUNIT_ASSERT_EQUAL(std::string("bicyclist"), kin->at(5).name);
        auto bicyclist = [&](double heading) {
            nlohmann::json j = nlohmann::json::parse(motion);
            for (auto& s : j["scatterers"]) // the library's speed-coupled rates at 4.7 m/s
                if (s.contains("harmonics"))
                    for (auto& h : s["harmonics"])
                        if (h["rate_hz"].is_object())
                            h["rate_hz"] = h["rate_hz"]["per_speed"].get<double>() * 4.7;
            return scene::parse(heading_scene_head + R"("classes": "kinematic", "targets": [{"class": "bicyclist", "range_m": 60,
                "speed_mps": 4.7, "heading_rad": )" + num(heading) + R"(, "micro_motion": )" + j.dump() + "}]}");
        };
        const double side = energy_beyond_bulk(fs, grid(fs, bicyclist(M_PI / 2)), 4.7 * std::cos(M_PI / 2));
        const double ahead = energy_beyond_bulk(fs, grid(fs, bicyclist(0.0)), 4.7);
        CPPUNIT_ASSERT_MESSAGE("side-on: " + std::to_string(side), side < 1e-10);
        CPPUNIT_ASSERT_MESSAGE("head-on: " + std::to_string(ahead), ahead > 0.05);
    }

    // {"per_speed": k, "offset": c}: the drawn value is c + k·speed, k drawn per frame from an
    // interval; every other draw of the library is unchanged.
    void coupled_parameters_follow_the_speed()
    {
        const auto lib = class_library::from_json(nlohmann::json::parse(R"({"format": "sems.classes", "version": 1,
            "name": "coupled", "classes": [{"name": "rider", "range_m": [10, 100], "speed_mps": [2, 9],
              "micro_motion": {"model": "scatterers", "scatterers": [
                {"power": 1, "harmonics": [{"amplitude_m": 0.3, "rate_hz": {"per_speed": 0.4681}},
                                           {"amplitude_m": 0.1, "rate_hz": {"per_speed": [0.25, 0.35], "offset": 0.2}}]}]}}]})"),
                                                 "coupled.json");
        random_spec r;
        r.classes.clear();
        r.heading = heading_kind::any;
        channel_model cm(frame_settings{}, scene::random(r, std::nullopt, fading_kind::none, lib), 7);
        double k_lo = 1.0, k_hi = 0.0;
        for (int f = 0; f < 400; ++f) {
            const auto fr = cm.draw(uint64_t(f));
            CPPUNIT_ASSERT_EQUAL(size_t(1), fr.bodies.size());
            const double v = fr.bodies[0].speed_mps;
            CPPUNIT_ASSERT(v >= 2.0 && v <= 9.0);
            const auto& hs = std::get<scatterers_motion>(fr.bodies[0].motion).scatterers[0].harmonics;
            CPPUNIT_ASSERT_DOUBLES_EQUAL(0.4681 * v, hs[0].rate_hz, 1e-12);
            const double k = (hs[1].rate_hz - 0.2) / v;
            CPPUNIT_ASSERT(k >= 0.25 - 1e-12 && k <= 0.35 + 1e-12);
            k_lo = std::min(k_lo, k);
            k_hi = std::max(k_hi, k);
            // the radial velocity is still speed·cos θ of the drawn speed
            CPPUNIT_ASSERT_DOUBLES_EQUAL(v * std::cos(fr.bodies[0].heading_rad), fr.truth.velocity_mps, 1e-9);
        }
        CPPUNIT_ASSERT(k_lo < 0.26 && k_hi > 0.34); // k is drawn over its whole interval
        // Bounds read the coupled values at the class's speed ends: the bulk 9 m/s plus the
        // fastest harmonics, 2π · 0.4681·9 Hz · 0.3 m and 2π · (0.2 + 0.35·9) Hz · 0.1 m.
        const double peak = 9.0 + 2 * M_PI * (0.4681 * 9 * 0.3 + (0.2 + 0.35 * 9) * 0.1);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(peak, lib->at(0).max_scatterer_speed_mps(), 1e-9);
        // The library writes the coupling back as given.
        CPPUNIT_ASSERT(class_library::from_json(lib->to_json(), "again")->to_json() == lib->to_json());
    }

    void bad_coupled_parameters_are_refused()
    {
        auto lib = [](const std::string& motion) {
            return [motion] {
                class_library::from_json(nlohmann::json::parse(R"({"format": "sems.classes", "version": 1, "name": "x",
                    "classes": [{"name": "a", "range_m": [0, 50], "speed_mps": [0, 5], "micro_motion": )" + motion + "}]}"),
                                         "lib.json");
            };
        };
        // negative at the slowest speed: the low end of offset + k·v is checked
        qa::assert_error(lib(R"({"model": "scatterers", "scatterers": [{"harmonics": [{"amplitude_m": 0.1,
            "rate_hz": {"per_speed": 1, "offset": -1}}]}]})"),
                         "lib.json: classes[0] (\"a\").micro_motion.scatterers[0].harmonics[0]", "rate_hz");
        qa::assert_error(lib(R"({"model": "rotor", "blade_length_m": 0.1, "rotation_hz": 50, "rotors": {"per_speed": 1}})"),
                         "micro_motion.rotors", "count cannot follow the speed");
        qa::assert_error(lib(R"({"model": "walker", "height_m": {"per_speed": 0.3, "slope": 1}})"),
                         "micro_motion.height_m.slope", "unknown key");
        qa::assert_error(lib(R"({"model": "walker", "height_m": {"offset": 1.7}})"), "micro_motion.height_m.per_speed",
                         "missing");
        qa::assert_error(lib(R"({"model": "walker", "height_m": {"per_speed": [0.4, 0.3]}})"),
                         "micro_motion.height_m.per_speed", "empty interval");
        // a scene gives values: a coupling there is refused naming the field
        qa::assert_error([] {
            scene::parse(heading_scene_head + R"("targets": [{"class": "car", "range_m": 30, "speed_mps": 3, "micro_motion":
                {"model": "scatterers", "scatterers": [{"harmonics": [{"amplitude_m": 0.1, "rate_hz": {"per_speed": 1}}]}]}}]})",
                         "scene.json");
        },
                         "scene.json: targets[0].micro_motion.scatterers[0].harmonics[0].rate_hz", "class library only");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_heading_and_speed);
