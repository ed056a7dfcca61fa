// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: tracks of a random scene — bookkeeping (ids, frames in a track, lengths, the end at
 * the range bounds), the body's motion against its closed form, phases that continue across
 * frames, gains that follow their stated coherence, any track drawn alone from (seed, index),
 * and bad track settings refused by name. */
#include "qa/qa_assert.h"
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <cppunit/TestAssert.h>
#include <cppunit/extensions/HelperMacros.h>
#include <cmath>
#include <complex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace gr::sems;
using gr::sems::qa::assert_error;
using cd = std::complex<double>;

namespace {

const std::string track_scene_head = R"({"format": "sems.scene", "version": 1, )";

scene tracked(const std::string& tracks, const std::string& rest = "", const std::string& fading = "rayleigh")
{
    return scene::parse(track_scene_head + R"("fading": ")" + fading + R"(", "random": {)" + rest + R"("tracks": )" + tracks +
                        "}}");
}

std::vector<gr_complex> grid(const channel_model& cm, const frame_realization& r, uint64_t first_symbol)
{
    std::vector<gr_complex> h(static_cast<size_t>(cm.settings().grid_size()));
    cm.factors(r, first_symbol).fill(h.data());
    return h;
}

} // namespace

class qa_tracks : public CppUnit::TestFixture
{
    CPPUNIT_TEST_SUITE(qa_tracks);
    CPPUNIT_TEST(ids_and_frames_in_track);
    CPPUNIT_TEST(a_track_keeps_its_target_and_moves_it);
    CPPUNIT_TEST(tracks_end_at_their_range_bounds);
    CPPUNIT_TEST(planned_lengths_cover_their_interval);
    CPPUNIT_TEST(any_track_is_drawn_alone);
    CPPUNIT_TEST(sinusoid_phase_continues_across_frames);
    CPPUNIT_TEST(walker_track_equals_a_moving_fixed_scene);
    CPPUNIT_TEST(gains_follow_their_coherence);
    CPPUNIT_TEST(per_frame_and_fixed_scenes_name_their_tracks);
    CPPUNIT_TEST(round_trip);
    CPPUNIT_TEST(bad_tracks_are_refused);
    CPPUNIT_TEST_SUITE_END();

public:
    // Frame after frame: frame_in_track counts 0, 1, ... up to the track's length, then the
    // next track (id + 1) starts at 0; the frame index only names the frame.
    void ids_and_frames_in_track()
    {
        const auto s = tracked(R"({"frames": 8})", R"("classes": ["pedestrian", "drone"], )");
        channel_model cm(frame_settings{}, s, 3);
        channel_model lengths(frame_settings{}, s, 3);
        uint64_t track = 0, in_track = 0;
        int length = lengths.begin_track(0);
        for (int f = 0; f < 200; ++f) {
            const auto r = cm.draw(1000 + 7 * f); // any frame index: it is only the truth's name
            if (in_track == static_cast<uint64_t>(length)) {
                ++track;
                in_track = 0;
                length = lengths.begin_track(track);
            }
            CPPUNIT_ASSERT(length >= 1 && length <= 8);
            CPPUNIT_ASSERT_EQUAL(track, r.truth.track_id);
            CPPUNIT_ASSERT_EQUAL(in_track, r.truth.frame_in_track);
            CPPUNIT_ASSERT_EQUAL(uint64_t(1000 + 7 * f), r.truth.frame);
            CPPUNIT_ASSERT(r.clock_symbol.has_value());
            CPPUNIT_ASSERT_EQUAL(in_track * 32, *r.clock_symbol);
            ++in_track;
        }
        CPPUNIT_ASSERT(track >= 24); // 200 frames of tracks of at most 8
        // A reseed starts again at track 0.
        cm.reseed(3);
        const auto r = cm.draw(0);
        CPPUNIT_ASSERT_EQUAL(uint64_t(0), r.truth.track_id);
        CPPUNIT_ASSERT_EQUAL(uint64_t(0), r.truth.frame_in_track);
    }

