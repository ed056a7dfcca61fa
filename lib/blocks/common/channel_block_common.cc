// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what the two target channel blocks share (see channel_block_common.h). */
#include "blocks/common/channel_block_common.h"
#include "core/common/checks.h"
#include <gnuradio/sems/core/array/array_setting.h>
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/common/tags.h>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>

namespace gr {
namespace sems {
namespace detail {

void check_snr(const char* who, double snr_db)
{
    if (std::isnan(snr_db) || snr_db == -std::numeric_limits<double>::infinity())
        throw std::invalid_argument(std::string(who) + ": snr_db must be a number or +inf (noiseless), got " +
                                    std::to_string(snr_db));
}

scene channel_block_scene(const char* who,
                          const std::string& text,
                          const std::vector<std::string>& classes,
                          int n_targets,
                          int paths_per_target,
                          bool micro_doppler,
                          const std::string& heading,
                          int clutter_paths,
                          double clutter_csr_db,
                          const std::string& class_library_name,
                          const track_options& tracks,
                          const stream_counts& streams,
                          const array_options& arrays)
{
    for (const auto& [name, count] : { std::pair<const char*, int>{ "n_receive", streams.receive },
                                       std::pair<const char*, int>{ "n_transmit", streams.transmit } })
        if (count < 1 || count > limits::max_array_elements)
            throw std::invalid_argument(std::string(who) + ": " + name + " must be in [1, " +
                                        std::to_string(limits::max_array_elements) + "] (the array's elements), got " +
                                        std::to_string(count));
    // The block's streams against the scene's array (1 x 1 without one), both counts named.
    auto check_streams = [&](const scene& sc) {
        const int rx = sc.array() ? sc.array()->n_receive() : 1, tx = sc.array() ? sc.array()->n_transmit() : 1;
        if (rx != streams.receive || tx != streams.transmit)
            throw std::invalid_argument(std::string(who) + ": the scene's array has " + std::to_string(rx) +
                                        " receive x " + std::to_string(tx) + " transmit elements, but n_receive = " +
                                        std::to_string(streams.receive) + " and n_transmit = " +
                                        std::to_string(streams.transmit) + ": set them to the array's counts");
    };
    const track_options no_tracks;
    const bool track_defaults = tracks.frames == no_tracks.frames && tracks.gains == no_tracks.gains &&
                                tracks.coherence_time_s == no_tracks.coherence_time_s && tracks.motion == no_tracks.motion;
    // A blank array is no array, as a blank scene is a random one.
    const bool has_array = arrays.array.find_first_not_of(" \t\r\n") != std::string::npos;
    const bool array_defaults = !has_array && arrays.azimuth_min_rad == 0.0 && arrays.azimuth_max_rad == 0.0;
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos) { // a fixed scene: file or JSON text
        const random_spec defaults;
        if (!classes.empty() || n_targets != defaults.n_targets ||
            paths_per_target != defaults.paths_per_target || micro_doppler != defaults.micro_doppler ||
            heading != heading_name(defaults.heading) || clutter_paths != 0 || clutter_csr_db != 0.0 ||
            !track_defaults || !array_defaults)
            throw std::invalid_argument(std::string(who) +
                                        ": classes, n_targets, paths_per_target, micro_doppler, heading, "
                                        "track_*, clutter_*, array, azimuth_min_rad and azimuth_max_rad "
                                        "describe random scenes; a fixed scene (scene = file or JSON) carries "
                                        "its own (its array in its \"array\" key, its targets' directions), so "
                                        "leave them at their defaults");
        if (class_library_name != default_class_library)
            throw std::invalid_argument(std::string(who) + ": class_library = \"" + class_library_name +
                                        "\" describes random scenes; a fixed scene (scene = file or JSON) "
                                        "names its own library in its \"classes\" key, so leave class_library at "
                                        "\"" + default_class_library + "\"");
        scene sc = text[first] == '{' ? scene::parse(text, std::string(who) + " scene JSON") : scene::load(text);
        check_streams(sc);
        return sc;
    }

