// SPDX-License-Identifier: GPL-3.0-or-later
/* What the channel harnesses share: an input is 8 bytes that choose the frame, the seed and
 * the SNR, then scene JSON, read through scene::parse (so every key the scene format gains
 * is fuzzed with no change here). A scene or frame the module refuses must be refused with
 * std::invalid_argument (the harness returns); anything else it must model as promised
 * (checks below), or the harness aborts with the broken promise on stderr.
 *
 * A harness is one small file: parse with scene_input::read, then check what its subject
 * promises. A harness of another reader (e.g. a class library) copies fuzz_scene.cc or
 * fuzz_channel.cc and changes the call that reads; CMake (fuzz/CMakeLists.txt) and
 * scripts/fuzz.sh pick up every fuzz/fuzz_<name>.cc with its seeds in fuzz/corpus/<name>/. */
#ifndef INCLUDED_SEMS_FUZZ_SCENE_INPUT_H
#define INCLUDED_SEMS_FUZZ_SCENE_INPUT_H

#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <vector>

namespace sems_fuzz {

using gr::sems::channel_path;
using gr::sems::frame_realization;
using gr::sems::frame_settings;
using gr::sems::scene;

//! Prints the broken promise and stops (libFuzzer keeps the input as a crash).
[[noreturn]] inline void fail(const char* fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    std::fprintf(stderr, "sems fuzz: ");
    std::vfprintf(stderr, fmt, ap);
    std::fprintf(stderr, "\n");
    va_end(ap);
    std::abort();
}

//! With SEMS_FUZZ_VERBOSE set, what an input reached and measured is printed, to see what
//! seeds exercise (`SEMS_FUZZ_VERBOSE=1 build-fuzz/fuzz_channel fuzz/corpus/channel/*`).
inline bool verbose()
{
    static const bool v = std::getenv("SEMS_FUZZ_VERBOSE") != nullptr;
    return v;
}

//! Prints a measurement (verbose only).
inline void note(const char* fmt, ...)
{
    if (!verbose())
        return;
    va_list ap;
    va_start(ap, fmt);
    std::vfprintf(stderr, fmt, ap);
    std::fprintf(stderr, "\n");
    va_end(ap);
}

//! A refusal (std::invalid_argument): accepted, printed when verbose.
inline void refused(const std::exception& e) { note("refused: %s", e.what()); }

//! |a - b| within rel·max(|a|, |b|) + abs_tol.
inline bool near(double a, double b, double rel, double abs_tol = 0.0)
{
    return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)) + abs_tol;
}

//! The frame, seed and SNR of an input (its first 8 bytes), and the scene text (the rest).
struct scene_input {
    frame_settings fs;
    uint64_t seed = 0;
    double snr_db = 10.0;
    std::string json;

    //! Splits an input. The frame spans extreme but valid values: N 1..32, M 1..128, any
    //! prefix 0..M, bandwidth and carrier from 1/16 to 16 times the defaults, the symbol
    //! interval from 1/256 to 256 times (bytes 8, 8, 16 give the defaults), SNR from -300 dB
    //! to noiseless.
    static scene_input split(const uint8_t* data, size_t size)
    {
        scene_input in;
        uint8_t b[8] = { 31, 63, 16, 8, 8, 16, 0, 3 }; // the default frame at 10 dB
        const size_t k = std::min<size_t>(size, 8);
        std::copy(data, data + k, b);
        in.fs.n_symbols = 1 + b[0] % 32;
        in.fs.n_subcarriers = 1 + b[1] % 128;
        in.fs.cp_len = b[2] % (in.fs.n_subcarriers + 1);
        in.fs.bandwidth_hz = 30e6 * std::exp2((b[3] % 17 - 8) / 2.0);
        in.fs.carrier_hz = 3e9 * std::exp2((b[4] % 17 - 8) / 2.0);
        in.fs.symbol_interval_s = 1e-3 * std::exp2((b[5] % 33 - 16) / 2.0);
        in.seed = b[6];
        static const double snrs[8] = { -300.0, -30.0, 0.0, 10.0, 30.0, 100.0, 300.0,
                                        std::numeric_limits<double>::infinity() };
        in.snr_db = snrs[b[7] % 8];
        if (size > 8)
            in.json.assign(reinterpret_cast<const char*>(data) + 8, size - 8);
        return in;
    }

    //! The scene, through the module's own reader: throws std::invalid_argument when refused.
    scene read() const { return scene::parse(json, "fuzz scene"); }
};

//! All paths of all targets and clutter of a realization, as the frequency-domain model
//! and the time-domain channel receive them.
inline double gain_sum(const std::vector<channel_path>& paths)
{
    double s = 0.0;
    for (const auto& p : paths)
        s += std::abs(p.gain);
    return s;
}

/*! What channel_model promises of one drawn frame, whatever the scene (header and
 *  docs/reference/file_formats.md): the mean path powers sum to 1 (unit mean channel power per
 *  resource element); fading "none" gives |α|² = p exactly; every path lies inside the frame
 *  (delay in [0, 1/Δf), peak Doppler within ±1/(2T)); the truth describes the scene's
 *  target of interest (fixed: exactly its class, range and velocity; random: a label class
 *  of the scene, inside that class's range and speed interval) with delay 2r/c and
 *  index τB, and it is one of the paths. */
