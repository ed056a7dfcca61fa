// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: scenes — construction, validation and the JSON file format.
 *
 * File format (docs/design.md §4), one of "targets" (fixed) or "random":
 *   {"format": "sems.scene", "version": 1, "fading": "rayleigh" | "none",
 *    "target_of_interest": 0,
 *    "targets": [{"class": "drone", "range_m": 50, "velocity_mps": 7, "power": 1,
 *                 "micro_doppler": {"rate_hz": 100, "amplitude_m": 0.01, "phase_rad": 0},
 *                 "paths": [{"excess_range_m": 0, "power": 1}, {"excess_range_m": 12, "power": 0.3}]}],
 *    "random": {"classes": ["pedestrian", "car", "drone"], "targets": 1, "paths_per_target": 1,
 *               "excess_range_m": [2, 30], "path_power_decay_db": 3, "micro_doppler": true,
 *               "heading": "approaching" | "any", "azimuth_rad": [lo, hi] | value,
 *               "elevation_rad": [lo, hi] | value (point, sinusoid and walker classes),
 *               "tracks": {"frames": 64 | [16, 64], "gains": "frame" | "track" | "gauss_markov",
 *                          "coherence_time_s": 0.1, "motion": "radial" | "straight"}},
 *    "clutter": {"csr_db": 10, "paths": 4, "range_m": [0, 200]}   or   {"csr_db": 10, "ranges_m": [...]},
 *    "array": {"receive": {"ula": {...}}, ...} | "file.json" | "preset name"}   (array_geometry.h; targets add
 *    "azimuth_rad" and "elevation_rad")
 */
#include "core/common/checks.h"
#include "core/common/json_object.h"
#include "core/scene/micro_motion_params.h"
#include "core/common/named_files.h"
#include "core/scene/walker_scatterers.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <fstream>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {

using json = nlohmann::json;
using json_read::fail;

namespace {

void check_finite_nonneg(double v, const std::string& source, const std::string& field)
{
    if (!checks::non_negative(v))
        fail(source, field, "must be a finite number >= 0, got " + std::to_string(v));
}

void check_positive(double v, const std::string& source, const std::string& field)
{
    if (!checks::positive(v))
        fail(source, field, "must be a finite number > 0, got " + std::to_string(v));
}

// A relative power: > 0 and at most limits::max_relative_power.
void check_power(double v, const std::string& source, const std::string& field)
{
    check_positive(v, source, field);
    if (v > limits::max_relative_power)
        fail(source, field, "must be at most 1e30 (a relative power), got " + std::to_string(v));
}

void validate_clutter(const clutter_spec& c, const std::string& source)
{
    if (!checks::finite(c.csr_db))
        fail(source, "clutter.csr_db", "must be finite");
    if (c.ranges_m.size() > static_cast<size_t>(limits::max_clutter_paths))
        fail(source, "clutter.ranges_m", "has " + std::to_string(c.ranges_m.size()) + " ranges, more than the limit of " +
                                             std::to_string(limits::max_clutter_paths));
    if (c.ranges_m.empty()) {
        if (c.n_paths < 1 || c.n_paths > limits::max_clutter_paths)
            fail(source, "clutter.paths", "must be in [1, " + std::to_string(limits::max_clutter_paths) + "], got " +
                                              std::to_string(c.n_paths));
        check_finite_nonneg(c.range_min_m, source, "clutter.range_m[0]");
        check_finite_nonneg(c.range_max_m, source, "clutter.range_m[1]");
        if (c.range_min_m > c.range_max_m)
            fail(source, "clutter.range_m", "min exceeds max");
    } else {
        for (double r : c.ranges_m)
            check_finite_nonneg(r, source, "clutter.ranges_m");
    }
    if (!c.azimuths_rad.empty() && c.azimuths_rad.size() != c.ranges_m.size())
        fail(source, "clutter.azimuths_rad", "has " + std::to_string(c.azimuths_rad.size()) + " azimuths for " +
                                                 std::to_string(c.ranges_m.size()) + " ranges_m: give one per scatterer");
    for (size_t i = 0; i < c.azimuths_rad.size(); ++i)
        if (!(checks::finite(c.azimuths_rad[i]) && std::fabs(c.azimuths_rad[i]) <= M_PI))
            fail(source, "clutter.azimuths_rad[" + std::to_string(i) + "]",
                 "must lie in [-pi, pi] rad, got " + checks::text(c.azimuths_rad[i]));
}

} // namespace

std::string heading_name(heading_kind h)
{
    switch (h) {
    case heading_kind::approaching:
        return "approaching";
    case heading_kind::any:
        return "any";
    }
    throw std::invalid_argument("unknown heading kind " + std::to_string(static_cast<int>(h)));
}

heading_kind heading_from_name(const std::string& name)
{
    if (name == "approaching")
        return heading_kind::approaching;
    if (name == "any")
        return heading_kind::any;
    throw std::invalid_argument("unknown heading \"" + name + "\" (known: approaching, any)");
}

