// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: scenes — construction, validation and the JSON file format.
 *
 * File format (DESIGN §4), one of "targets" (fixed) or "random":
 *   {"format": "sems.scene", "version": 1, "fading": "rayleigh" | "none",
 *    "target_of_interest": 0,
 *    "targets": [{"class": "drone", "range_m": 50, "velocity_mps": 7, "power": 1,
 *                 "micro_doppler": {"rate_hz": 100, "amplitude_m": 0.01, "phase_rad": 0},
 *                 "paths": [{"excess_range_m": 0, "power": 1}, {"excess_range_m": 12, "power": 0.3}]}],
 *    "random": {"classes": ["pedestrian", "car", "drone"], "targets": 1, "paths_per_target": 1,
 *               "excess_range_m": [2, 30], "path_power_decay_db": 3, "micro_doppler": true,
 *               "heading": "approaching" | "any"},
 *    "clutter": {"csr_db": 10, "paths": 4, "range_m": [0, 200]}   or   {"csr_db": 10, "ranges_m": [...]}}
 */
#include "core/json_read.h"
#include "core/checks.h"
#include <gnuradio/sems/core/scene.h>
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

void validate_clutter(const clutter_spec& c, const std::string& source)
{
    if (!checks::finite(c.csr_db))
        fail(source, "clutter.csr_db", "must be finite");
    if (c.ranges_m.empty()) {
        if (c.n_paths < 1)
            fail(source, "clutter.paths", "must be >= 1, got " + std::to_string(c.n_paths));
        check_finite_nonneg(c.range_min_m, source, "clutter.range_m[0]");
        check_finite_nonneg(c.range_max_m, source, "clutter.range_m[1]");
        if (c.range_min_m > c.range_max_m)
            fail(source, "clutter.range_m", "min exceeds max");
    } else {
        for (double r : c.ranges_m)
            check_finite_nonneg(r, source, "clutter.ranges_m");
    }
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

namespace {

json range_pair(double lo, double hi) { return json::array({ lo, hi }); }

std::pair<double, double> read_pair(const json& v, const std::string& field, const std::string& source)
{
    if (!v.is_array() || v.size() != 2)
        fail(source, field, "expected [min, max]");
    return { json_read::finite_number(v[0], field, source), json_read::finite_number(v[1], field, source) };
}

} // namespace

scene scene::fixed(std::vector<target_spec> targets, std::optional<clutter_spec> clutter, int toi, fading_kind fading)
{
    scene s;
    s.d_targets = std::move(targets);
    s.d_clutter = std::move(clutter);
    s.d_toi = toi;
    s.d_fading = fading;
    s.validate("fixed scene");
    return s;
}

scene scene::random(random_spec spec, std::optional<clutter_spec> clutter, fading_kind fading)
{
    scene s;
    s.d_random = std::move(spec);
    s.d_clutter = std::move(clutter);
    s.d_fading = fading;
    s.validate("random scene");
    return s;
}

std::vector<target_class> scene::label_classes() const
{
    if (d_random)
        return d_random->classes;
    return { d_targets.at(d_toi).cls };
}

void scene::validate(const std::string& source) const
{
    if (d_clutter)
        validate_clutter(*d_clutter, source);
    if (d_random) {
        const auto& r = *d_random;
        if (r.classes.empty())
            fail(source, "random.classes", "needs at least one class");
        auto sorted = r.classes;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
            fail(source, "random.classes", "lists a class twice");
        if (r.n_targets < 1)
            fail(source, "random.targets", "must be >= 1, got " + std::to_string(r.n_targets));
        if (r.paths_per_target < 1)
            fail(source, "random.paths_per_target", "must be >= 1, got " + std::to_string(r.paths_per_target));
        check_finite_nonneg(r.excess_range_min_m, source, "random.excess_range_m[0]");
        check_finite_nonneg(r.excess_range_max_m, source, "random.excess_range_m[1]");
        if (r.excess_range_min_m > r.excess_range_max_m)
            fail(source, "random.excess_range_m", "min exceeds max");
        check_finite_nonneg(r.path_power_decay_db, source, "random.path_power_decay_db");
        if (r.heading != heading_kind::approaching && r.heading != heading_kind::any)
            fail(source, "random.heading", "unknown heading kind " + std::to_string(static_cast<int>(r.heading)));
        return;
    }
    if (d_targets.empty())
        fail(source, "targets", "a fixed scene needs at least one target");
    if (d_toi < 0 || d_toi >= static_cast<int>(d_targets.size()))
        fail(source, "target_of_interest",
             "is " + std::to_string(d_toi) + " but the scene has " + std::to_string(d_targets.size()) + " targets");
    for (size_t i = 0; i < d_targets.size(); ++i) {
        const auto& t = d_targets[i];
        const std::string f = "targets[" + std::to_string(i) + "]";
        class_info(t.cls); // throws on an unknown class
        check_finite_nonneg(t.range_m, source, f + ".range_m");
        if (!checks::finite(t.velocity_mps))
            fail(source, f + ".velocity_mps", "must be finite");
        check_positive(t.power, source, f + ".power");
        if (t.md) {
            check_finite_nonneg(t.md->rate_hz, source, f + ".micro_doppler.rate_hz");
            check_finite_nonneg(t.md->amplitude_m, source, f + ".micro_doppler.amplitude_m");
            if (!checks::finite(t.md->phase_rad))
                fail(source, f + ".micro_doppler.phase_rad", "must be finite");
        }
        if (t.paths.empty())
            fail(source, f + ".paths", "needs at least one path");
        if (t.paths[0].excess_range_m != 0.0)
            fail(source, f + ".paths[0].excess_range_m", "the first path is the direct path and must be 0");
        for (size_t k = 0; k < t.paths.size(); ++k) {
            const std::string pf = f + ".paths[" + std::to_string(k) + "]";
            check_finite_nonneg(t.paths[k].excess_range_m, source, pf + ".excess_range_m");
            check_positive(t.paths[k].power, source, pf + ".power");
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
        for (auto c : r.classes)
            classes.push_back(class_info(c).name);
        j["random"] = { { "classes", classes },
                        { "targets", r.n_targets },
                        { "paths_per_target", r.paths_per_target },
                        { "excess_range_m", range_pair(r.excess_range_min_m, r.excess_range_max_m) },
                        { "path_power_decay_db", r.path_power_decay_db },
                        { "micro_doppler", r.micro_doppler },
                        { "heading", heading_name(r.heading) } };
    } else {
        j["target_of_interest"] = d_toi;
        json targets = json::array();
        for (const auto& t : d_targets) {
            json paths = json::array();
            for (const auto& p : t.paths)
                paths.push_back({ { "excess_range_m", p.excess_range_m }, { "power", p.power } });
            json jt = { { "class", class_info(t.cls).name },
                        { "range_m", t.range_m },
                        { "velocity_mps", t.velocity_mps },
                        { "power", t.power },
                        { "paths", paths } };
            if (t.md)
                jt["micro_doppler"] = { { "rate_hz", t.md->rate_hz },
                                        { "amplitude_m", t.md->amplitude_m },
                                        { "phase_rad", t.md->phase_rad } };
            targets.push_back(jt);
        }
        j["targets"] = targets;
    }
    if (d_clutter) {
        const auto& c = *d_clutter;
        json jc = { { "csr_db", c.csr_db } };
        if (c.ranges_m.empty()) {
            jc["paths"] = c.n_paths;
            jc["range_m"] = range_pair(c.range_min_m, c.range_max_m);
        } else {
            jc["ranges_m"] = c.ranges_m;
        }
        j["clutter"] = jc;
    }
    return j;
}

scene scene::from_json(const json& j, const std::string& source)
{
    using namespace json_read;
    check_format(j, format_name, format_version, source);
    static const std::vector<std::string> known = { "format", "version", "fading", "target_of_interest",
                                                    "targets", "random", "clutter", "description" };
    for (auto it = j.begin(); it != j.end(); ++it)
        if (std::find(known.begin(), known.end(), it.key()) == known.end())
            fail(source, it.key(), "unknown key");

    scene s;
    const std::string fading = j.contains("fading") ? string(j["fading"], "fading", source) : "rayleigh";
    if (fading == "rayleigh")
        s.d_fading = fading_kind::rayleigh;
    else if (fading == "none")
        s.d_fading = fading_kind::none;
    else
        fail(source, "fading", "expected \"rayleigh\" or \"none\", got \"" + fading + "\"");

    auto class_of = [&](const json& v, const std::string& field) {
        try {
            return class_from_name(string(v, field, source));
        } catch (const std::invalid_argument& e) {
            if (std::string(e.what()).rfind(source, 0) == 0)
                throw;
            fail(source, field, e.what());
        }
    };

    if (j.contains("targets") == j.contains("random"))
        fail(source, "", "give exactly one of \"targets\" (a fixed scene) or \"random\"");

    if (j.contains("random")) {
        const auto& r = j["random"];
        if (!r.is_object())
            fail(source, "random", "expected a JSON object");
        random_spec spec;
        if (r.contains("classes")) {
            if (!r["classes"].is_array())
                fail(source, "random.classes", "expected a list of class names");
            spec.classes.clear();
            for (size_t i = 0; i < r["classes"].size(); ++i)
                spec.classes.push_back(class_of(r["classes"][i], "random.classes[" + std::to_string(i) + "]"));
        }
        if (r.contains("targets"))
            spec.n_targets = static_cast<int>(integer(r["targets"], "random.targets", source));
        if (r.contains("paths_per_target"))
            spec.paths_per_target = static_cast<int>(integer(r["paths_per_target"], "random.paths_per_target", source));
        if (r.contains("excess_range_m"))
            std::tie(spec.excess_range_min_m, spec.excess_range_max_m) =
                read_pair(r["excess_range_m"], "random.excess_range_m", source);
        spec.path_power_decay_db = number_or(r, "path_power_decay_db", spec.path_power_decay_db, source);
        if (r.contains("micro_doppler")) {
            if (!r["micro_doppler"].is_boolean())
                fail(source, "random.micro_doppler", "expected true or false");
            spec.micro_doppler = r["micro_doppler"].get<bool>();
        }
        if (r.contains("heading")) {
            const std::string h = string(r["heading"], "random.heading", source);
            try {
                spec.heading = heading_from_name(h);
            } catch (const std::invalid_argument& e) {
                fail(source, "random.heading", e.what());
            }
        }
        s.d_random = spec;
    } else {
        const auto& list = j["targets"];
        if (!list.is_array())
            fail(source, "targets", "expected a list of targets");
        for (size_t i = 0; i < list.size(); ++i) {
            const auto& jt = list[i];
            const std::string f = "targets[" + std::to_string(i) + "]";
            if (!jt.is_object())
                fail(source, f, "expected a JSON object");
            target_spec t;
            t.cls = class_of(require(jt, "class", source), f + ".class");
            t.range_m = finite_number(require(jt, "range_m", source), f + ".range_m", source);
            t.velocity_mps = finite_number(require(jt, "velocity_mps", source), f + ".velocity_mps", source);
            t.power = number_or(jt, "power", 1.0, source);
            if (jt.contains("micro_doppler")) {
                const auto& md = jt["micro_doppler"];
                micro_doppler m;
                m.rate_hz = finite_number(require(md, "rate_hz", source), f + ".micro_doppler.rate_hz", source);
                m.amplitude_m = md.contains("amplitude_m")
                                    ? finite_number(md["amplitude_m"], f + ".micro_doppler.amplitude_m", source)
                                    : class_info(t.cls).md_amplitude_m;
                m.phase_rad = number_or(md, "phase_rad", 0.0, source);
                t.md = m;
            }
            if (jt.contains("paths")) {
                const auto& paths = jt["paths"];
                if (!paths.is_array())
                    fail(source, f + ".paths", "expected a list of paths");
                t.paths.clear();
                for (size_t k = 0; k < paths.size(); ++k) {
                    const std::string pf = f + ".paths[" + std::to_string(k) + "]";
                    if (!paths[k].is_object())
                        fail(source, pf, "expected a JSON object");
                    t.paths.push_back({ number_or(paths[k], "excess_range_m", 0.0, source),
                                        number_or(paths[k], "power", 1.0, source) });
                }
            }
            s.d_targets.push_back(t);
        }
        if (j.contains("target_of_interest"))
            s.d_toi = static_cast<int>(integer(j["target_of_interest"], "target_of_interest", source));
    }

    if (j.contains("clutter")) {
        const auto& jc = j["clutter"];
        if (!jc.is_object())
            fail(source, "clutter", "expected a JSON object");
        clutter_spec c;
        c.csr_db = finite_number(require(jc, "csr_db", source), "clutter.csr_db", source);
        if (jc.contains("ranges_m")) {
            if (!jc["ranges_m"].is_array() || jc["ranges_m"].empty())
                fail(source, "clutter.ranges_m", "expected a non-empty list of ranges");
            for (const auto& r : jc["ranges_m"])
                c.ranges_m.push_back(finite_number(r, "clutter.ranges_m", source));
            c.n_paths = static_cast<int>(c.ranges_m.size());
        } else {
            if (jc.contains("paths"))
                c.n_paths = static_cast<int>(integer(jc["paths"], "clutter.paths", source));
            if (jc.contains("range_m"))
                std::tie(c.range_min_m, c.range_max_m) = read_pair(jc["range_m"], "clutter.range_m", source);
        }
        s.d_clutter = c;
    }
    s.validate(source);
    return s;
}

scene scene::load(const std::string& path) { return from_json(json_read::parse_file(path), path); }

scene scene::parse(const std::string& json_text, const std::string& source)
{
    return from_json(json_read::parse_text(json_text, source), source);
}

std::string scene::to_json_string() const { return to_json().dump(); }

void scene::save(const std::string& path) const { json_read::write_file(path, to_json()); }

} // namespace sems
} // namespace gr