    // Within a track the class, speed, heading, micro-motion and extra paths stay; the range
    // follows R_f = R_0 − v·f·N·T; the paths' delays follow the range.
    void a_track_keeps_its_target_and_moves_it()
    {
        const auto lib = class_library::find("kinematic");
        const auto s = tracked(R"({"frames": 40})", R"("heading": "any", "paths_per_target": 2, )")
                           .with_library(lib);
        const frame_settings fs;
        const double frame_s = fs.n_symbols * fs.symbol_interval_s;
        channel_model cm(fs, s, 11);
        int checked = 0;
        for (uint64_t k = 0; k < 30; ++k) {
            const int len = cm.begin_track(k);
            const auto first = cm.draw(0);
            for (int f = 1; f < len; ++f) {
                const auto r = cm.draw(f);
                CPPUNIT_ASSERT_EQUAL(first.truth.class_id, r.truth.class_id);
                CPPUNIT_ASSERT_EQUAL(first.truth.velocity_mps, r.truth.velocity_mps);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(first.truth.range_m - first.truth.velocity_mps * f * frame_s,
                                             r.truth.range_m, 1e-9);
                CPPUNIT_ASSERT_EQUAL(first.paths.size(), r.paths.size());
                // the extra path keeps its excess range: the same delay offset from the direct path
                CPPUNIT_ASSERT_DOUBLES_EQUAL(first.paths[1].delay_s - first.paths[0].delay_s,
                                             r.paths[1].delay_s - r.paths[0].delay_s, 1e-15);
                CPPUNIT_ASSERT_DOUBLES_EQUAL(fs.delay_from_range(r.truth.range_m), r.paths[0].delay_s, 1e-18);
                CPPUNIT_ASSERT_EQUAL(first.bodies.size(), r.bodies.size());
                for (size_t b = 0; b < r.bodies.size(); ++b) {
                    CPPUNIT_ASSERT(first.bodies[b].motion == r.bodies[b].motion);
                    CPPUNIT_ASSERT_EQUAL(first.bodies[b].speed_mps, r.bodies[b].speed_mps);
                    CPPUNIT_ASSERT_EQUAL(first.bodies[b].heading_rad, r.bodies[b].heading_rad);
                }
                ++checked;
            }
        }
        CPPUNIT_ASSERT(checked > 500);
    }

    // A track ends at its last frame inside its class's range interval: every frame lies
    // inside, and a track cut short would have left it on the next frame.
    void tracks_end_at_their_range_bounds()
    {
        // Cars at 10–20 m/s over 0–200 m: a pass lasts 10–20 s, 300–600 frames; tracks of 10 000.
        const auto s = tracked(R"({"frames": 10000})", R"("classes": ["car"], "heading": "any", )");
        const frame_settings fs;
        const double frame_s = fs.n_symbols * fs.symbol_interval_s;
        const auto& spec = s.library().at(static_cast<int>(target_class::car));
        channel_model cm(fs, s, 5);
        int cut = 0;
        for (uint64_t k = 0; k < 40; ++k) {
            const int len = cm.begin_track(k);
            auto r = cm.draw(0);
            const double r0 = r.truth.range_m, v = r.truth.velocity_mps;
            for (int f = 1; f < len; ++f) {
                r = cm.draw(f);
                CPPUNIT_ASSERT(r.truth.range_m >= spec.range_min_m && r.truth.range_m <= spec.range_max_m);
            }
            if (len < 10000) {
                ++cut;
                const double next = r0 - v * (len * frame_s);
                CPPUNIT_ASSERT_MESSAGE("track " + std::to_string(k) + " ended inside its interval",
                                       next < spec.range_min_m || next > spec.range_max_m);
            }
            // The next draw starts the next track.
            const auto after = cm.draw(len);
            CPPUNIT_ASSERT_EQUAL(k + 1, after.truth.track_id);
            CPPUNIT_ASSERT_EQUAL(uint64_t(0), after.truth.frame_in_track);
        }
        CPPUNIT_ASSERT(cut >= 35); // a 320 s track outlasts a 200 m pass unless a car is nearly crossing
    }