    std::shared_ptr<const class_library> lib;
    try {
        lib = class_library::find(class_library_name);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(who) + ": class_library: " + e.what());
    }
    random_spec r;
    if (!classes.empty() || lib->name() != class_library::paper()->name()) // empty: every class of the library
        r.classes.clear();
    for (const auto& name : classes) {
        try {
            r.classes.push_back(static_cast<target_class>(lib->id_of(name)));
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(std::string(who) + ": classes (library \"" + lib->name() + "\"): " + e.what());
        }
    }
    r.n_targets = n_targets;
    r.paths_per_target = paths_per_target;
    r.micro_doppler = micro_doppler;
    try {
        r.heading = heading_from_name(heading);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(who) + ": heading: " + e.what());
    }
    if (tracks.frames < 0 || tracks.frames > limits::max_track_frames)
        throw std::invalid_argument(std::string(who) + ": track_frames must be in [0, " +
                                    std::to_string(limits::max_track_frames) +
                                    "] (0: every frame drawn afresh), got " + std::to_string(tracks.frames));
    if (tracks.frames == 0 && !track_defaults)
        throw std::invalid_argument(std::string(who) + ": track_gains, track_coherence_time_s and track_motion describe tracks, "
                                    "which track_frames = 0 turns off: set track_frames > 0, or leave them at "
                                    "their defaults");
    if (tracks.frames > 0) {
        track_draw_spec t;
        t.frames_min = t.frames_max = tracks.frames;
        try {
            t.gains = gain_coherence_from_name(tracks.gains);
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(std::string(who) + ": track_gains: " + e.what());
        }
        if (t.gains != gain_coherence::gauss_markov && tracks.coherence_time_s != no_tracks.coherence_time_s)
            throw std::invalid_argument(std::string(who) + ": track_coherence_time_s applies to track_gains = "
                                        "\"gauss_markov\" only, got track_gains = \"" + tracks.gains + "\"");
        if (!(std::isfinite(tracks.coherence_time_s) && tracks.coherence_time_s > 0.0))
            throw std::invalid_argument(std::string(who) + ": track_coherence_time_s must be a finite time > 0 s, got " +
                                        std::to_string(tracks.coherence_time_s));
        t.coherence_time_s = tracks.coherence_time_s;
        try {
            t.motion = track_motion_from_name(tracks.motion);
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(std::string(who) + ": track_motion: " + e.what());
        }
        r.tracks = t;
    }
    std::optional<clutter_spec> clutter;
    if (clutter_paths < 0)
        throw std::invalid_argument(std::string(who) + ": clutter_paths must be >= 0, got " +
                                    std::to_string(clutter_paths));
    if (clutter_paths == 0 && clutter_csr_db != 0.0)
        throw std::invalid_argument(std::string(who) + ": clutter_csr_db = " + std::to_string(clutter_csr_db) +
                                    " has no effect with clutter_paths = 0: set clutter_paths > 0 to add "
                                    "clutter, or leave clutter_csr_db at 0");
    if (clutter_paths > 0) {
        clutter_spec c;
        c.n_paths = clutter_paths;
        c.csr_db = clutter_csr_db;
        clutter = c;
    }
    // The azimuth interval: checked here, by the parameters' names (scene::validate would name
    // its file key, random.azimuth_rad), with the bounds validate accepts.
    for (const auto& [name, v] : { std::pair<const char*, double>{ "azimuth_min_rad", arrays.azimuth_min_rad },
                                   std::pair<const char*, double>{ "azimuth_max_rad", arrays.azimuth_max_rad } })
        if (!(v >= -M_PI && v <= M_PI)) // NaN fails too
            throw std::invalid_argument(std::string(who) + ": " + name + " must lie in [-pi, pi] rad, got " +
                                        checks::text(v));
    if (arrays.azimuth_min_rad > arrays.azimuth_max_rad)
        throw std::invalid_argument(std::string(who) + ": azimuth_min_rad = " + checks::text(arrays.azimuth_min_rad) +
                                    " exceeds azimuth_max_rad = " + checks::text(arrays.azimuth_max_rad) +
                                    ": the azimuths are drawn from [azimuth_min_rad, azimuth_max_rad]");
    // Without an array a direction changes nothing: refused rather than silently ignored.
    if (!has_array && (arrays.azimuth_min_rad != 0.0 || arrays.azimuth_max_rad != 0.0))
        throw std::invalid_argument(std::string(who) + ": azimuth_min_rad = " + checks::text(arrays.azimuth_min_rad) +
                                    " and azimuth_max_rad = " + checks::text(arrays.azimuth_max_rad) +
                                    " set the targets' directions, which change nothing without an array: set "
                                    "array (a preset's name such as ula8_3g, an array file or its JSON text), or "
                                    "leave them at 0");
    r.azimuth_min_rad = arrays.azimuth_min_rad;
    r.azimuth_max_rad = arrays.azimuth_max_rad;
    auto sc = scene::random(r, clutter, fading_kind::rayleigh, lib);
    if (has_array) {
        try {
            sc = sc.with_array(array_from_setting(arrays.array, who));
        } catch (const std::invalid_argument& e) {
            // array_from_setting names `who` for JSON text; a preset or file's error names the file only.
            const std::string what = e.what();
            throw std::invalid_argument(what.rfind(who, 0) == 0 ? what : std::string(who) + ": array: " + what);
        }
    }
    sc.validate(std::string(who) + " random scene");
    check_streams(sc);
    return sc;
}