inline void check_realization(const frame_settings& fs, const scene& sc, const frame_realization& r, uint64_t frame)
{
    using gr::sems::fading_kind;
    const auto& t = r.truth;
    if (t.frame != frame)
        fail("truth.frame %llu, drawn as frame %llu", (unsigned long long)t.frame, (unsigned long long)frame);
    if (t.n_paths != static_cast<int>(r.paths.size()))
        fail("truth.n_paths %d but %zu paths", t.n_paths, r.paths.size());
    if (r.paths.empty())
        fail("a frame without paths");
    double power = 0.0;
    bool toi_path = false;
    for (size_t l = 0; l < r.paths.size(); ++l) {
        const auto& p = r.paths[l];
        if (!std::isfinite(p.mean_power) || p.mean_power < 0.0)
            fail("path %zu: mean power %g", l, p.mean_power);
        power += p.mean_power;
        if (!std::isfinite(p.gain.real()) || !std::isfinite(p.gain.imag()))
            fail("path %zu: gain not finite", l);
        if (sc.fading() == fading_kind::none &&
            !near(std::norm(p.gain), p.mean_power, 1e-12, 1e-300))
            fail("fading none, path %zu: |gain|^2 %.17g != mean power %.17g", l, std::norm(p.gain), p.mean_power);
        if (!(p.delay_s >= 0.0 && p.delay_s < fs.max_delay_s()))
            fail("path %zu: delay %g s outside [0, 1/df = %g s)", l, p.delay_s, fs.max_delay_s());
        const double peak = std::fabs(p.doppler_hz) + 2.0 / fs.wavelength_m() * 2.0 * M_PI * p.md_rate_hz * p.md_amplitude_m;
        if (!(peak <= fs.max_doppler_hz() * (1.0 + 1e-9)))
            fail("path %zu: peak Doppler %g Hz beyond 1/(2T) = %g Hz", l, peak, fs.max_doppler_hz());
        if (p.delay_s == t.delay_s && p.doppler_hz == fs.doppler_from_velocity(t.velocity_mps))
            toi_path = true;
    }
    if (const auto& b = sc.budget()) {
        // With a link budget the powers are SNRs from the radar equation: the target of
        // interest's at its range, every one inside what a frame holds.
        if (!(t.link_snr_db <= gr::sems::limits::max_link_snr_db))
            fail("link budget: the target of interest's SNR %g dB, beyond %g dB", t.link_snr_db,
                 gr::sems::limits::max_link_snr_db);
        if (!(power <= (1.0 + (sc.clutter() ? std::pow(10.0, sc.clutter()->csr_db / 10.0) : 0.0)) *
                           static_cast<double>(r.paths.size()) * std::pow(10.0, gr::sems::limits::max_link_snr_db / 10.0)))
            fail("link budget: mean path powers sum to %g", power);
        if (!sc.is_random()) {
            const auto& toi = sc.targets().at(static_cast<size_t>(sc.target_of_interest()));
            if (!near(t.link_snr_db, b->snr_db(fs, t.range_m, toi.rcs_dbsm), 1e-9))
                fail("link budget: truth SNR %.17g dB, the radar equation's %.17g dB", t.link_snr_db,
                     b->snr_db(fs, t.range_m, toi.rcs_dbsm));
        }
    } else if (!near(power, 1.0, 1e-9)) {
        fail("mean path powers sum to %.17g, not 1", power);
    }
    if (!toi_path)
        fail("no path has the truth's delay %g s and Doppler", t.delay_s);
    if (t.delay_s != fs.delay_from_range(t.range_m) || t.delay_index != fs.delay_index(t.delay_s))
        fail("truth delay %g s / index %g do not follow from range %g m", t.delay_s, t.delay_index, t.range_m);
    if (!std::isinf(t.snr_db))
        fail("a drawn frame's truth has SNR %g, not +inf (noiseless)", t.snr_db);
    if (!sc.is_random()) {
        const auto& toi = sc.targets().at(static_cast<size_t>(sc.target_of_interest()));
        const auto& track = sc.track();
        if (track && !(t.range_m >= track->range_min_m && t.range_m <= track->range_max_m))
            fail("moving scene: truth range %g m outside the track [%g, %g]", t.range_m, track->range_min_m,
                 track->range_max_m);
        if (t.class_id != static_cast<int>(toi.cls) || (!track && t.range_m != toi.range_m) ||
            std::fabs(t.velocity_mps) != std::fabs(toi.velocity_mps))
            fail("fixed scene: truth (class %d, %g m, %g m/s) is not target %d (class %d, %g m, %g m/s)", t.class_id,
                 t.range_m, t.velocity_mps, sc.target_of_interest(), static_cast<int>(toi.cls), toi.range_m,
                 toi.velocity_mps);
    } else {
        const auto labels = sc.label_classes();
        if (std::none_of(labels.begin(), labels.end(), [&](auto c) { return static_cast<int>(c) == t.class_id; }))
            fail("random scene: truth class %d is not a label class of the scene", t.class_id);
        const auto& spec = sc.library().at(t.class_id);
        if (t.class_name != spec.name)
            fail("truth class name '%s' is not class %d's '%s'", t.class_name.c_str(), t.class_id, spec.name.c_str());
        if (!(t.range_m >= spec.range_min_m && t.range_m <= spec.range_max_m))
            fail("random scene: range %g m outside class %s's [%g, %g]", t.range_m, spec.name.c_str(),
                 spec.range_min_m, spec.range_max_m);
        const bool any = sc.random_settings()->heading == gr::sems::heading_kind::any;
        const double v = t.velocity_mps;
        if (any ? !(std::fabs(v) <= spec.speed_max_mps) : !(v >= spec.speed_min_mps && v <= spec.speed_max_mps))
            fail("random scene: velocity %g m/s outside class %s's speeds [%g, %g]", v, spec.name.c_str(),
                 spec.speed_min_mps, spec.speed_max_mps);
    }
}