    // K ~ U{min..max}: pedestrians (≤ 2 m/s) over 6 frames move ≤ 0.4 m, so lengths below 3 are
    // (almost) never a cut; every length of [3, 6] is drawn, none outside.
    void planned_lengths_cover_their_interval()
    {
        const auto s = tracked(R"({"frames": [3, 6]})", R"("classes": ["pedestrian"], )");
        channel_model cm(frame_settings{}, s, 2);
        std::set<int> seen;
        int short_ones = 0;
        for (uint64_t k = 0; k < 400; ++k) {
            const int len = cm.begin_track(k);
            CPPUNIT_ASSERT(len >= 1 && len <= 6);
            short_ones += len < 3;
            seen.insert(len);
        }
        CPPUNIT_ASSERT(seen.count(3) && seen.count(4) && seen.count(5) && seen.count(6));
        CPPUNIT_ASSERT(short_ones <= 4); // cut at a bound: ≈ 0.4 m of 200 m, 0.2 %
    }

    // Track k's frames are a function of (seed, k): begun alone, they equal the same track
    // reached by streaming, channel and truth, bit for bit.
    void any_track_is_drawn_alone()
    {
        const auto s = tracked(R"({"frames": [4, 9], "gains": "gauss_markov", "coherence_time_s": 0.05})",
                               R"("paths_per_target": 2, "heading": "any", )")
                           .with_library(class_library::find("kinematic"));
        const frame_settings fs;
        channel_model stream(fs, s, 21);
        std::vector<frame_realization> streamed;
        while (streamed.empty() || streamed.back().truth.track_id <= 6)
            streamed.push_back(stream.draw(streamed.size()));
        channel_model alone(fs, s, 21);
        const int len = alone.begin_track(5);
        int matched = 0;
        for (const auto& want : streamed) {
            if (want.truth.track_id != 5)
                continue;
            const auto got = alone.draw(12345);
            CPPUNIT_ASSERT_EQUAL(want.truth.frame_in_track, got.truth.frame_in_track);
            CPPUNIT_ASSERT_EQUAL(want.truth.range_m, got.truth.range_m);
            CPPUNIT_ASSERT_EQUAL(want.truth.class_id, got.truth.class_id);
            // the track's own clock: any absolute first symbol gives the same channel
            CPPUNIT_ASSERT(grid(stream, want, 0) == grid(alone, got, 99 * 32));
            ++matched;
        }
        CPPUNIT_ASSERT_EQUAL(len, matched);
        // Another seed gives other tracks.
        channel_model other(fs, s, 22);
        other.begin_track(5);
        channel_model again(fs, s, 21);
        again.begin_track(5);
        CPPUNIT_ASSERT(other.draw(0).truth.range_m != again.draw(0).truth.range_m);
    }