std::string gain_coherence_name(gain_coherence c)
{
    switch (c) {
    case gain_coherence::frame:
        return "frame";
    case gain_coherence::track:
        return "track";
    case gain_coherence::gauss_markov:
        return "gauss_markov";
    }
    throw std::invalid_argument("unknown gain coherence " + std::to_string(static_cast<int>(c)));
}

gain_coherence gain_coherence_from_name(const std::string& name)
{
    if (name == "frame")
        return gain_coherence::frame;
    if (name == "track")
        return gain_coherence::track;
    if (name == "gauss_markov")
        return gain_coherence::gauss_markov;
    throw std::invalid_argument("unknown gain coherence \"" + name + "\" (known: frame, track, gauss_markov)");
}

std::string track_motion_name(track_motion m)
{
    switch (m) {
    case track_motion::radial:
        return "radial";
    case track_motion::straight:
        return "straight";
    }
    throw std::invalid_argument("unknown track motion " + std::to_string(static_cast<int>(m)));
}

track_motion track_motion_from_name(const std::string& name)
{
    if (name == "radial")
        return track_motion::radial;
    if (name == "straight")
        return track_motion::straight;
    throw std::invalid_argument("unknown track motion \"" + name + "\" (known: radial, straight)");
}

namespace {

json range_pair(double lo, double hi) { return json::array({ lo, hi }); }

std::pair<double, double> read_pair(const json& v, const std::string& field, const std::string& source)
{
    if (!v.is_array() || v.size() != 2)
        fail(source, field, "expected [min, max]");
    return { json_read::finite_number(v[0], field, source), json_read::finite_number(v[1], field, source) };
}

} // namespace

scene scene::fixed(std::vector<target_spec> targets,
                   std::optional<clutter_spec> clutter,
                   int toi,
                   fading_kind fading,
                   std::shared_ptr<const class_library> library)
{
    scene s;
    if (library)
        s.d_library = std::move(library);
    s.d_targets = std::move(targets);
    s.d_clutter = std::move(clutter);
    s.d_toi = toi;
    s.d_fading = fading;
    s.validate("fixed scene");
    return s;
}

scene scene::random(random_spec spec,
                    std::optional<clutter_spec> clutter,
                    fading_kind fading,
                    std::shared_ptr<const class_library> library)
{
    scene s;
    if (library)
        s.d_library = std::move(library);
    s.d_random = std::move(spec);
    s.d_clutter = std::move(clutter);
    s.d_fading = fading;
    s.validate("random scene");
    return s;
}

std::vector<target_class> scene::label_classes() const
{
    if (d_random) {
        if (!d_random->classes.empty())
            return d_random->classes;
        std::vector<target_class> all;
        for (int i = 0; i < d_library->size(); ++i)
            all.push_back(static_cast<target_class>(i));
        return all;
    }
    return { d_targets.at(d_toi).cls };
}

std::pair<double, double> target_speed_heading(const target_spec& t)
{
    if (!std::isnan(t.speed_mps))
        return { t.speed_mps, t.heading_rad };
    return { std::fabs(t.velocity_mps), t.velocity_mps < 0.0 ? M_PI : 0.0 };
}

scene scene::with_library(std::shared_ptr<const class_library> lib) const
{
    if (!lib)
        throw std::invalid_argument("scene: with_library needs a library");
    scene s = *this;
    const std::vector<target_class> paper_default = random_spec{}.classes;
    if (s.d_random && s.d_library.get() == class_library::paper().get() && s.d_random->classes == paper_default)
        s.d_random->classes.clear(); // the default (every paper class) becomes every class of the new library
    s.d_library = std::move(lib);
    s.validate("scene with class library " + s.d_library->name());
    return s;
}

scene scene::with_track(track_spec t) const
{
    scene s = *this;
    s.d_track = t;
    s.validate("scene with a track");
    return s;
}

scene scene::with_array(array_geometry a) const
{
    scene s = *this;
    s.d_array = std::move(a);
    return s;
}

scene scene::with_budget(link_budget b) const
{
    scene s = *this;
    b.validate("scene", "link_budget");
    s.d_budget = b;
    s.validate("scene with a link budget");
    return s;
}

