// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: micro-motion models against their physics — Chen's rotor closed form, the
 * sinusoid's narrowband bound, rolling wheels' Doppler span, the expansion against a direct
 * per-scatterer sum, the paper and kinematic scenes' bits, extremes and bad input. */
#include "core/channel/scatterer_moments.h"
#include "core/kernels/vector_math.h"
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <cstdio>
#include <cstdlib>
#include <complex>
#include <fstream>
#include <string>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;
using cd = std::complex<double>;

namespace {

const std::string motion_scene_head = R"({"format": "sems.scene", "version": 1, "fading": "none", )";

// The noiseless grids of `frames` consecutive frames of a scene (frame f at slow time f·N).
std::vector<gr_complex> grids(const frame_settings& fs, const scene& s, size_t frames, uint64_t seed = 1)
{
    channel_model cm(fs, s, seed);
    std::vector<gr_complex> h(frames * fs.grid_size());
    cm.generate(frames, h.data());
    return h;
}

uint64_t fnv(const void* p, size_t n, uint64_t h)
{
    const auto* b = static_cast<const unsigned char*>(p);
    for (size_t i = 0; i < n; ++i) {
        h ^= b[i];
        h *= 1099511628211ULL;
    }
    return h;
}

// One hash of `frames` frames of a scene from frame `first_frame` on (the noiseless grids and
// the target of interest's class, range and velocity) and of 4 096 noise samples at 10 dB.
uint64_t frames_hash(const frame_settings& fs, const scene& s, uint64_t seed, size_t frames, uint64_t first_frame)
{
    channel_model cm(fs, s, seed);
    std::vector<gr_complex> h(frames * fs.grid_size());
    auto truths = cm.generate(frames, h.data(), first_frame);
    uint64_t hash = fnv(h.data(), h.size() * sizeof(gr_complex), 1469598103934665603ULL);
    for (auto& tr : truths) {
        hash = fnv(&tr.class_id, sizeof tr.class_id, hash);
        hash = fnv(&tr.range_m, 8, hash);
        hash = fnv(&tr.velocity_mps, 8, hash);
    }
    std::vector<gr_complex> y(4096, gr_complex(1, 0));
    cm.add_noise(y.data(), y.size(), 10.0);
    return fnv(y.data(), y.size() * 8, hash);
}

std::string hex(uint64_t x)
{
    char b[17];
    std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(x));
    return b;
}

double sinc(double x) { return std::fabs(x) < 1e-12 ? 1.0 : std::sin(x) / x; }

// |<a, b>| / (|a| |b|)
double correlation(const std::vector<cd>& a, const std::vector<cd>& b)
{
    cd dot = 0.0;
    double na = 0.0, nb = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        dot += a[i] * std::conj(b[i]);
        na += std::norm(a[i]);
        nb += std::norm(b[i]);
    }
    return std::abs(dot) / std::sqrt(na * nb);
}

} // namespace

class qa_micro_motion : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_micro_motion);
    CPPUNIT_TEST(paper_scenes_keep_their_bits);
    CPPUNIT_TEST(kinematic_scenes_keep_their_bits);
    CPPUNIT_TEST(sinusoid_model_is_micro_doppler);
    CPPUNIT_TEST(rotor_equals_chen_closed_form);
    CPPUNIT_TEST(one_harmonic_is_the_sinusoid_within_its_narrowband_bound);
    CPPUNIT_TEST(expansion_equals_direct_sum_on_wide_band);
    CPPUNIT_TEST(wheels_head_on_span_zero_to_twice_the_body);
    CPPUNIT_TEST(walker_torso_line_and_limb_spread);
    CPPUNIT_TEST(line_integrals_match_quadrature);
    CPPUNIT_TEST(extremes_stay_finite);
    CPPUNIT_TEST(mean_power_is_near_one);
    CPPUNIT_TEST(moving_scene_follows_its_track);
    CPPUNIT_TEST(bad_micro_motion_is_refused);
    CPPUNIT_TEST(shipped_class_libraries);
    CPPUNIT_TEST(bad_class_libraries_are_refused);
    CPPUNIT_TEST(scene_reads_its_library_beside_it);
    CPPUNIT_TEST(walker_frame_equals_direct_sum);
    CPPUNIT_TEST_SUITE_END();

