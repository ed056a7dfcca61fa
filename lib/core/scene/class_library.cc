// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: class libraries (class_library.h).
 *
 * File format:
 *   {"format": "sems.classes", "version": 1, "name": "kinematic", "description": "...",
 *    "classes": [{"name": "adult", "description": "...", "range_m": [5, 150], "speed_mps": [0.5, 2.0],
 *                 "micro_motion": {"model": "walker", "height_m": [1.6, 1.95]},
 *                 "azimuth_rad": [-0.5, 0.5], "elevation_rad": 0}, ...]}   (both optional)
 * Every micro-motion value is a number or an interval [min, max] drawn uniformly per frame;
 * a phase not given is drawn over [0, 2π).
 */
#include "core/common/checks.h"
#include "core/common/math_constants.h"
#include "core/common/json_object.h"
#include "core/scene/micro_motion_params.h"
#include "core/common/named_files.h"
#include "core/scene/walker_scatterers.h"
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/common/limits.h>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#ifndef SEMS_SOURCE_CLASSES_DIR
#define SEMS_SOURCE_CLASSES_DIR ""
#endif
#ifndef SEMS_INSTALLED_CLASSES_DIR
#define SEMS_INSTALLED_CLASSES_DIR ""
#endif

namespace gr {
namespace sems {

using json = nlohmann::json;
using json_read::fail;
using json_read::object_reader;

namespace {


std::pair<double, double> read_interval(object_reader& r, const char* key)
{
    const auto p = detail::read_number_or_interval(r.require(key), r.field(key), r.source());
    return { p.lo, p.hi };
}

double sinusoid_peak(const detail::motion_template& t, detail::endpoint e)
{
    const auto m = detail::sinusoid_at(t, e);
    return two_pi * m.rate_hz * m.amplitude_m;
}

} // namespace

std::string class_definition::motion_model() const { return motion ? motion->model : "none"; }

double class_definition::max_extent_m() const
{
    if (!motion)
        return 0.0;
    if (motion->model == "sinusoid")
        return detail::sinusoid_at(*motion, detail::endpoint::high).amplitude_m;
    double e = 0.0;
    for (auto end : { detail::endpoint::low, detail::endpoint::high })
        e = std::max(e, micro_motion_extent_m(detail::motion_at(*motion, end)));
    return e;
}

double class_definition::max_sinusoid_speed_mps() const
{
    if (!motion || motion->model != "sinusoid")
        return 0.0;
    return std::max(sinusoid_peak(*motion, detail::endpoint::low), sinusoid_peak(*motion, detail::endpoint::high));
}

double class_definition::max_scatterer_speed_mps() const
{
    double micro = max_sinusoid_speed_mps();
    if (motion && motion->model == "walker") {
        // Not the corners: a walker's peak speed can be largest inside its height interval.
        const double h0 = std::get<walker_motion>(detail::motion_at(*motion, detail::endpoint::low)).height_m;
        const double h1 = std::get<walker_motion>(detail::motion_at(*motion, detail::endpoint::high)).height_m;
        micro = detail::walker_peak_speed_mps(std::min(h0, h1), std::max(h0, h1), speed_max_mps);
    } else if (motion && motion->model != "sinusoid") {
        for (auto end : { detail::endpoint::low, detail::endpoint::high })
            micro = std::max(micro, micro_motion_peak_speed_mps(detail::motion_at(*motion, end), speed_max_mps));
    }
    return speed_max_mps + micro;
}

std::shared_ptr<const class_library> class_library::paper()
{
    // The paper's table (docs/design.md §1). Micro-Doppler displacements: pedestrian 0.10 m (limb
    // swing), drone 0.01 m (rotor blades); every class stays inside ±500 Hz at 3 GHz, 1 ms.
    // Mean RCS (used with a link budget only): indicative microwave values, a person about
    // 1 m², a car 10–100 m², a small drone 0.01–0.1 m².
    static const std::shared_ptr<const class_library> lib = [] {
        const json j = {
            { "format", format_name },
            { "version", format_version },
            { "name", "paper" },
            { "description", "The paper's three classes: the sinusoidal micro-Doppler of a point target." },
            { "classes",
              json::array(
                  { { { "name", "pedestrian" },
                      { "range_m", { 0.0, 200.0 } },
                      { "speed_mps", { 0.0, 2.0 } },
                      { "rcs_dbsm", { -3.0, 0.0 } },
                      { "micro_motion", { { "model", "sinusoid" }, { "rate_hz", { 1.0, 3.0 } }, { "amplitude_m", 0.10 } } } },
                    { { "name", "car" }, { "range_m", { 0.0, 200.0 } }, { "speed_mps", { 10.0, 20.0 } }, { "rcs_dbsm", { 10.0, 20.0 } } },
                    { { "name", "drone" },
                      { "range_m", { 0.0, 200.0 } },
                      { "speed_mps", { 5.0, 10.0 } },
                      { "rcs_dbsm", { -20.0, -10.0 } },
                      { "micro_motion",
                        { { "model", "sinusoid" }, { "rate_hz", { 80.0, 120.0 } }, { "amplitude_m", 0.01 } } } } }) }
        };
        return from_json(j, "the built-in paper class library");
    }();
    return lib;
}

std::shared_ptr<const class_library> class_library::find(const std::string& name_or_path)
{
    if (name_or_path.empty() || name_or_path == "paper")
        return paper();
    std::string searched;
    const std::string path = detail::find_named_file(name_or_path, "SEMS_CLASSES_PATH", "classes",
                                                     { SEMS_SOURCE_CLASSES_DIR, SEMS_INSTALLED_CLASSES_DIR }, searched);
    if (!path.empty())
        return load(path);
    throw std::invalid_argument("class library \"" + name_or_path + "\": not built in (paper) and no such file (searched " +
                                searched + "; SEMS_CLASSES_PATH adds folders)");
}

std::shared_ptr<const class_library> class_library::load(const std::string& path)
{
    return from_json(json_read::parse_file(path), path);
}

std::shared_ptr<const class_library> class_library::from_json(const json& j, const std::string& source)
{
    json_read::check_format(j, format_name, format_version, source);
    object_reader top(j, source);
    top.allow("format");
    top.allow("version");
    auto lib = std::make_shared<class_library>();
    lib->d_name = top.string("name");
    if (lib->d_name.empty())
        fail(source, "name", "must not be empty");
    lib->d_description = top.string_or("description", "");
    const json& list = top.array("classes", 1, limits::max_classes);
    for (size_t i = 0; i < list.size(); ++i) {
        object_reader r(list[i], source, "classes[" + std::to_string(i) + "]");
        class_definition c;
        c.name = r.string("name");
        const std::string where = "classes[" + std::to_string(i) + "] (\"" + c.name + "\")";
        if (c.name.empty())
            fail(source, r.field("name"), "must not be empty");
        for (const auto& other : lib->d_classes)
            if (other.name == c.name)
                fail(source, r.field("name"), "class \"" + c.name + "\" is defined twice");
        c.description = r.string_or("description", "");
        std::tie(c.range_min_m, c.range_max_m) = read_interval(r, "range_m");
        std::tie(c.speed_min_mps, c.speed_max_mps) = read_interval(r, "speed_mps");
        if (!checks::non_negative(c.range_min_m))
            fail(source, where + ".range_m", "must be >= 0 m, got " + std::to_string(c.range_min_m));
        if (!checks::non_negative(c.speed_min_mps))
            fail(source, where + ".speed_mps", "must be >= 0 m/s (the heading sets the direction), got " +
                                                   std::to_string(c.speed_min_mps));
        if (r.has("rcs_dbsm")) // uniform in dB per frame where a link budget uses it
            std::tie(c.rcs_min_dbsm, c.rcs_max_dbsm) = read_interval(r, "rcs_dbsm");
        if (r.has("azimuth_rad")) { // the line of sight's, in place of the scene's interval
            std::tie(c.azimuth_min_rad, c.azimuth_max_rad) = read_interval(r, "azimuth_rad");
            if (!(c.azimuth_min_rad >= -M_PI && c.azimuth_max_rad <= M_PI))
                fail(source, where + ".azimuth_rad", "must lie in [-pi, pi] rad, got [" +
                                                         checks::text(c.azimuth_min_rad) + ", " +
                                                         checks::text(c.azimuth_max_rad) + "]");
        }
        if (r.has("elevation_rad")) {
            std::tie(c.elevation_min_rad, c.elevation_max_rad) = read_interval(r, "elevation_rad");
            if (!(c.elevation_min_rad >= -M_PI / 2 && c.elevation_max_rad <= M_PI / 2))
                fail(source, where + ".elevation_rad", "must lie in [-pi/2, pi/2] rad, got [" +
                                                           checks::text(c.elevation_min_rad) + ", " +
                                                           checks::text(c.elevation_max_rad) + "]");
        }
        if (const json* m = r.find("micro_motion")) {
            c.motion = std::make_shared<const detail::motion_template>(
                detail::read_motion_template(*m, source, where + ".micro_motion", true, c.speed_min_mps, c.speed_max_mps));
            if (c.motion->model == "walker")
                for (auto end : { detail::endpoint::low, detail::endpoint::high }) {
                    const auto w = std::get<walker_motion>(detail::motion_at(*c.motion, end));
                    for (double v : { c.speed_min_mps, c.speed_max_mps })
                        detail::walker_check_speed(w.height_m, v, source, where + ".speed_mps");
                }
        }
        // The rule a scene's interval follows (scene.cc).
        if (c.has_elevation() && (c.elevation_min_rad != 0.0 || c.elevation_max_rad != 0.0) &&
            !detail::modelled_from_any_elevation(c.motion_model()))
            fail(source, where + ".elevation_rad",
                 "a " + c.motion_model() + " class is modelled as seen from the ground plane: only " +
                     detail::models_from_any_elevation + " classes take an elevation other than 0");
        r.finish();
        lib->d_classes.push_back(std::move(c));
    }
    top.finish();
    return lib;
}

json class_library::to_json() const
{
    json classes = json::array();
    for (const auto& c : d_classes) {
        json jc = { { "name", c.name },
                    { "range_m", { c.range_min_m, c.range_max_m } },
                    { "speed_mps", { c.speed_min_mps, c.speed_max_mps } } };
        if (!c.description.empty())
            jc["description"] = c.description;
        if (c.has_rcs())
            jc["rcs_dbsm"] = c.rcs_min_dbsm == c.rcs_max_dbsm ? json(c.rcs_min_dbsm) : json({ c.rcs_min_dbsm, c.rcs_max_dbsm });
        const auto value_or_interval = [](double lo, double hi) { return lo == hi ? json(lo) : json({ lo, hi }); };
        if (c.has_azimuth())
            jc["azimuth_rad"] = value_or_interval(c.azimuth_min_rad, c.azimuth_max_rad);
        if (c.has_elevation())
            jc["elevation_rad"] = value_or_interval(c.elevation_min_rad, c.elevation_max_rad);
        if (c.motion)
            jc["micro_motion"] = c.motion->source_json;
        classes.push_back(jc);
    }
    json j = { { "format", format_name }, { "version", format_version }, { "name", d_name }, { "classes", classes } };
    if (!d_description.empty())
        j["description"] = d_description;
    return j;
}

const class_definition& class_library::at(int id) const
{
    if (id < 0 || id >= size())
        throw std::invalid_argument("class library " + d_name + ": unknown class id " + std::to_string(id) + " (it has " +
                                    std::to_string(size()) + " classes)");
    return d_classes[static_cast<size_t>(id)];
}

int class_library::id_of(const std::string& name) const
{
    for (size_t i = 0; i < d_classes.size(); ++i)
        if (d_classes[i].name == name)
            return static_cast<int>(i);
    std::string known;
    for (const auto& c : d_classes)
        known += (known.empty() ? "" : ", ") + c.name;
    throw std::invalid_argument("unknown target class \"" + name + "\" in class library " + d_name + " (known: " + known +
                                ")");
}

std::vector<std::string> class_library::class_names() const
{
    std::vector<std::string> names;
    for (const auto& c : d_classes)
        names.push_back(c.name);
    return names;
}

namespace {
json without_descriptions(json j)
{
    j.erase("description");
    for (auto& c : j["classes"]) {
        c.erase("description");
        c.erase("rcs_dbsm"); // a power scale: the classes move alike whatever their RCS
    }
    return j;
}
} // namespace

bool class_library::same_classes(const class_library& other) const { return difference(other).empty(); }

std::string class_library::difference(const class_library& other) const
{
    const json a = without_descriptions(to_json()), b = without_descriptions(other.to_json());
    if (a["classes"] == b["classes"])
        return "";
    if (a["classes"].size() != b["classes"].size())
        return "library " + d_name + " has " + std::to_string(size()) + " classes, library " + other.d_name + " has " +
               std::to_string(other.size());
    for (size_t i = 0; i < a["classes"].size(); ++i)
        if (a["classes"][i] != b["classes"][i])
            return "class " + std::to_string(i) + " differs: " + a["classes"][i].dump() + " in " + d_name + " against " +
                   b["classes"][i].dump() + " in " + other.d_name;
    return "";
}

} // namespace sems
} // namespace gr