    // The paper's drone over a track: H[f·N + n, m] equals the closed form with continuous slow
    // time t = (f·N + n)·T from the track's start and the frame's range R_f = R_0 − v·f·N·T:
    //   α · exp(−j2π m Δf 2R_f/c) · exp(j2π ν t) · exp(j (4π/λ) A sin(ω t + φ)).
    void sinusoid_phase_continues_across_frames()
    {
        const auto s = tracked(R"({"frames": 12})", R"("classes": ["drone"], )", "none");
        const frame_settings fs;
        const double T = fs.symbol_interval_s, frame_s = fs.n_symbols * T, lambda = fs.wavelength_m();
        channel_model cm(fs, s, 4);
        const int len = cm.begin_track(0);
        CPPUNIT_ASSERT_EQUAL(12, len);
        double worst = 0.0;
        frame_realization first;
        for (int f = 0; f < len; ++f) {
            const auto r = cm.draw(f);
            if (f == 0)
                first = r;
            const auto& p = r.paths[0];
            CPPUNIT_ASSERT_DOUBLES_EQUAL(first.truth.range_m - first.truth.velocity_mps * f * frame_s, r.truth.range_m,
                                         1e-9);
            CPPUNIT_ASSERT(p.md_rate_hz > 0.0);
            const auto h = grid(cm, r, 777); // the frame's own clock, whatever the caller's index
            for (int n = 0; n < fs.n_symbols; ++n) {
                const double t = (f * fs.n_symbols + n) * T;
                const cd slow = p.gain * std::exp(cd(0, 2 * M_PI * p.doppler_hz * t)) *
                                std::exp(cd(0, 4 * M_PI / lambda * p.md_amplitude_m *
                                                   std::sin(2 * M_PI * p.md_rate_hz * t + p.md_phase_rad)));
                for (int m = 0; m < fs.n_subcarriers; m += 9) {
                    const cd want = slow * std::exp(cd(0, -2 * M_PI * m * fs.subcarrier_spacing_hz() *
                                                              fs.delay_from_range(r.truth.range_m)));
                    worst = std::max(worst, std::abs(cd(h[n * fs.n_subcarriers + m]) - want));
                }
            }
        }
        CPPUNIT_ASSERT_MESSAGE("worst error " + std::to_string(worst), worst < 1e-5);
    }