truth_dict::truth_dict(const std::string& library)
    : d_truth_key(pmt::intern(keys::truth_tag)),
      d_frame(pmt::intern(keys::frame)),
      d_class(pmt::intern(keys::class_id)),
      d_class_name(pmt::intern(keys::class_name)),
      d_delay_s(pmt::intern(keys::delay_s)),
      d_delay_index(pmt::intern(keys::delay_index)),
      d_range_m(pmt::intern(keys::range_m)),
      d_velocity_mps(pmt::intern(keys::velocity_mps)),
      d_snr_db(pmt::intern(keys::snr_db)),
      d_n_paths(pmt::intern(keys::n_paths)),
      d_micro_motion(pmt::intern(keys::micro_motion)),
      d_micro_motion_params(pmt::intern(keys::micro_motion_params)),
      d_class_library(pmt::intern(keys::class_library)),
      d_track_id(pmt::intern(keys::track_id)),
      d_frame_in_track(pmt::intern(keys::frame_in_track)),
      d_azimuth_rad(pmt::intern(keys::azimuth_rad)),
      d_elevation_rad(pmt::intern(keys::elevation_rad)),
      d_library_symbol(pmt::string_to_symbol(library)),
      d_no_params(pmt::PMT_NIL)
{
}

namespace {
// Equal as stored (a -0 is not a +0): a cached PMT is reused only for the very same value.
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_body(const std::optional<scatterer_body>& a, const scatterer_body* b)
{
    if (!a || !b)
        return !a && !b;
    return a->motion == b->motion && same_bits(a->speed_mps, b->speed_mps) &&
           same_bits(a->heading_rad, b->heading_rad);
}

// JSON as PMT: objects as dicts, arrays as vectors, numbers, booleans, and strings as
// symbols (only model names here, a handful: interned once each).
pmt::pmt_t json_to_pmt(const nlohmann::json& j)
{
    if (j.is_object()) {
        pmt::pmt_t d = pmt::make_dict();
        for (auto it = j.rbegin(); it != j.rend(); ++it) // acons prepends: keep the JSON's order
            d = pmt::acons(pmt::string_to_symbol(it.key()), json_to_pmt(it.value()), d);
        return d;
    }
    if (j.is_array()) {
        pmt::pmt_t v = pmt::make_vector(j.size(), pmt::PMT_NIL);
        for (size_t k = 0; k < j.size(); ++k)
            pmt::vector_set(v, k, json_to_pmt(j[k]));
        return v;
    }
    if (j.is_boolean())
        return pmt::from_bool(j.get<bool>());
    if (j.is_number_integer())
        return pmt::from_long(j.get<long>());
    if (j.is_number())
        return pmt::from_double(j.get<double>());
    if (j.is_string())
        return pmt::string_to_symbol(j.get<std::string>());
    return pmt::PMT_NIL;
}

// The body's drawn parameters as a PMT dict (micro_motion_to_json, speed and heading). Not
// as JSON text: PMT strings are symbols, interned for the life of the process, and a
// random scene draws new parameters every frame.
pmt::pmt_t body_params(const scatterer_body& b)
{
    auto j = micro_motion_to_json(b.motion);
    j["speed_mps"] = b.speed_mps;
    j["heading_rad"] = b.heading_rad;
    return json_to_pmt(j);
}
} // namespace