// A link budget needs every target's RCS and ranges where the radar equation holds.
void scene::validate_budget(const std::string& source) const
{
    const double near = link_budget::min_range_m;
    const std::string why = " (a link budget's radar equation holds from " + std::to_string(near) + " m)";
    if (d_random) {
        for (auto c : label_classes()) { // every target of a frame draws from these
            const auto& def = d_library->at(static_cast<int>(c));
            const std::string f = "class \"" + def.name + "\" of class library " + d_library->name();
            if (!def.has_rcs())
                fail(source, "link_budget", f + " has no rcs_dbsm: a link budget needs each class's RCS");
            if (def.range_min_m < near)
                fail(source, "link_budget", f + " comes as near as " + std::to_string(def.range_min_m) + " m" + why);
        }
    }
    for (size_t i = 0; i < d_targets.size(); ++i) {
        const auto& t = d_targets[i];
        const std::string f = "targets[" + std::to_string(i) + "]";
        if (std::isnan(t.rcs_dbsm))
            fail(source, f + ".rcs_dbsm", "missing: a scene with a link budget needs each target's RCS in dBsm");
        if (t.power != 1.0)
            fail(source, f + ".power", "a link budget sets the power from the range and RCS; give rcs_dbsm, not power");
        if (t.range_m < near)
            fail(source, f + ".range_m", std::to_string(t.range_m) + " m is too near" + why);
    }
    if (d_track && d_track->range_min_m < near)
        fail(source, "track.range_m", "starts at " + std::to_string(d_track->range_min_m) + " m" + why);
}