    // A walker followed over a track is the same walker as a fixed scene's moving target
    // started at the track's first frame: gait phases and Doppler continue across frames.
    void walker_track_equals_a_moving_fixed_scene()
    {
        const auto lib = class_library::find("kinematic");
        const auto s = scene::parse(track_scene_head + R"("classes": "kinematic", "fading": "none", "random": {
            "classes": ["adult"], "heading": "any", "tracks": {"frames": 20}}})");
        const frame_settings fs;
        channel_model cm(fs, s, 8);
        const int len = cm.begin_track(3);
        const auto r0 = cm.draw(0);
        CPPUNIT_ASSERT_EQUAL(1, static_cast<int>(r0.bodies.size()));
        target_spec t;
        t.cls = static_cast<target_class>(r0.truth.class_id);
        t.range_m = r0.truth.range_m;
        t.speed_mps = r0.bodies[0].speed_mps;
        t.heading_rad = r0.bodies[0].heading_rad;
        t.velocity_mps = r0.truth.velocity_mps;
        t.motion = r0.bodies[0].motion;
        const auto& cls = lib->at(r0.truth.class_id);
        track_spec along;
        along.range_min_m = cls.range_min_m;
        along.range_max_m = cls.range_max_m;
        const auto fixed = scene::fixed({ t }, std::nullopt, 0, fading_kind::none, lib).with_track(along);
        channel_model ref(fs, fixed, 0);
        double worst = 0.0, peak = 0.0;
        for (int f = 0; f < len; ++f) {
            const auto a = f == 0 ? r0 : cm.draw(f);
            const auto b = ref.draw(f);
            const auto ha = grid(cm, a, 0), hb = grid(ref, b, uint64_t(f) * fs.n_symbols);
            for (size_t i = 0; i < ha.size(); ++i) {
                worst = std::max(worst, double(std::abs(ha[i] - hb[i])));
                peak = std::max(peak, double(std::abs(hb[i])));
            }
        }
        CPPUNIT_ASSERT(peak > 0.1);
        CPPUNIT_ASSERT_MESSAGE("worst difference " + std::to_string(worst), worst < 1e-4 * peak);
    }

    // Gains: "track" keeps the first frame's; "frame" draws independent ones; "gauss_markov" is
    // stationary CN(0, p) with E[α_f α*_{f+k}] = p·ρ^k, ρ = exp(−N·T/τ_c) (within 4 SE).
    void gains_follow_their_coherence()
    {
        const frame_settings fs;
        const double frame_s = fs.n_symbols * fs.symbol_interval_s;
        auto correlations = [&](const std::string& tracks, int lag_max, int tracks_n) {
            channel_model cm(fs, tracked(tracks, R"("classes": ["pedestrian"], )"), 17);
            std::vector<cd> sum(lag_max + 1, 0.0);
            std::vector<double> sq(lag_max + 1, 0.0);
            std::vector<int> count(lag_max + 1, 0);
            for (int k = 0; k < tracks_n; ++k) {
                const int len = cm.begin_track(k);
                std::vector<cd> g;
                for (int f = 0; f < len; ++f)
                    g.push_back(cm.draw(f).paths[0].gain);
                for (int lag = 0; lag <= lag_max; ++lag)
                    for (int f = 0; f + lag < len; ++f) {
                        const cd x = g[f] * std::conj(g[f + lag]);
                        sum[lag] += x;
                        sq[lag] += std::norm(x);
                        ++count[lag];
                    }
            }
            std::vector<std::pair<double, double>> out; // (mean of Re, its SE) per lag
            for (int lag = 0; lag <= lag_max; ++lag) {
                const double mean = sum[lag].real() / count[lag];
                const double se = std::sqrt(sq[lag] / count[lag] / count[lag]);
                out.emplace_back(mean, se);
            }
            return out;
        };
        // Gauss–Markov with τ_c = 0.1 s: ρ = exp(−0.032/0.1) = 0.726 per frame.
        const double rho = std::exp(-frame_s / 0.1);
        const auto gm = correlations(R"({"frames": 16, "gains": "gauss_markov", "coherence_time_s": 0.1})", 4, 3000);
        for (int lag = 0; lag <= 4; ++lag) {
            // frames of one track are correlated: widen the SE by √(frames per track)
            const double se = gm[lag].second * 4.0;
            CPPUNIT_ASSERT_MESSAGE("lag " + std::to_string(lag) + ": " + std::to_string(gm[lag].first),
                                   std::fabs(gm[lag].first - std::pow(rho, lag)) < 4 * se);
        }
        const auto indep = correlations(R"({"frames": 16, "gains": "frame"})", 2, 2000);
        CPPUNIT_ASSERT(std::fabs(indep[0].first - 1.0) < 4 * indep[0].second * 4.0);
        CPPUNIT_ASSERT(std::fabs(indep[1].first) < 4 * indep[1].second * 4.0);
        CPPUNIT_ASSERT(std::fabs(indep[2].first) < 4 * indep[2].second * 4.0);
        // "track": the very same gain on every frame of a track.
        channel_model cm(fs, tracked(R"({"frames": 16, "gains": "track"})", R"("paths_per_target": 3, )"), 9);
        for (int k = 0; k < 20; ++k) {
            const int len = cm.begin_track(k);
            const auto first = cm.draw(0);
            for (int f = 1; f < len; ++f) {
                const auto r = cm.draw(f);
                for (size_t l = 0; l < r.paths.size(); ++l)
                    CPPUNIT_ASSERT(r.paths[l].gain == first.paths[l].gain);
            }
        }
    }

    // Scenes without tracks: a per-frame random scene's every frame is its own track (id = the
    // frame index); a fixed scene is one track (id 0) counted by the frame index; neither has
    // a clock of its own.
    void per_frame_and_fixed_scenes_name_their_tracks()
    {
        channel_model random(frame_settings{}, scene::random(random_spec{}), 1);
        for (uint64_t f : { 0, 5, 6, 1000 }) {
            const auto r = random.draw(f);
            CPPUNIT_ASSERT_EQUAL(f, r.truth.track_id);
            CPPUNIT_ASSERT_EQUAL(uint64_t(0), r.truth.frame_in_track);
            CPPUNIT_ASSERT(!r.clock_symbol.has_value());
        }
        target_spec t;
        channel_model fixed(frame_settings{}, scene::fixed({ t }), 1);
        const auto r = fixed.draw(42);
        CPPUNIT_ASSERT_EQUAL(uint64_t(0), r.truth.track_id);
        CPPUNIT_ASSERT_EQUAL(uint64_t(42), r.truth.frame_in_track);
        CPPUNIT_ASSERT(!r.clock_symbol.has_value());
        CPPUNIT_ASSERT_THROW(random.begin_track(0), std::logic_error);
        CPPUNIT_ASSERT_THROW(fixed.begin_track(0), std::logic_error);
    }

    void round_trip()
    {
        for (const std::string tracks : { R"({"frames": 64})", R"({"frames": [16, 64], "gains": "track"})",
                                          R"({"frames": 31, "gains": "gauss_markov", "coherence_time_s": 0.25})" }) {
            const auto s = tracked(tracks);
            const auto back = scene::parse(s.to_json_string());
            CPPUNIT_ASSERT_EQUAL(s.to_json().dump(), back.to_json().dump());
            CPPUNIT_ASSERT(back.random_settings()->tracks.has_value());
        }
        const auto s = tracked(R"({"frames": [16, 64], "gains": "gauss_markov", "coherence_time_s": 0.25})");
        const auto& t = *s.random_settings()->tracks;
        CPPUNIT_ASSERT_EQUAL(16, t.frames_min);
        CPPUNIT_ASSERT_EQUAL(64, t.frames_max);
        CPPUNIT_ASSERT(t.gains == gain_coherence::gauss_markov);
        CPPUNIT_ASSERT_EQUAL(0.25, t.coherence_time_s);
        CPPUNIT_ASSERT(!scene::random(random_spec{}).to_json()["random"].contains("tracks"));
    }

    void bad_tracks_are_refused()
    {
        const std::string top = std::to_string(limits::max_track_frames);
        const std::string beyond = std::to_string(limits::max_track_frames + 1LL);
        assert_error([] { tracked(R"({"frames": 0})"); }, "random.tracks.frames", "[1, ");
        assert_error([&] { tracked(R"({"frames": )" + beyond + "}"); }, "random.tracks.frames", top);
        assert_error([] { tracked(R"({"frames": [5, 0]})"); }, "random.tracks.frames[1]");
        assert_error([] { tracked(R"({"frames": [6, 3]})"); }, "random.tracks.frames", "min 6 exceeds max 3");
        assert_error([] { tracked(R"({"frames": [1, 2, 3]})"); }, "random.tracks.frames", "2 to 2 entries");
        assert_error([] { tracked(R"({})"); }, "random.tracks.frames", "missing");
        assert_error([] { tracked(R"({"frames": 4, "gains": "swerling"})"); }, "random.tracks.gains", "gauss_markov");
        assert_error([] { tracked(R"({"frames": 4, "gains": "gauss_markov", "coherence_time_s": 0})"); },
                     "random.tracks.coherence_time_s", "> 0");
        assert_error([] { tracked(R"({"frames": 4, "gains": "gauss_markov", "coherence_time_s": -1})"); },
                     "random.tracks.coherence_time_s");
        assert_error([] { tracked(R"({"frames": 4, "coherence_time_s": 0.2})"); }, "random.tracks.coherence_time_s",
                     "\"frame\"");
        assert_error([] { tracked(R"({"frames": 4, "gains": "track"})", "", "none"); }, "random.tracks.gains",
                     "\"none\"");
        assert_error([] { tracked(R"({"frames": 4, "lenght": 3})"); }, "random.tracks.lenght", "unknown key");
        assert_error([] { tracked(R"(64)"); }, "random.tracks", "JSON object");
        // The struct's own bounds, as code would set them.
        random_spec r;
        r.tracks = track_draw_spec{};
        r.tracks->frames_min = r.tracks->frames_max = 0;
        assert_error([&] { scene::random(r); }, "random.tracks.frames", "got 0");
        r.tracks->frames_min = 1;
        r.tracks->frames_max = limits::max_track_frames + 1;
        assert_error([&] { scene::random(r); }, "random.tracks.frames", top);
        r.tracks->frames_max = 8;
        r.tracks->gains = gain_coherence::gauss_markov;
        r.tracks->coherence_time_s = std::nan("");
        assert_error([&] { scene::random(r); }, "random.tracks.coherence_time_s");
    }
};

CPPUNIT_TEST_SUITE_REGISTRATION(qa_tracks);