//! Whether a scene follows its targets over tracks (random_spec::tracks).
inline bool tracked(const scene& sc) { return sc.is_random() && sc.random_settings()->tracks.has_value(); }

//! The track bookkeeping of consecutive frames `prev` (frame f − 1; null for the first) and
//! `cur` (frame f): a tracked scene goes on with its track (the next frame of it, the same
//! class and velocity, the range moved on by v·N·T) or starts the next one at its frame 0;
//! a per-frame random scene's frame is its own track; a fixed scene is track 0.
inline void check_track_step(const frame_settings& fs, const scene& sc, const frame_realization* prev,
                             const frame_realization& cur)
{
    const auto& t = cur.truth;
    if (!tracked(sc)) {
        const uint64_t id = sc.is_random() ? t.frame : 0, in = sc.is_random() ? 0 : t.frame;
        if (t.track_id != id || t.frame_in_track != in || cur.clock_symbol)
            fail("no tracks: frame %llu is track %llu, frame %llu of it%s (want %llu, %llu, no clock)",
                 (unsigned long long)t.frame, (unsigned long long)t.track_id, (unsigned long long)t.frame_in_track,
                 cur.clock_symbol ? ", with a clock" : "", (unsigned long long)id, (unsigned long long)in);
        return;
    }
    if (!cur.clock_symbol || *cur.clock_symbol != t.frame_in_track * static_cast<uint64_t>(fs.n_symbols))
        fail("track %llu, frame %llu of it: clock symbol is not frame_in_track x N", (unsigned long long)t.track_id,
             (unsigned long long)t.frame_in_track);
    if (!prev) {
        if (t.track_id != 0 || t.frame_in_track != 0)
            fail("the first frame is track %llu, frame %llu of it", (unsigned long long)t.track_id,
                 (unsigned long long)t.frame_in_track);
        return;
    }
    const auto& p = prev->truth;
    if (t.track_id != p.track_id) {
        if (t.track_id != p.track_id + 1 || t.frame_in_track != 0)
            fail("after track %llu comes track %llu at its frame %llu", (unsigned long long)p.track_id,
                 (unsigned long long)t.track_id, (unsigned long long)t.frame_in_track);
        return;
    }
    const double nt = fs.n_symbols * fs.symbol_interval_s, step = t.velocity_mps * nt;
    // A body moving straight across the line of sight changes its radial velocity from frame to
    // frame: the range moves by the velocity somewhere between the two frames' (the mean value).
    const bool straight = sc.random_settings()->tracks->motion == gr::sems::track_motion::straight;
    const double lo = std::min(p.velocity_mps, t.velocity_mps) * nt, hi = std::max(p.velocity_mps, t.velocity_mps) * nt;
    const double slack = 1e-6 * std::fabs(hi) + 1e-9 * (1.0 + std::fabs(p.range_m));
    const bool moved = straight ? (p.range_m - t.range_m >= lo - slack && p.range_m - t.range_m <= hi + slack)
                                : (t.velocity_mps == p.velocity_mps &&
                                   near(p.range_m - t.range_m, step, 1e-6, 1e-9 * (1.0 + std::fabs(p.range_m))));
    if (t.frame_in_track != p.frame_in_track + 1 || t.class_id != p.class_id || !moved)
        fail("track %llu: frame %llu (class %d, %.17g m, %g m/s) does not follow frame %llu (class %d, %.17g m, %g m/s)",
             (unsigned long long)t.track_id, (unsigned long long)t.frame_in_track, t.class_id, t.range_m,
             t.velocity_mps, (unsigned long long)p.frame_in_track, p.class_id, p.range_m, p.velocity_mps);
}

//! Bounds on the work one input may cost (libFuzzer's -timeout is 20 s, under ASan).
constexpr double max_work = 2e7;

} // namespace sems_fuzz

#endif // INCLUDED_SEMS_FUZZ_SCENE_INPUT_H