void scene::validate(const std::string& source) const
{
    if (d_clutter)
        validate_clutter(*d_clutter, source);
    for (size_t i = 0; i < d_targets.size(); ++i)
        if (!std::isnan(d_targets[i].rcs_dbsm) && !std::isfinite(d_targets[i].rcs_dbsm))
            fail(source, "targets[" + std::to_string(i) + "].rcs_dbsm", "must be a finite number of dBsm");
    if (d_budget)
        validate_budget(source);
    if (d_track) {
        if (d_random)
            fail(source, "track", "applies to fixed scenes only (a random scene follows its targets with random.tracks)");
        check_finite_nonneg(d_track->range_min_m, source, "track.range_m[0]");
        check_finite_nonneg(d_track->range_max_m, source, "track.range_m[1]");
        if (!(d_track->range_min_m < d_track->range_max_m))
            fail(source, "track.range_m", "min must be below max");
        for (size_t i = 0; i < d_targets.size(); ++i)
            if (d_targets[i].range_m < d_track->range_min_m || d_targets[i].range_m > d_track->range_max_m)
                fail(source, "targets[" + std::to_string(i) + "].range_m",
                     "starts outside the track [" + std::to_string(d_track->range_min_m) + ", " +
                         std::to_string(d_track->range_max_m) + "] m");
    }
    if (d_random) {
        const auto& r = *d_random;
        for (auto c : r.classes)
            if (static_cast<int>(c) < 0 || static_cast<int>(c) >= d_library->size())
                fail(source, "random.classes", "class id " + std::to_string(static_cast<int>(c)) +
                                                   " is beyond class library " + d_library->name() + " (" +
                                                   std::to_string(d_library->size()) + " classes)");
        auto sorted = r.classes;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
            fail(source, "random.classes", "lists a class twice");
        if (r.classes.size() > static_cast<size_t>(limits::max_classes))
            fail(source, "random.classes", "lists more than " + std::to_string(limits::max_classes) + " classes");
        if (r.n_targets < 1 || r.n_targets > limits::max_targets)
            fail(source, "random.targets", "must be in [1, " + std::to_string(limits::max_targets) + "], got " +
                                               std::to_string(r.n_targets));
        if (r.paths_per_target < 1 || r.paths_per_target > limits::max_paths)
            fail(source, "random.paths_per_target", "must be in [1, " + std::to_string(limits::max_paths) +
                                                        "], got " + std::to_string(r.paths_per_target));
        check_finite_nonneg(r.excess_range_min_m, source, "random.excess_range_m[0]");
        check_finite_nonneg(r.excess_range_max_m, source, "random.excess_range_m[1]");
        if (r.excess_range_min_m > r.excess_range_max_m)
            fail(source, "random.excess_range_m", "min exceeds max");
        check_finite_nonneg(r.path_power_decay_db, source, "random.path_power_decay_db");
        if (r.heading != heading_kind::approaching && r.heading != heading_kind::any)
            fail(source, "random.heading", "unknown heading kind " + std::to_string(static_cast<int>(r.heading)));
        if (!(checks::finite(r.azimuth_min_rad) && checks::finite(r.azimuth_max_rad) && r.azimuth_min_rad >= -M_PI &&
              r.azimuth_max_rad <= M_PI))
            fail(source, "random.azimuth_rad", "must lie in [-pi, pi] rad, got [" + checks::text(r.azimuth_min_rad) +
                                                   ", " + checks::text(r.azimuth_max_rad) + "]");
        if (r.azimuth_min_rad > r.azimuth_max_rad)
            fail(source, "random.azimuth_rad", "min exceeds max");
        if (!(checks::finite(r.elevation_min_rad) && checks::finite(r.elevation_max_rad) &&
              r.elevation_min_rad >= -M_PI / 2 && r.elevation_max_rad <= M_PI / 2))
            fail(source, "random.elevation_rad", "must lie in [-pi/2, pi/2] rad, got [" +
                                                     checks::text(r.elevation_min_rad) + ", " +
                                                     checks::text(r.elevation_max_rad) + "]");
        if (r.elevation_min_rad > r.elevation_max_rad)
            fail(source, "random.elevation_rad", "min exceeds max");
        if (r.micro_doppler && (r.elevation_min_rad != 0.0 || r.elevation_max_rad != 0.0))
            for (auto c : label_classes()) { // a drawn body must be one modelled from any elevation
                const auto& def = d_library->at(static_cast<int>(c));
                const std::string model = def.motion_model();
                if (!detail::modelled_from_any_elevation(model))
                    fail(source, "random.elevation_rad",
                         "class \"" + def.name + "\" of class library " + d_library->name() + " is a " + model +
                             ", modelled as seen from the ground plane: only " +
                             detail::models_from_any_elevation +
                             " targets take an elevation other than 0 (or set micro_doppler false)");
            }
        if (r.tracks) {
            const auto& t = *r.tracks;
            const std::string bound = "[1, " + std::to_string(limits::max_track_frames) + "]";
            if (t.frames_min < 1 || t.frames_min > limits::max_track_frames)
                fail(source, "random.tracks.frames", "the track length must be in " + bound + " frames, got " +
                                                         std::to_string(t.frames_min));
            if (t.frames_max < 1 || t.frames_max > limits::max_track_frames)
                fail(source, "random.tracks.frames", "the track length must be in " + bound + " frames, got " +
                                                         std::to_string(t.frames_max));
            if (t.frames_min > t.frames_max)
                fail(source, "random.tracks.frames", "min " + std::to_string(t.frames_min) + " exceeds max " +
                                                         std::to_string(t.frames_max));
            if (t.gains != gain_coherence::frame && t.gains != gain_coherence::track &&
                t.gains != gain_coherence::gauss_markov)
                fail(source, "random.tracks.gains", "unknown gain coherence " + std::to_string(static_cast<int>(t.gains)));
            if (!(checks::finite(t.coherence_time_s) && t.coherence_time_s > 0.0))
                fail(source, "random.tracks.coherence_time_s", "must be a finite time > 0 s, got " +
                                                                   std::to_string(t.coherence_time_s));
            if (t.motion != track_motion::radial && t.motion != track_motion::straight)
                fail(source, "random.tracks.motion", "unknown track motion " + std::to_string(static_cast<int>(t.motion)));
            if (d_fading == fading_kind::none && t.gains != gain_coherence::frame)
                fail(source, "random.tracks.gains", "\"" + gain_coherence_name(t.gains) +
                                                        "\" describes fading gains, but the scene's fading is "
                                                        "\"none\" (fixed gains): leave gains at \"frame\"");
        }
        return;
    }
    if (d_targets.empty())
        fail(source, "targets", "a fixed scene needs at least one target");
    if (d_targets.size() > static_cast<size_t>(limits::max_targets))
        fail(source, "targets", "has " + std::to_string(d_targets.size()) + " targets, more than the limit of " +
                                    std::to_string(limits::max_targets));
    if (d_toi < 0 || d_toi >= static_cast<int>(d_targets.size()))
        fail(source, "target_of_interest",
             "is " + std::to_string(d_toi) + " but the scene has " + std::to_string(d_targets.size()) + " targets");
    for (size_t i = 0; i < d_targets.size(); ++i) {
        const auto& t = d_targets[i];
        const std::string f = "targets[" + std::to_string(i) + "]";
        if (static_cast<int>(t.cls) < 0 || static_cast<int>(t.cls) >= d_library->size())
            fail(source, f + ".class", "class id " + std::to_string(static_cast<int>(t.cls)) + " is beyond class library " +
                                           d_library->name());
        check_finite_nonneg(t.range_m, source, f + ".range_m");
        if (!checks::finite(t.velocity_mps))
            fail(source, f + ".velocity_mps", "must be finite");
        check_power(t.power, source, f + ".power");
        if (!(checks::finite(t.azimuth_rad) && std::fabs(t.azimuth_rad) <= M_PI))
            fail(source, f + ".azimuth_rad", "must lie in [-pi, pi] rad, got " + checks::text(t.azimuth_rad));
        if (!(checks::finite(t.elevation_rad) && std::fabs(t.elevation_rad) <= M_PI / 2))
            fail(source, f + ".elevation_rad", "must lie in [-pi/2, pi/2] rad, got " + checks::text(t.elevation_rad));
        if (t.elevation_rad != 0.0 && t.motion && !std::holds_alternative<walker_motion>(*t.motion))
            fail(source, f + ".elevation_rad",
                 "a " + micro_motion_model(*t.motion) +
                     " target is modelled as seen from the ground plane: its elevation must be 0 (walkers, sinusoids "
                     "and point targets take any)");
        if (!std::isnan(t.speed_mps)) {
            check_finite_nonneg(t.speed_mps, source, f + ".speed_mps");
            if (!checks::finite(t.heading_rad))
                fail(source, f + ".heading_rad", "must be finite");
            if (std::fabs(t.velocity_mps - t.speed_mps * std::cos(t.heading_rad) * std::cos(t.elevation_rad)) >
                1e-9 * (1.0 + t.speed_mps))
                fail(source, f + ".velocity_mps",
                     "must equal speed_mps·cos(heading_rad)·cos(elevation_rad) when a speed is given");
        }
        if (t.md && t.motion)
            fail(source, f + ".micro_motion", "a target has one micro-motion: a sinusoid or a scatterer model, not both");
        if (t.motion) {
            validate_micro_motion(*t.motion, source, f + ".micro_motion");
            if (std::holds_alternative<walker_motion>(*t.motion))
                detail::walker_check_speed(std::get<walker_motion>(*t.motion).height_m, target_speed_heading(t).first,
                                           source, f + ".speed_mps");
        }
        if (t.md) {
            check_finite_nonneg(t.md->rate_hz, source, f + ".micro_doppler.rate_hz");
            check_finite_nonneg(t.md->amplitude_m, source, f + ".micro_doppler.amplitude_m");
            if (!checks::finite(t.md->phase_rad))
                fail(source, f + ".micro_doppler.phase_rad", "must be finite");
        }
        if (t.paths.empty())
            fail(source, f + ".paths", "needs at least one path");
        if (t.paths.size() > static_cast<size_t>(limits::max_paths))
            fail(source, f + ".paths", "has " + std::to_string(t.paths.size()) + " paths, more than the limit of " +
                                           std::to_string(limits::max_paths));
        if (t.paths[0].excess_range_m != 0.0)
            fail(source, f + ".paths[0].excess_range_m", "the first path is the direct path and must be 0");
        for (size_t k = 0; k < t.paths.size(); ++k) {
            const std::string pf = f + ".paths[" + std::to_string(k) + "]";
            check_finite_nonneg(t.paths[k].excess_range_m, source, pf + ".excess_range_m");
            check_power(t.paths[k].power, source, pf + ".power");
        }
    }
}