public:
    // The paper's scenes (paper class library, sinusoid micro-Doppler) give the same frames,
    // truths and noise, bit for bit, as before micro-motion models existed.
    void paper_scenes_keep_their_bits()
    {
        frame_settings fs;
        std::vector<scene> scenes;
        scenes.push_back(scene::random(random_spec{}));
        random_spec any;
        any.heading = heading_kind::any;
        scenes.push_back(scene::random(any));
        random_spec no_md;
        no_md.micro_doppler = false;
        scenes.push_back(scene::random(no_md));
        random_spec multi;
        multi.paths_per_target = 3;
        multi.n_targets = 2;
        scenes.push_back(scene::random(multi, clutter_spec{}));
        target_spec t;
        t.cls = target_class::drone;
        t.range_m = 40;
        t.velocity_mps = 7;
        t.md = micro_doppler{ 100, 0.01, 0.3 };
        target_spec u;
        u.cls = target_class::pedestrian;
        u.range_m = 90;
        u.velocity_mps = -1.2;
        u.paths.push_back(path_spec{ 12, 0.3 });
        scenes.push_back(scene::fixed({ t, u }, clutter_spec{}, 1));
        // Hashes of the frames these scenes gave before scatterer models and class libraries.
        const uint64_t expected[] = { 0xcbf87bec03ccf82bULL, 0x34325b3486c4c9feULL, 0x8b45061bd66fa3cfULL,
                                      0x5b219f8ec08be7f3ULL, 0x005b5f462b830228ULL };
        for (size_t i = 0; i < scenes.size(); ++i)
            CPPUNIT_ASSERT_EQUAL_MESSAGE("paper scene " + std::to_string(i), expected[i], frames_hash(fs, scenes[i], 1234, 50, 7));
    }

    // The kinematic library's scenes (walkers, rotors, wheels; any heading; with and without
    // fading, extra paths and clutter; the paper's frame and the 2.4 GHz radio's) give the same
    // frames, truths and noise, bit for bit, as when these hashes were taken: a change of layout
    // or of an optimisation that moves a single bit fails here. The approaching scene (every
    // body head-on) keeps the hash it had before the scatterers model followed the line of
    // sight; the any-heading scenes took theirs then.
    void kinematic_scenes_keep_their_bits()
    {
        const auto kin = class_library::find("kinematic");
        struct kinematic_case {
            frame_settings fs;
            scene s;
        };
        std::vector<kinematic_case> cases;
        random_spec any;
        any.classes.clear(); // every class of the library
        any.heading = heading_kind::any;
        cases.push_back({ frame_settings{}, scene::random(any, std::nullopt, fading_kind::rayleigh, kin) });
        random_spec multi = any;
        multi.heading = heading_kind::approaching;
        multi.n_targets = 2;
        multi.paths_per_target = 2;
        cases.push_back({ frame_settings{}, scene::random(multi, clutter_spec{}, fading_kind::none, kin) });
        cases.push_back({ frame_file::find("sdr_2g4_20mhz").frame, scene::random(any, std::nullopt, fading_kind::rayleigh, kin) });
        const uint64_t expected[] = { 0x1cfb84c04e37a3bdULL, 0xaaef9ed5b08e9bc2ULL, 0xe9319c5321b852cfULL };
        std::string changed; // every case that moved, so one run shows them all
        for (size_t i = 0; i < cases.size(); ++i) {
            const uint64_t got = frames_hash(cases[i].fs, cases[i].s, 4321, 24, 11);
            if (got != expected[i])
                changed += " scene " + std::to_string(i) + ": 0x" + hex(got);
        }
        CPPUNIT_ASSERT_MESSAGE("kinematic scenes changed:" + changed, changed.empty());
    }

    void sinusoid_model_is_micro_doppler()
    {
        const auto a = scene::parse(motion_scene_head + R"("targets": [{"class": "drone", "range_m": 40, "velocity_mps": 7,
            "micro_doppler": {"rate_hz": 97, "amplitude_m": 0.012, "phase_rad": 0.4}}]})");
        const auto b = scene::parse(motion_scene_head + R"("targets": [{"class": "drone", "range_m": 40, "velocity_mps": 7,
            "micro_motion": {"model": "sinusoid", "rate_hz": 97, "amplitude_m": 0.012, "phase_rad": 0.4}}]})");
        const frame_settings fs;
        CPPUNIT_ASSERT(grids(fs, a, 3) == grids(fs, b, 3));
    }

    // Chen: a blade of length L returns L sinc(x) e^{-jx}, x = κ (L/2) cos β cos(2π f t + φ + 2πk/K),
    // at subcarrier m with κ_m = 4π(f_c + mΔf)/c. A fixed rotor, no bulk motion, no fading.
    // Odd and even blade counts: an even count's opposite blades are computed as conjugate pairs.
    void rotor_equals_chen_closed_form()
    {
        for (int K : { 3, 2, 4 })
            check_rotor_against_chen(K);
    }

    void check_rotor_against_chen(const int K)
    {
        const double L = 0.16, f_rot = 47.0, phi = 0.3, beta = 0.2;
        const int rotors = 2;
        const auto s = scene::parse(motion_scene_head + R"("targets": [{"class": "drone", "range_m": 30, "velocity_mps": 0,
            "micro_motion": {"model": "rotor", "rotors": 2, "blades": )" + std::to_string(K) + R"(, "blade_length_m": 0.16,
                             "rotation_hz": [47, 47], "phase_rad": [0.3, 0.3], "elevation_rad": 0.2, "body_power": 0}}]})");
        const frame_settings fs;
        const auto h = grids(fs, s, 2);
        const double tau = fs.delay_from_range(30.0);
        for (int m = 0; m < fs.n_subcarriers; m += 7) {
            const double kappa = 4.0 * M_PI * (fs.carrier_hz + m * fs.subcarrier_spacing_hz()) / speed_of_light_mps;
            std::vector<cd> got, want;
            for (int row = 0; row < 2 * fs.n_symbols; ++row) {
                const double t = row * fs.symbol_interval_s;
                cd sum = 0.0;
                for (int r = 0; r < rotors; ++r)
                    for (int k = 0; k < K; ++k) {
                        const double x = kappa * L / 2 * std::cos(beta) *
                                         std::cos(2 * M_PI * f_rot * t + phi + 2 * M_PI * k / K);
                        sum += L * sinc(x) * std::exp(cd(0, -x));
                    }
                want.push_back(sum * std::exp(cd(0, -2 * M_PI * m * fs.subcarrier_spacing_hz() * tau)));
                got.push_back(cd(h[size_t(row) * fs.n_subcarriers + m]));
            }
            const double c = correlation(got, want);
            CPPUNIT_ASSERT_MESSAGE(std::to_string(K) + " blades, subcarrier " + std::to_string(m) + ": correlation " +
                                       std::to_string(c),
                                   c > 0.999);
            // Stronger than the correlation: equal up to one real scale, to float rounding.
            cd num = 0.0;
            double den = 0.0;
            for (size_t i = 0; i < got.size(); ++i) {
                num += got[i] * std::conj(want[i]);
                den += std::norm(want[i]);
            }
            const cd scale = num / den;
            CPPUNIT_ASSERT(std::fabs(std::arg(scale)) < 1e-5);
            for (size_t i = 0; i < got.size(); ++i)
                CPPUNIT_ASSERT(std::abs(got[i] - scale * want[i]) < 2e-5 * std::abs(scale) * L * rotors * K);
        }
    }

    // A point scatterer with one harmonic is the paper's sinusoid made exact: the two differ
    // only by the per-subcarrier delay of the displacement, |e^{-j k_m r} − 1| ≤ 4π (M−1)Δf A / c.
    void one_harmonic_is_the_sinusoid_within_its_narrowband_bound()
    {
        const double A = 0.4;
        const auto sin = scene::parse(motion_scene_head + R"("targets": [{"class": "pedestrian", "range_m": 20, "velocity_mps": 1.5,
            "micro_motion": {"model": "sinusoid", "rate_hz": 2, "amplitude_m": 0.4, "phase_rad": 1}}]})");
        const auto pts = scene::parse(motion_scene_head + R"("targets": [{"class": "pedestrian", "range_m": 20, "velocity_mps": 1.5,
            "micro_motion": {"model": "scatterers", "scatterers": [{"power": 1,
                "harmonics": [{"amplitude_m": 0.4, "rate_hz": 2, "phase_rad": 1}]}]}}]})");
        const frame_settings fs;
        const auto a = grids(fs, sin, 20), b = grids(fs, pts, 20);
        const double bound = 4 * M_PI * (fs.n_subcarriers - 1) * fs.subcarrier_spacing_hz() * A / speed_of_light_mps;
        double worst = 0.0;
        for (size_t i = 0; i < a.size(); ++i)
            worst = std::max(worst, double(std::abs(a[i] - b[i])));
        CPPUNIT_ASSERT_MESSAGE("difference " + std::to_string(worst) + " > bound " + std::to_string(bound),
                               worst <= bound + 1e-6);
        CPPUNIT_ASSERT(worst > 0.3 * bound); // the exact delay term is really there
        // Subcarrier 0 has no delay term: the two agree to float rounding there.
        for (size_t row = 0; row < a.size() / fs.n_subcarriers; ++row)
            CPPUNIT_ASSERT(std::abs(a[row * fs.n_subcarriers] - b[row * fs.n_subcarriers]) < 1e-5);
    }

    // A 77 GHz, 1 GHz frame of 16 x 256: a body spans several range cells, so the expansion
    // needs sub-bands and high orders.
    static frame_settings wide_band_frame()
    {
        frame_settings fs;
        fs.carrier_hz = 77e9;
        fs.bandwidth_hz = 1e9;
        fs.n_subcarriers = 256;
        fs.n_symbols = 16;
        fs.symbol_interval_s = 20e-6;
        return fs;
    }

    // The separable expansion (scatterer_moments.h) against the direct sum Σ_s a_s e^{-jκ_m r_s}
    // on a 77 GHz, 1 GHz frame where a 0.6 m displacement spans 4 range cells: sub-bands and
    // high orders are in use, the error stays at float rounding.
    void expansion_equals_direct_sum_on_wide_band()
    {
        const frame_settings fs = wide_band_frame();
        const auto s = scene::parse(motion_scene_head + R"("targets": [{"class": "car", "range_m": 10, "velocity_mps": 0,
            "micro_motion": {"model": "scatterers", "scatterers": [
                {"power": 1, "harmonics": [{"amplitude_m": 0.6, "rate_hz": 900, "phase_rad": 0.2}]},
                {"power": 2, "harmonics": [{"amplitude_m": 0.05, "rate_hz": 3000, "phase_rad": 1},
                                           {"amplitude_m": 0.2, "rate_hz": 150, "phase_rad": 2}]},
                {"power": 0.5}]}}]})");
        const auto plan = detail::plan_expansion(fs, 0.6, 3.0);
        CPPUNIT_ASSERT(plan.sub_bands > 1);
        const auto h = grids(fs, s, 1);
        const double tau = fs.delay_from_range(10.0);
        const double amps[] = { std::sqrt(1 / 3.5), std::sqrt(2 / 3.5), std::sqrt(0.5 / 3.5) };
        std::vector<cd> got, want;
        for (int n = 0; n < fs.n_symbols; ++n) {
            const double t = n * fs.symbol_interval_s;
            const double r[] = { -0.6 * std::sin(2 * M_PI * 900 * t + 0.2),
                                 -0.05 * std::sin(2 * M_PI * 3000 * t + 1) - 0.2 * std::sin(2 * M_PI * 150 * t + 2),
                                 0.0 };
            for (int m = 0; m < fs.n_subcarriers; ++m) {
                const double kappa = 4 * M_PI * (fs.carrier_hz + m * fs.subcarrier_spacing_hz()) / speed_of_light_mps;
                cd w = 0.0;
                for (int k = 0; k < 3; ++k)
                    w += amps[k] * std::exp(cd(0, -kappa * r[k]));
                want.push_back(w * std::exp(cd(0, -2 * M_PI * m * fs.subcarrier_spacing_hz() * tau)));
                got.push_back(cd(h[size_t(n) * fs.n_subcarriers + m]));
            }
        }
        // Equal up to the model's one real power normalisation, to float rounding.
        qa::assert_equal_up_to_power(got, want, 2e-6, "wide band");
    }

    // Seen head-on, a rolling wheel's points move at 0 (contact) to 2v (top) radially: the
    // slow-time spectrum of a wheels-only target spans 0 to twice the body's Doppler.
    void wheels_head_on_span_zero_to_twice_the_body()
    {
        frame_settings fs;
        fs.n_symbols = 512; // 1.95 Hz bins at T = 1 ms
        const double v = 10.0; // body Doppler 2v/λ = 200 Hz; wheel tops 400 Hz
        const auto s = scene::parse(motion_scene_head + R"("targets": [{"class": "car", "range_m": 25, "velocity_mps": 10,
            "micro_motion": {"model": "wheels", "wheels": 2, "wheel_radius_m": 0.3, "rim_points": 16,
                             "spokes": 0, "body_power": 0}}]})");
        const auto h = grids(fs, s, 1);
        const int n = fs.n_symbols;
        const double bin = 1.0 / (n * fs.symbol_interval_s);
        double in_span = 0.0, total = 0.0, top = 0.0, bottom = 0.0;
        for (int k = 0; k < n; ++k) {
            cd acc = 0.0;
            for (int i = 0; i < n; ++i) {
                const double w = 0.5 - 0.5 * std::cos(2 * M_PI * i / n); // Hann: no leakage past a few bins
                acc += w * cd(h[size_t(i) * fs.n_subcarriers]) * std::exp(cd(0, -2 * M_PI * double(k) * i / n));
            }
            const double f = (k < n / 2 ? k : k - n) * bin;
            const double p = std::norm(acc);
            total += p;
            if (f >= -4 * bin && f <= 2 * fs.doppler_from_velocity(v) + 4 * bin)
                in_span += p;
            if (f > 300.0)
                top += p;
            if (f < 100.0)
                bottom += p;
        }
        CPPUNIT_ASSERT_MESSAGE("share in [0, 2ν]: " + std::to_string(in_span / total), in_span / total > 0.999);
        CPPUNIT_ASSERT(top / total > 0.01);    // the wheel tops reach towards 2ν
        CPPUNIT_ASSERT(bottom / total > 0.01); // the contact points towards 0
    }

    // A walker's strongest Doppler is the torso's 2v/λ; its limbs spread the spectrum out to the
    // feet's swing peak (about 4 v in the Boulic model) and no further.
    void walker_torso_line_and_limb_spread()
    {
        frame_settings fs;
        fs.n_symbols = 1024; // 1.02 s: more than one gait cycle; 0.98 Hz bins
        const double v = 1.4;
        const auto s = scene::parse(motion_scene_head + R"("targets": [{"class": "pedestrian", "range_m": 25, "velocity_mps": 1.4,
            "micro_motion": {"model": "walker", "height_m": 1.8}}]})");
        const auto h = grids(fs, s, 1);
        const int n = fs.n_symbols;
        const double bin = 1.0 / (n * fs.symbol_interval_s);
        const double torso = fs.doppler_from_velocity(v);
        double total = 0.0, limbs = 0.0, beyond = 0.0, peak = 0.0, peak_f = 0.0;
        for (int k = 0; k < n; ++k) {
            cd acc = 0.0;
            for (int i = 0; i < n; ++i) {
                const double w = 0.5 - 0.5 * std::cos(2 * M_PI * i / n);
                acc += w * cd(h[size_t(i) * fs.n_subcarriers + 32]) * std::exp(cd(0, -2 * M_PI * double(k) * i / n));
            }
            const double f = (k < n / 2 ? k : k - n) * bin;
            const double p = std::norm(acc);
            total += p;
            if (p > peak) {
                peak = p;
                peak_f = f;
            }
            if (std::fabs(f - torso) > 10.0)
                limbs += p;
            if (f > fs.doppler_from_velocity(4.5 * v) + 4 * bin || f < -fs.doppler_from_velocity(1.0 * v) - 4 * bin)
                beyond += p;
        }
        const std::string msg = "peak at " + std::to_string(peak_f) + " Hz (torso " + std::to_string(torso) +
                                "), limbs " + std::to_string(limbs / total) + ", beyond " + std::to_string(beyond / total);
        CPPUNIT_ASSERT_MESSAGE(msg, std::fabs(peak_f - torso) <= 2 * bin);
        CPPUNIT_ASSERT_MESSAGE(msg, limbs / total > 0.05);
        CPPUNIT_ASSERT_MESSAGE(msg, beyond / total < 0.005);
        // Outside the model's speeds: refused, naming the speed and the range.
        assert_error([] {
            scene::parse(R"({"format": "sems.scene", "version": 1, "targets": [{"class": "pedestrian", "range_m": 25,
                "velocity_mps": 4, "micro_motion": {"model": "walker", "height_m": 1.2}}]})", "w.json");
        }, "w.json: targets[0].speed_mps", "valid range");
    }

    void line_integrals_match_quadrature()
    {
        for (double z : { 0.0, 1e-9, 0.5, 3.0, 7.99, 8.01, 20.0, -35.0, 400.0 }) {
            cd got[detail::max_order + 1];
            detail::line_integrals(z, detail::max_order, got);
            for (int p = 0; p <= detail::max_order; ++p) {
                cd want = 0.0; // composite Simpson on 20 000 intervals
                const int n = 20000;
                for (int i = 0; i <= n; ++i) {
                    const double s = double(i) / n;
                    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
                    want += w * std::pow(s, p) * std::exp(cd(0, -z * s));
                }
                want /= 3.0 * n;
                CPPUNIT_ASSERT_MESSAGE("E_" + std::to_string(p) + "(" + std::to_string(z) + ")",
                                       std::abs(got[p] - want) < 1e-9);
            }
        }
        // The frame-at-a-time upward recurrence (a rotor's blades) is line_integrals' own where
        // |z| ≥ max(2, order), its stable range: the same values for every order.
        const std::vector<double> zs = { 2.0, -2.5, 3.7, 8.01, -14.0, 20.0, -35.0, 400.0 };
        const size_t n = zs.size();
        std::vector<double> cs(n), sn(n), re, im, w(n);
        for (size_t i = 0; i < n; ++i) {
            cs[i] = std::cos(zs[i]);
            sn[i] = std::sin(zs[i]);
        }
        for (int order = 0; order <= detail::max_order; ++order) {
            re.assign(size_t(order + 1) * n, 0.0);
            im.assign(size_t(order + 1) * n, 0.0);
            detail::upward_line_integrals(zs.data(), cs.data(), sn.data(), n, order, re.data(), im.data(), w.data());
            for (size_t i = 0; i < n; ++i) {
                if (std::fabs(zs[i]) < std::max(2.0, double(order)))
                    continue;
                cd want[detail::max_order + 1];
                detail::line_integrals(zs[i], cd(cs[i], -sn[i]), order, want);
                for (int p = 0; p <= order; ++p)
                    CPPUNIT_ASSERT(std::abs(cd(re[size_t(p) * n + i], im[size_t(p) * n + i]) - want[p]) <=
                                   1e-15 * std::abs(want[p]));
            }
        }
    }

    void extremes_stay_finite()
    {
        std::string many = R"({"model": "scatterers", "scatterers": [)";
        for (int i = 0; i < 256; ++i)
            many += std::string(i ? "," : "") + R"({"power": )" + std::to_string(1 + i % 5) +
                    R"(, "harmonics": [{"amplitude_m": 0.3, "rate_hz": )" + std::to_string(10 * i + 1) + "}]}";
        many += "]}";
        const std::vector<std::string> motions = {
            R"({"model": "rotor", "rotors": 8, "blades": 5, "blade_length_m": 0.5, "rotation_hz": 300, "body_power": 0.1})",
            R"({"model": "rotor", "rotors": 1, "blades": 1, "blade_length_m": 0.2, "rotation_hz": 0, "body_power": 1})",
            R"({"model": "wheels", "wheels": 16, "wheel_radius_m": 0.4, "rim_points": 64, "spokes": 64, "body_power": 0})",
            // Harmonic rates 1e300 apart: the normalisation's sampling must not overflow an int
            // (found by fuzz_classes).
            R"({"model": "scatterers", "scatterers": [{"power": 1, "harmonics": [{"amplitude_m": 0.1, "rate_hz": 1e-150},
                {"amplitude_m": 0.1, "rate_hz": 1e150}]}]})",
            many
        };
        const frame_settings fs;
        for (const auto& m : motions)
            for (double v : { 0.0, 20.0 }) {
                const auto s = scene::parse(R"({"format": "sems.scene", "version": 1, "targets": [{"class": "drone",
                    "range_m": 60, "velocity_mps": )" + std::to_string(v) + R"(, "micro_motion": )" + m + "}]}");
                channel_model cm(fs, s, 3);
                std::vector<gr_complex> h(4 * fs.grid_size());
                cm.generate(4, h.data(), 123456789);
                for (double snr : { -50.0, 300.0 }) {
                    auto y = h;
                    cm.add_noise(y.data(), y.size(), snr);
                    for (auto x : y)
                        CPPUNIT_ASSERT(std::isfinite(x.real()) && std::isfinite(x.imag()));
                }
            }
    }

    // Scatterer powers are normalised incoherently (Σ a_s² = 1): over Rayleigh gains and random
    // phases the mean channel power is 1 up to the scatterers' cross terms.
    void mean_power_is_near_one()
    {
        const auto lib = class_library::from_json(nlohmann::json::parse(R"({"format": "sems.classes", "version": 1,
            "name": "qa", "classes": [
              {"name": "quad", "range_m": [10, 100], "speed_mps": [0, 5],
               "micro_motion": {"model": "rotor", "rotors": 4, "blades": 2, "blade_length_m": [0.1, 0.15],
                                "rotation_hz": [80, 120], "body_power": 0.5}},
              {"name": "car", "range_m": [10, 100], "speed_mps": [5, 15],
               "micro_motion": {"model": "wheels", "wheels": 4, "wheel_radius_m": 0.3, "rim_points": 8, "body_power": 0.8}},
              {"name": "adult", "range_m": [10, 100], "speed_mps": [0.5, 2],
               "micro_motion": {"model": "walker", "height_m": [1.6, 1.9]}},
              {"name": "pts", "range_m": [10, 100], "speed_mps": [0, 2],
               "micro_motion": {"model": "scatterers", "scatterers": [
                   {"power": 1, "harmonics": [{"amplitude_m": [0.1, 0.3], "rate_hz": [1, 2]}]},
                   {"power": 3}]}}]})"), "qa library");
        const frame_settings fs;
        for (int c = 0; c < lib->size(); ++c) {
            random_spec r;
            r.classes = { static_cast<target_class>(c) };
            const auto s = scene::random(r, std::nullopt, fading_kind::rayleigh, lib);
            const auto h = grids(fs, s, 3000, 11);
            double p = 0.0;
            for (auto x : h)
                p += std::norm(x);
            p /= h.size();
            CPPUNIT_ASSERT_MESSAGE(lib->at(c).name + ": mean power " + std::to_string(p), std::fabs(p - 1.0) < 0.1);
        }
    }

    void moving_scene_follows_its_track()
    {
        const auto s = scene::parse(motion_scene_head + R"("track": {"range_m": [10, 30], "at_bound": "reflect"},
            "targets": [{"class": "pedestrian", "range_m": 20, "velocity_mps": 1.5}]})");
        const frame_settings fs; // 32 ms frames
        channel_model cm(fs, s, 1);
        const double frame_s = fs.n_symbols * fs.symbol_interval_s;
        auto r0 = cm.draw(0), r100 = cm.draw(100), r300 = cm.draw(300);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(20.0, r0.truth.range_m, 1e-12);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(20.0 - 1.5 * 100 * frame_s, r100.truth.range_m, 1e-9); // 15.2 m, approaching
        // 300 frames = 9.6 s = 14.4 m: 10 m to the near end, then 4.4 m back out, receding.
        CPPUNIT_ASSERT_DOUBLES_EQUAL(14.4, r300.truth.range_m, 1e-9);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(-1.5, r300.truth.velocity_mps, 0.0);
        const auto restart = scene::parse(motion_scene_head + R"("track": {"range_m": [10, 30]},
            "targets": [{"class": "pedestrian", "range_m": 20, "velocity_mps": 1.5}]})");
        channel_model cr(fs, restart, 1);
        CPPUNIT_ASSERT_DOUBLES_EQUAL(20.0 - std::fmod(1.5 * 300 * frame_s, 10.0), cr.draw(300).truth.range_m, 1e-9);
        // A target's micro-motion phases continue across frames: frame 1 of a long stream equals
        // rows N..2N-1 of the stream, not a restart.
        const auto w = scene::parse(motion_scene_head + R"("targets": [{"class": "drone", "range_m": 30, "velocity_mps": 3,
            "micro_motion": {"model": "rotor", "rotors": 1, "blades": 2, "blade_length_m": 0.1, "rotation_hz": 7.3}}]})");
        const auto both = grids(fs, w, 2);
        channel_model single(fs, w, 1);
        std::vector<gr_complex> second(fs.grid_size());
        single.generate(1, second.data(), 1);
        for (int i = 0; i < fs.grid_size(); ++i)
            CPPUNIT_ASSERT(second[i] == both[fs.grid_size() + i]);
    }

    // models/classes: paper.json is the built-in library; kinematic.json loads, fits the paper's
    // frame, and every class draws finite frames of unit mean power.
    void shipped_class_libraries()
    {
        const char* src = std::getenv("SEMS_SOURCE_DIR");
        CPPUNIT_ASSERT_MESSAGE("SEMS_SOURCE_DIR must point at the source tree", src != nullptr);
        const auto paper = class_library::load(std::string(src) + "/models/classes/paper.json");
        CPPUNIT_ASSERT_EQUAL(std::string(""), paper->difference(*class_library::paper()));
        const auto kin = class_library::find("kinematic");
        CPPUNIT_ASSERT(kin->size() >= 6);
        const std::vector<std::string> models = { "walker", "walker", "rotor", "rotor", "wheels", "scatterers" };
        for (int c = 0; c < 6; ++c)
            CPPUNIT_ASSERT_EQUAL(models[c], kin->at(c).motion_model());
        const frame_settings fs;
        for (auto heading : { heading_kind::approaching, heading_kind::any }) {
            random_spec r;
            r.classes.clear();
            r.heading = heading;
            const auto s = scene::random(r, std::nullopt, fading_kind::rayleigh, kin);
            channel_model cm(fs, s, 5);
            std::vector<double> power(kin->size(), 0.0), count(kin->size(), 0.0);
            std::vector<gr_complex> h(fs.grid_size());
            for (uint64_t f = 0; f < 6000; ++f) {
                const auto r = cm.draw(f);
                cm.factors(r, f * fs.n_symbols).fill(h.data());
                double p = 0.0;
                for (auto x : h) {
                    CPPUNIT_ASSERT(std::isfinite(x.real()) && std::isfinite(x.imag()));
                    p += std::norm(x);
                }
                power[r.truth.class_id] += p / h.size();
                count[r.truth.class_id] += 1;
            }
            for (int c = 0; c < kin->size(); ++c) {
                CPPUNIT_ASSERT(count[c] > 700);
                const double mean = power[c] / count[c];
                CPPUNIT_ASSERT_MESSAGE(kin->at(c).name + ": mean power " + std::to_string(mean), std::fabs(mean - 1.0) < 0.15);
            }
        }
    }

    void bad_class_libraries_are_refused()
    {
        auto lib = [](const std::string& classes) {
            return [classes] {
                class_library::from_json(nlohmann::json::parse(R"({"format": "sems.classes", "version": 1, "name": "x",
                    "classes": )" + classes + "}"), "lib.json");
            };
        };
        assert_error(lib(R"([{"name": "a", "range_m": [10, 5], "speed_mps": 1}])"), "lib.json: classes[0].range_m", "empty interval");
        assert_error(lib(R"([{"name": "a", "range_m": [0, 5], "speed_mps": [-1, 1]}])"), "classes[0] (\"a\").speed_mps", ">= 0");
        assert_error(lib(R"([{"name": "a", "range_m": [0, 5], "speed_mps": 1, "colour": "red"}])"), "classes[0].colour", "unknown key");
        assert_error(lib(R"([{"name": "a", "range_m": [0, 5], "speed_mps": 1}, {"name": "a", "range_m": [0, 5], "speed_mps": 1}])"),
                     "classes[1].name", "defined twice");
        assert_error(lib(R"([{"name": "a", "range_m": [0, 5], "speed_mps": 1,
            "micro_motion": {"model": "rotor", "blade_length_m": [0.1, -0.2], "rotation_hz": 50}}])"),
                     "blade_length_m", "empty interval");
        assert_error(lib(R"([{"name": "a", "range_m": [0, 5], "speed_mps": 1,
            "micro_motion": {"model": "rotor", "blade_length_m": [-0.1, 0.2], "rotation_hz": 50}}])"),
                     "classes[0] (\"a\").micro_motion.blade_length_m", "> 0");
        assert_error(lib(R"([{"name": "a", "range_m": [0, 5], "speed_mps": 1,
            "micro_motion": {"model": "rotor", "blade_length_m": 0.1, "rotation_hz": 50, "rotors": [2, 40]}}])"),
                     "micro_motion.rotors[1]", "16");
        assert_error(lib(R"([{"name": "a", "range_m": [0, 5], "speed_mps": [1, 3.5],
            "micro_motion": {"model": "walker", "height_m": [1.0, 1.2]}}])"), "classes[0] (\"a\").speed_mps", "valid range");
        assert_error(lib(R"([])"), "lib.json: classes", "1 to");
        assert_error([] { class_library::find("no_such_library"); }, "no_such_library", "SEMS_CLASSES_PATH");
        // A random scene whose class does not fit the frame: refused naming the class and the limit.
        const auto fast = class_library::from_json(nlohmann::json::parse(R"({"format": "sems.classes", "version": 1,
            "name": "fast", "classes": [{"name": "jet", "range_m": [0, 100], "speed_mps": [100, 200]},
                                        {"name": "far", "range_m": [0, 400], "speed_mps": 1}]})"), "fast.json");
        random_spec r;
        r.classes = { static_cast<target_class>(0) };
        assert_error([&] { channel_model(frame_settings{}, scene::random(r, std::nullopt, fading_kind::rayleigh, fast), 1); },
                     "class jet", "Doppler");
        r.classes = { static_cast<target_class>(1) };
        assert_error([&] { channel_model(frame_settings{}, scene::random(r, std::nullopt, fading_kind::rayleigh, fast), 1); },
                     "class far", "unambiguous range");
    }

    // A scene file naming its library by a relative path reads it from the scene's folder,
    // whatever the working directory; a missing file is named as given (no ".json" added).
    void scene_reads_its_library_beside_it()
    {
        char tmpl[] = "/tmp/sems_qa_sceneXXXXXX";
        CPPUNIT_ASSERT(::mkdtemp(tmpl) != nullptr);
        const std::string dir = tmpl;
        std::ofstream(dir + "/street.json") << R"({"format": "sems.classes", "version": 1, "name": "street",
            "classes": [{"name": "slow_walker", "range_m": [5, 50], "speed_mps": [0.5, 1.5]},
                        {"name": "fast_car", "range_m": [5, 150], "speed_mps": [10, 20]}]})";
        std::ofstream(dir + "/scene.json") << R"({"format": "sems.scene", "version": 1, "classes": "street.json",
            "random": {"classes": ["fast_car"]}})";
        const auto sc = scene::load(dir + "/scene.json");
        CPPUNIT_ASSERT_EQUAL(std::string("street"), sc.library().name());
        std::ofstream(dir + "/lost.json") << R"({"format": "sems.scene", "version": 1, "classes": "nothere.json"})";
        assert_error([&] { scene::load(dir + "/lost.json"); }, "\"nothere.json\": not built in", "searched nothere.json;");
        for (const char* f : { "street.json", "scene.json", "lost.json" })
            std::remove((dir + "/" + f).c_str());
        ::rmdir(dir.c_str());
    }

    void bad_micro_motion_is_refused()
    {
        auto scene_with = [](const std::string& motion) {
            return [motion] {
                scene::parse(R"({"format": "sems.scene", "version": 1, "targets": [{"class": "drone",
                    "range_m": 60, "velocity_mps": 3, "micro_motion": )" + motion + "}]}", "bad.json");
            };
        };
        assert_error(scene_with(R"({"model": "propeller"})"), "bad.json", "unknown micro-motion model");
        assert_error(scene_with(R"({"model": "rotor", "blade_length_m": 0.1, "rotation_hz": 50, "blade": 3})"),
                     "targets[0].micro_motion.blade", "unknown key");
        assert_error(scene_with(R"({"model": "rotor", "blade_length_m": -0.1, "rotation_hz": 50})"),
                     "micro_motion.blade_length_m", "> 0");
        assert_error(scene_with(R"({"model": "rotor", "blade_length_m": 0.1, "rotation_hz": 50, "rotors": 17})"),
                     "micro_motion.rotors", "16");
        assert_error(scene_with(R"({"model": "rotor", "blade_length_m": 0.1, "rotation_hz": [50, 60], "rotors": 3})"),
                     "micro_motion.rotation_hz", "3");
        assert_error(scene_with(R"({"model": "rotor", "blade_length_m": [0.1, 0.2], "rotation_hz": 50})"),
                     "micro_motion.blade_length_m", "class library only");
        assert_error(scene_with(R"({"model": "rotor", "blade_length_m": 0.1, "rotation_hz": 50, "body_power": 1.5})"),
                     "body_power", "[0, 1]");
        assert_error(scene_with(R"({"model": "wheels", "wheel_radius_m": 0.3, "rim_points": 0, "spokes": 0})"),
                     "micro_motion", "no rim_points");
        assert_error(scene_with(R"({"model": "scatterers", "scatterers": []})"), "micro_motion.scatterers", "1 to 256");
        assert_error(scene_with(R"({"model": "scatterers", "scatterers": [{"power": -1}]})"),
                     "scatterers[0].power", ">= 0");
        assert_error(scene_with(R"({"model": "scatterers", "scatterers": [{"power": 1e308}, {"power": 1e308}]})"),
                     "scatterers[0].power", "at most 1e30");
        // Target and path powers whose sum would overflow (found by fuzz_channel).
        assert_error([] {
            scene::parse(R"({"format": "sems.scene", "version": 1, "targets": [
                {"class": "car", "range_m": 30, "velocity_mps": 1, "power": 1e308},
                {"class": "car", "range_m": 40, "velocity_mps": 1, "power": 1e308}]})", "p.json");
        }, "p.json: targets[0].power", "at most 1e30");
        assert_error([] {
            scene::parse(R"({"format": "sems.scene", "version": 1, "targets": [{"class": "car", "range_m": 30,
                "velocity_mps": 1, "paths": [{"power": 1}, {"excess_range_m": 3, "power": 1e31}]}]})", "p.json");
        }, "targets[0].paths[1].power", "at most 1e30");
        assert_error(scene_with(R"({"model": "scatterers", "scatterers": [{"power": 1, "harmonics": [{"amplitude_m": 0.1}]}]})"),
                     "harmonics[0].rate_hz", "missing");
        assert_error(scene_with(R"({"model": "sinusoid", "rate_hz": 10, "amplitude_m": 0.1}, "micro_doppler": {"rate_hz": 1, "amplitude_m": 0.1})"),
                     "bad.json", "not both");
    }

    // A walker through the frame model (the expansion's order chosen per frame from the
    // scatterers' own amplitudes and reaches) against the direct sum Σ_s a_s e^{-jκ_m r_s} of
    // the same scatterers, on the paper's frame and on a 77 GHz, 1 GHz frame (sub-bands): per
    // symbol equal up to the one phasor the target's Doppler and gain give, to float rounding.
    void walker_frame_equals_direct_sum()
    {
        const frame_settings wide = wide_band_frame();
        for (const frame_settings& fs : { frame_settings{}, wide }) {
            const auto s = scene::parse(motion_scene_head + R"("targets": [{"class": "pedestrian", "range_m": 12, "speed_mps": 1.6,
                "heading_rad": 0.4, "micro_motion": {"model": "walker", "height_m": 1.75, "phase_rad": 0.3}}]})");
            channel_model cm(fs, s, 1);
            const uint64_t frame = 37;
            const auto r = cm.draw(frame);
            std::vector<gr_complex> h(fs.grid_size());
            cm.factors(r, frame * fs.n_symbols).fill(h.data());
            const detail::body_model bm(r.bodies.at(0), fs);
            detail::body_snapshot snap;
            double worst = 0.0;
            for (int n = 0; n < fs.n_symbols; ++n) {
                bm.snapshot(double(frame * fs.n_symbols + n) * fs.symbol_interval_s, snap);
                const gr_complex* got = h.data() + size_t(n) * fs.n_subcarriers;
                std::vector<cd> want(fs.n_subcarriers);
                cd num = 0.0; // the least-squares phasor c of got ≈ c·want
                double den = 0.0;
                for (int m = 0; m < fs.n_subcarriers; ++m) {
                    const double kappa =
                        4 * M_PI * (fs.carrier_hz + m * fs.subcarrier_spacing_hz()) / speed_of_light_mps;
                    for (size_t i = 0; i < snap.point_r.size(); ++i)
                        want[m] += snap.point_a[i] * std::exp(cd(0, -kappa * snap.point_r[i]));
                    want[m] *= std::exp(cd(0, -2 * M_PI * m * fs.subcarrier_spacing_hz() * r.truth.delay_s));
                    num += cd(got[m]) * std::conj(want[m]);
                    den += std::norm(want[m]);
                }
                const cd c = num / den; // the symbol's Doppler phasor times the gain (1 here)
                CPPUNIT_ASSERT_DOUBLES_EQUAL(1.0, std::abs(c), 1e-5);
                for (int m = 0; m < fs.n_subcarriers; ++m)
                    worst = std::max(worst, std::abs(cd(got[m]) - c * want[m]));
            }
            CPPUNIT_ASSERT_MESSAGE("worst error " + std::to_string(worst), worst < 2e-6);
        }
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_micro_motion);