pmt::pmt_t truth_dict::make(const frame_realization& r, uint64_t frame, double snr_setting_db)
{
    const frame_truth& t = r.truth;
    // With a link budget the target's SNR is the radar equation's plus the setting's shift.
    const double snr_db = std::isnan(t.link_snr_db) ? snr_setting_db : snr_setting_db + t.link_snr_db;
    if (r.truth_body >= static_cast<int>(r.bodies.size()))
        throw std::invalid_argument("sems_truth: the target of interest's body " + std::to_string(r.truth_body) +
                                    " is beyond the frame's " + std::to_string(r.bodies.size()) + " bodies");
    const scatterer_body* body = r.truth_body >= 0 ? &r.bodies[static_cast<size_t>(r.truth_body)] : nullptr;
    const bool same_tail = d_tail_valid && t.class_id == d_tail_truth.class_id &&
                           t.n_paths == d_tail_truth.n_paths && t.class_name == d_tail_truth.class_name &&
                           same_bits(t.delay_s, d_tail_truth.delay_s) &&
                           same_bits(t.delay_index, d_tail_truth.delay_index) &&
                           same_bits(t.range_m, d_tail_truth.range_m) &&
                           same_bits(t.velocity_mps, d_tail_truth.velocity_mps) && same_bits(snr_db, d_tail_snr_db) &&
                           same_bits(t.azimuth_rad, d_tail_truth.azimuth_rad) &&
                           same_bits(t.elevation_rad, d_tail_truth.elevation_rad) &&
                           t.micro_motion == d_tail_truth.micro_motion && same_body(d_tail_body, body);
    if (!same_tail) {
        if (t.class_id < 0)
            throw std::invalid_argument("sems_truth: negative class id " + std::to_string(t.class_id));
        const auto cls = static_cast<size_t>(t.class_id);
        if (cls >= d_class_symbols.size())
            d_class_symbols.resize(cls + 1);
        if (!d_class_symbols[cls]) // interning hashes and locks: once per class, not per frame
            d_class_symbols[cls] = pmt::string_to_symbol(t.class_name);
        pmt::pmt_t tail = pmt::make_dict();
        tail = pmt::acons(d_class, pmt::from_long(t.class_id), tail);
        tail = pmt::acons(d_class_name, d_class_symbols[cls], tail);
        tail = pmt::acons(d_delay_s, pmt::from_double(t.delay_s), tail);
        tail = pmt::acons(d_delay_index, pmt::from_double(t.delay_index), tail);
        tail = pmt::acons(d_range_m, pmt::from_double(t.range_m), tail);
        tail = pmt::acons(d_velocity_mps, pmt::from_double(t.velocity_mps), tail);
        tail = pmt::acons(d_snr_db, pmt::from_double(snr_db), tail);
        if (!std::isnan(t.azimuth_rad)) { // a scene with an array: the target's direction
            tail = pmt::acons(d_azimuth_rad, pmt::from_double(t.azimuth_rad), tail);
            tail = pmt::acons(d_elevation_rad, pmt::from_double(t.elevation_rad), tail);
        }
        tail = pmt::acons(d_n_paths, pmt::from_long(t.n_paths), tail);
        auto& model = d_motion_symbols[t.micro_motion]; // a handful of model names: interned once each
        if (!model)
            model = pmt::string_to_symbol(t.micro_motion);
        tail = pmt::acons(d_micro_motion, model, tail);
        tail = pmt::acons(d_micro_motion_params, body ? body_params(*body) : d_no_params, tail);
        tail = pmt::acons(d_class_library, d_library_symbol, tail);
        d_tail = tail;
        if (body)
            d_tail_body = *body;
        else
            d_tail_body.reset();
        d_tail_truth = t;
        d_tail_snr_db = snr_db;
        d_tail_valid = true;
    }
    // Per frame: the frame and its place in its track; the rest is shared while it stays.
    pmt::pmt_t head = pmt::acons(d_frame_in_track, pmt::from_uint64(t.frame_in_track), d_tail);
    head = pmt::acons(d_track_id, pmt::from_uint64(t.track_id), head);
    return pmt::acons(d_frame, pmt::from_uint64(frame), head);
}

} // namespace detail
} // namespace sems
} // namespace gr