json scene::to_json() const
{
    json j = { { "format", format_name },
               { "version", format_version },
               { "fading", d_fading == fading_kind::rayleigh ? "rayleigh" : "none" } };
    if (d_random) {
        const auto& r = *d_random;
        json classes = json::array();
        for (auto c : label_classes())
            classes.push_back(d_library->at(static_cast<int>(c)).name);
        j["random"] = { { "classes", classes },
                        { "targets", r.n_targets },
                        { "paths_per_target", r.paths_per_target },
                        { "excess_range_m", range_pair(r.excess_range_min_m, r.excess_range_max_m) },
                        { "path_power_decay_db", r.path_power_decay_db },
                        { "micro_doppler", r.micro_doppler },
                        { "heading", heading_name(r.heading) } };
        if (r.azimuth_min_rad != 0.0 || r.azimuth_max_rad != 0.0)
            j["random"]["azimuth_rad"] = range_pair(r.azimuth_min_rad, r.azimuth_max_rad);
        if (r.elevation_min_rad != 0.0 || r.elevation_max_rad != 0.0)
            j["random"]["elevation_rad"] = range_pair(r.elevation_min_rad, r.elevation_max_rad);
        if (r.tracks) {
            const auto& t = *r.tracks;
            json jt = { { "frames", t.frames_min == t.frames_max ? json(t.frames_min)
                                                               : json::array({ t.frames_min, t.frames_max }) },
                        { "gains", gain_coherence_name(t.gains) } };
            if (t.gains == gain_coherence::gauss_markov)
                jt["coherence_time_s"] = t.coherence_time_s;
            if (t.motion != track_motion::radial) // written only when given: older files read back as they were
                jt["motion"] = track_motion_name(t.motion);
            j["random"]["tracks"] = jt;
        }
    } else {
        j["target_of_interest"] = d_toi;
        json targets = json::array();
        for (const auto& t : d_targets) {
            json paths = json::array();
            for (const auto& p : t.paths)
                paths.push_back({ { "excess_range_m", p.excess_range_m }, { "power", p.power } });
            json jt = { { "class", d_library->at(static_cast<int>(t.cls)).name },
                        { "range_m", t.range_m },
                        { "power", t.power },
                        { "paths", paths } };
            if (std::isnan(t.speed_mps)) {
                jt["velocity_mps"] = t.velocity_mps;
            } else {
                jt["speed_mps"] = t.speed_mps;
                jt["heading_rad"] = t.heading_rad;
            }
            if (!std::isnan(t.rcs_dbsm))
                jt["rcs_dbsm"] = t.rcs_dbsm;
            if (t.azimuth_rad != 0.0)
                jt["azimuth_rad"] = t.azimuth_rad;
            if (t.elevation_rad != 0.0)
                jt["elevation_rad"] = t.elevation_rad;
            if (t.motion)
                jt["micro_motion"] = micro_motion_to_json(*t.motion);
            if (t.md)
                jt["micro_doppler"] = { { "rate_hz", t.md->rate_hz },
                                        { "amplitude_m", t.md->amplitude_m },
                                        { "phase_rad", t.md->phase_rad } };
            targets.push_back(jt);
        }
        j["targets"] = targets;
    }
    if (d_library->name() != "paper")
        j["classes"] = d_library->name();
    if (d_track)
        j["track"] = { { "range_m", range_pair(d_track->range_min_m, d_track->range_max_m) },
                       { "at_bound", d_track->at_bound == track_bound::restart ? "restart" : "reflect" } };
    if (d_budget)
        j["link_budget"] = d_budget->to_json();
    if (d_array) {
        json ja = d_array->to_json();
        ja.erase("format");
        ja.erase("version");
        j["array"] = ja;
    }
    if (d_clutter) {
        const auto& c = *d_clutter;
        json jc = { { "csr_db", c.csr_db } };
        if (c.ranges_m.empty()) {
            jc["paths"] = c.n_paths;
            jc["range_m"] = range_pair(c.range_min_m, c.range_max_m);
        } else {
            jc["ranges_m"] = c.ranges_m;
            if (!c.azimuths_rad.empty())
                jc["azimuths_rad"] = c.azimuths_rad;
        }
        j["clutter"] = jc;
    }
    return j;
}

scene scene::from_json(const json& j, const std::string& source)
{
    using namespace json_read;
    check_format(j, format_name, format_version, source);
    // Every object is read through an object_reader: a key nobody reads is an error
    // naming its path (targets[0].powr), at every level.
    object_reader top(j, source);
    top.allow("format");
    top.allow("version");
    top.allow("description"); // free text for people

    scene s;
    if (top.has("classes")) {
        const std::string lib = top.string("classes");
        try {
            s.d_library = class_library::find(lib);
        } catch (const std::invalid_argument& e) {
            fail(source, "classes", e.what());
        }
    }
    const std::string fading = top.string_or("fading", "rayleigh");
    if (fading == "rayleigh")
        s.d_fading = fading_kind::rayleigh;
    else if (fading == "none")
        s.d_fading = fading_kind::none;
    else
        fail(source, "fading", "expected \"rayleigh\" or \"none\", got \"" + fading + "\"");

    auto class_of = [&](const json& v, const std::string& field) {
        try {
            return static_cast<target_class>(s.d_library->id_of(string(v, field, source)));
        } catch (const std::invalid_argument& e) {
            if (std::string(e.what()).rfind(source, 0) == 0)
                throw;
            fail(source, field, e.what());
        }
    };

    const auto* jtargets = top.find("targets");
    const auto* jrandom = top.find("random");
    if ((jtargets != nullptr) == (jrandom != nullptr))
        fail(source, "", "give exactly one of \"targets\" (a fixed scene) or \"random\"");

    if (jrandom) {
        object_reader r(*jrandom, source, "random");
        random_spec spec;
        spec.classes.clear(); // absent: every class of the library
        if (const auto* classes = r.find("classes")) {
            object_reader::checked_array(*classes, "random.classes", source, 0, limits::max_classes);
            if (classes->empty())
                fail(source, "random.classes", "needs at least one class (leave it out for every class of the library)");
            spec.classes.clear();
            for (size_t i = 0; i < classes->size(); ++i)
                spec.classes.push_back(class_of((*classes)[i], "random.classes[" + std::to_string(i) + "]"));
        }
        spec.n_targets = r.int_or("targets", spec.n_targets, 1, limits::max_targets);
        spec.paths_per_target = r.int_or("paths_per_target", spec.paths_per_target, 1, limits::max_paths);
        if (const auto* er = r.find("excess_range_m"))
            std::tie(spec.excess_range_min_m, spec.excess_range_max_m) =
                read_pair(*er, "random.excess_range_m", source);
        spec.path_power_decay_db = r.number_or("path_power_decay_db", spec.path_power_decay_db);
        spec.micro_doppler = r.boolean_or("micro_doppler", spec.micro_doppler);
        if (r.has("heading")) {
            const std::string h = r.string("heading");
            try {
                spec.heading = heading_from_name(h);
            } catch (const std::invalid_argument& e) {
                fail(source, "random.heading", e.what());
            }
        }
        if (const auto* az = r.find("azimuth_rad")) {
            if (az->is_array())
                std::tie(spec.azimuth_min_rad, spec.azimuth_max_rad) = read_pair(*az, "random.azimuth_rad", source);
            else
                spec.azimuth_min_rad = spec.azimuth_max_rad = finite_number(*az, "random.azimuth_rad", source);
        }
        if (const auto* el = r.find("elevation_rad")) {
            if (el->is_array())
                std::tie(spec.elevation_min_rad, spec.elevation_max_rad) = read_pair(*el, "random.elevation_rad", source);
            else
                spec.elevation_min_rad = spec.elevation_max_rad = finite_number(*el, "random.elevation_rad", source);
        }
        if (r.has("tracks")) {
            object_reader rt = r.object("tracks");
            track_draw_spec t;
            const auto& frames = rt.require("frames");
            const int top_frames = limits::max_track_frames;
            if (frames.is_array()) {
                object_reader::checked_array(frames, "random.tracks.frames", source, 2, 2);
                t.frames_min = int_in(frames[0], "random.tracks.frames[0]", source, 1, top_frames);
                t.frames_max = int_in(frames[1], "random.tracks.frames[1]", source, 1, top_frames);
            } else {
                t.frames_min = t.frames_max = int_in(frames, "random.tracks.frames", source, 1, top_frames);
            }
            if (rt.has("gains")) {
                try {
                    t.gains = gain_coherence_from_name(rt.string("gains"));
                } catch (const std::invalid_argument& e) {
                    fail(source, "random.tracks.gains", e.what());
                }
            }
            if (rt.has("coherence_time_s")) {
                if (t.gains != gain_coherence::gauss_markov)
                    fail(source, "random.tracks.coherence_time_s",
                         "applies to \"gains\": \"gauss_markov\" only, the gains here are \"" +
                             gain_coherence_name(t.gains) + "\"");
                t.coherence_time_s = rt.number("coherence_time_s");
            }
            if (rt.has("motion")) {
                try {
                    t.motion = track_motion_from_name(rt.string("motion"));
                } catch (const std::invalid_argument& e) {
                    fail(source, "random.tracks.motion", e.what());
                }
            }
            rt.finish();
            spec.tracks = t;
        }
        r.finish();
        if (top.has("target_of_interest"))
            fail(source, "target_of_interest", "applies to fixed scenes only (a random scene's is target 0)");
        s.d_random = spec;
    } else {
        const auto& list = object_reader::checked_array(*jtargets, "targets", source, 0, limits::max_targets);
        for (size_t i = 0; i < list.size(); ++i) {
            const std::string f = "targets[" + std::to_string(i) + "]";
            object_reader rt(list[i], source, f);
            target_spec t;
            t.cls = class_of(rt.require("class"), f + ".class");
            t.range_m = rt.number("range_m");
            if (rt.has("speed_mps")) { // speed along a heading: the radial velocity follows
                if (rt.has("velocity_mps"))
                    fail(source, f, "give velocity_mps (radial) or speed_mps with heading_rad, not both");
                t.speed_mps = rt.number("speed_mps");
                t.heading_rad = rt.number_or("heading_rad", 0.0);
                t.elevation_rad = rt.number_or("elevation_rad", 0.0);
                t.velocity_mps = t.speed_mps * std::cos(t.heading_rad);
                if (t.elevation_rad != 0.0) // the ground-plane motion's projection on the line of sight
                    t.velocity_mps *= std::cos(t.elevation_rad);
            } else {
                if (rt.has("heading_rad"))
                    fail(source, f + ".heading_rad", "goes with speed_mps (velocity_mps is already radial)");
                t.velocity_mps = rt.number("velocity_mps");
            }
            t.power = rt.number_or("power", 1.0);
            t.rcs_dbsm = rt.number_or("rcs_dbsm", t.rcs_dbsm);
            t.azimuth_rad = rt.number_or("azimuth_rad", 0.0);
            t.elevation_rad = rt.number_or("elevation_rad", t.elevation_rad);
            if (const auto* mm = rt.find("micro_motion")) {
                if (rt.has("micro_doppler"))
                    fail(source, f, "give micro_motion or its short form micro_doppler, not both");
                const auto tmpl = detail::read_motion_template(*mm, source, f + ".micro_motion", false);
                if (tmpl.model == "sinusoid")
                    t.md = detail::draw_sinusoid(tmpl, nullptr);
                else
                    t.motion = detail::draw_motion(tmpl, nullptr);
            }
            if (const auto* md = rt.find("micro_doppler")) {
                object_reader rm(*md, source, f + ".micro_doppler");
                micro_doppler m;
                m.rate_hz = rm.number("rate_hz");
                // No silent class default: a scene that models micro-Doppler states its size.
                if (!rm.has("amplitude_m"))
                    fail(source, rm.field("amplitude_m"),
                         "missing (the displacement in metres; class \"" + s.d_library->at(static_cast<int>(t.cls)).name +
                             "\" of class library " + s.d_library->name() + " uses " +
                             std::to_string(s.d_library->at(static_cast<int>(t.cls)).max_extent_m()) + ")");
                m.amplitude_m = rm.number("amplitude_m");
                m.phase_rad = rm.number_or("phase_rad", 0.0);
                rm.finish();
                t.md = m;
            }
            if (const auto* paths = rt.find("paths")) {
                object_reader::checked_array(*paths, f + ".paths", source, 1, limits::max_paths);
                t.paths.clear();
                for (size_t k = 0; k < paths->size(); ++k) {
                    object_reader rp((*paths)[k], source, f + ".paths[" + std::to_string(k) + "]");
                    t.paths.push_back({ rp.number_or("excess_range_m", 0.0), rp.number_or("power", 1.0) });
                    rp.finish();
                }
            }
            rt.finish();
            s.d_targets.push_back(t);
        }
        s.d_toi = top.int_or("target_of_interest", 0, 0, limits::max_targets - 1);
    }

    if (top.has("track")) {
        object_reader rt = top.object("track");
        track_spec tr;
        std::tie(tr.range_min_m, tr.range_max_m) = read_pair(rt.require("range_m"), "track.range_m", source);
        const std::string rule = rt.string_or("at_bound", "restart");
        if (rule == "restart")
            tr.at_bound = track_bound::restart;
        else if (rule == "reflect")
            tr.at_bound = track_bound::reflect;
        else
            fail(source, "track.at_bound", "expected \"restart\" or \"reflect\", got \"" + rule + "\"");
        rt.finish();
        s.d_track = tr;
    }
    if (const json* b = top.find("link_budget"))
        s.d_budget = link_budget::from_json(*b, source, "link_budget");
    if (const json* a = top.find("array")) {
        if (a->is_string()) { // a preset's name or a file (scene::load made a relative path the scene folder's)
            try {
                s.d_array = array_geometry::find(a->get<std::string>());
            } catch (const std::invalid_argument& e) {
                fail(source, "array", e.what());
            }
        }
        else
            s.d_array = array_geometry::from_json(*a, source, "array", false);
    }
    if (top.has("clutter")) {
        object_reader rc = top.object("clutter");
        clutter_spec c;
        c.csr_db = rc.number("csr_db");
        if (const auto* ranges = rc.find("ranges_m")) {
            object_reader::checked_array(*ranges, "clutter.ranges_m", source, 1, limits::max_clutter_paths);
            for (size_t i = 0; i < ranges->size(); ++i)
                c.ranges_m.push_back(finite_number((*ranges)[i], "clutter.ranges_m[" + std::to_string(i) + "]", source));
            c.n_paths = static_cast<int>(c.ranges_m.size());
            if (const auto* az = rc.find("azimuths_rad")) {
                object_reader::checked_array(*az, "clutter.azimuths_rad", source, c.ranges_m.size(), c.ranges_m.size());
                for (size_t i = 0; i < az->size(); ++i)
                    c.azimuths_rad.push_back(finite_number((*az)[i], "clutter.azimuths_rad[" + std::to_string(i) + "]", source));
            }
            if (rc.has("paths") || rc.has("range_m"))
                fail(source, "clutter", "give either \"ranges_m\" (fixed scatterers) or \"paths\" and \"range_m\", not both");
        } else {
            c.n_paths = rc.int_or("paths", c.n_paths, 1, limits::max_clutter_paths);
            if (const auto* rr = rc.find("range_m"))
                std::tie(c.range_min_m, c.range_max_m) = read_pair(*rr, "clutter.range_m", source);
        }
        rc.finish();
        s.d_clutter = c;
    }
    top.finish();
    s.validate(source);
    return s;
}

scene scene::load(const std::string& path)
{
    json j = json_read::parse_file(path);
    // A relative library path in a scene file ("classes": "my_classes.json") is read from the
    // scene file's folder when the file is there, so a scene and its library travel together
    // and work from any working directory.
    if (j.is_object() && j.contains("classes") && j["classes"].is_string()) {
        const std::string lib = j["classes"].get<std::string>();
        const auto slash = path.rfind('/');
        if (!lib.empty() && lib.front() != '/' && slash != std::string::npos &&
            detail::names_a_path(lib)) {
            const std::string beside = path.substr(0, slash + 1) + lib;
            if (std::ifstream(beside).good())
                j["classes"] = beside;
        }
    }
    if (j.is_object() && j.contains("array") && j["array"].is_string()) {
        const std::string file = j["array"].get<std::string>();
        const auto slash = path.rfind('/');
        if (!file.empty() && file.front() != '/' && slash != std::string::npos && detail::names_a_path(file))
            j["array"] = path.substr(0, slash + 1) + file;
    }
    return from_json(j, path);
}

scene scene::parse(const std::string& json_text, const std::string& source)
{
    return from_json(json_read::parse_text(json_text, source), source);
}

std::string scene::to_json_string() const { return to_json().dump(); }

void scene::save(const std::string& path) const { json_read::write_file(path, to_json()); }

} // namespace sems
} // namespace gr
