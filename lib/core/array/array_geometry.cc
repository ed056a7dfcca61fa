// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: an antenna array as data — ULA, URA or positions, checked (array_geometry.h). */
#include "core/common/checks.h"
#include "core/common/json_object.h"
#include "core/common/named_files.h"
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/common/limits.h>
#include <cmath>
#include <string>

#ifndef SEMS_SOURCE_ARRAYS_DIR
#define SEMS_SOURCE_ARRAYS_DIR ""
#endif
#ifndef SEMS_INSTALLED_ARRAYS_DIR
#define SEMS_INSTALLED_ARRAYS_DIR ""
#endif

namespace gr {
namespace sems {

using json = nlohmann::json;
using json_read::fail;
using json_read::object_reader;

namespace {

std::string num(double x) { return checks::text(x); }

std::string where(const position3& p)
{
    return "(" + num(p[0]) + ", " + num(p[1]) + ", " + num(p[2]) + ") m";
}

// Every element finite, at most limits::max_array_elements, no two closer than the separation.
// Quadratic in K: at most 1024² / 2 distances, once per array.
void check_elements(const std::vector<position3>& e, const std::string& source, const std::string& field)
{
    if (e.empty())
        fail(source, field, "needs at least one element");
    if (e.size() > static_cast<size_t>(limits::max_array_elements))
        fail(source, field, "has " + std::to_string(e.size()) + " elements, more than the " +
                                std::to_string(limits::max_array_elements) + " limits.h allows");
    for (size_t k = 0; k < e.size(); ++k)
        for (int c = 0; c < 3; ++c)
            if (!checks::finite(e[k][c]))
                fail(source, field + "[" + std::to_string(k) + "]", "position must be finite");
    for (size_t a = 0; a < e.size(); ++a)
        for (size_t b = a + 1; b < e.size(); ++b) {
            const double d = std::hypot(e[a][0] - e[b][0], e[a][1] - e[b][1], e[a][2] - e[b][2]);
            if (d < array_geometry::min_element_separation_m)
                fail(source, field,
                     "elements " + std::to_string(a) + " and " + std::to_string(b) + " coincide at " + where(e[a]) +
                         " (closer than " + num(array_geometry::min_element_separation_m) + " m)");
        }
}

void check_count(long long count, const std::string& source, const std::string& field)
{
    if (count < 1 || count > limits::max_array_elements)
        fail(source, field, "must be in [1, " + std::to_string(limits::max_array_elements) + "] (limits.h), got " +
                                std::to_string(count));
}

void check_spacing(double d, const std::string& source, const std::string& field)
{
    if (!checks::positive(d))
        fail(source, field, "must be a finite spacing > 0 m, got " + num(d));
}

std::vector<position3> grid(int columns, int rows, double dy, double dz)
{
    std::vector<position3> e;
    e.reserve(size_t(columns) * rows);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < columns; ++c)
            e.push_back({ 0.0, (c - 0.5 * (columns - 1)) * dy, (r - 0.5 * (rows - 1)) * dz });
    return e;
}

std::vector<position3> read_positions(const json& v, const std::string& source, const std::string& field)
{
    object_reader::checked_array(v, field, source, 1, size_t(limits::max_array_elements));
    std::vector<position3> e;
    e.reserve(v.size());
    for (size_t k = 0; k < v.size(); ++k) {
        const std::string f = field + "[" + std::to_string(k) + "]";
        object_reader::checked_array(v[k], f, source, 3, 3);
        e.push_back({ json_read::finite_number(v[k][0], f + "[0]", source),
                      json_read::finite_number(v[k][1], f + "[1]", source),
                      json_read::finite_number(v[k][2], f + "[2]", source) });
    }
    return e;
}

// {"ula": {...}} | {"ura": {...}} | {"positions_m": [...]}: exactly one.
std::vector<position3> read_elements(object_reader r)
{
    const json* ula = r.find("ula");
    const json* ura = r.find("ura");
    const json* pos = r.find("positions_m");
    r.finish();
    if ((ula != nullptr) + (ura != nullptr) + (pos != nullptr) != 1)
        fail(r.source(), r.path(), "give exactly one of ula, ura, positions_m");
    if (pos)
        return read_positions(*pos, r.source(), r.field("positions_m"));
    if (ula) {
        object_reader u(*ula, r.source(), r.field("ula"));
        const long long k = json_read::integer(u.require("elements"), u.field("elements"), r.source());
        check_count(k, r.source(), u.field("elements"));
        const double d = u.number("spacing_m");
        check_spacing(d, r.source(), u.field("spacing_m"));
        u.finish();
        return grid(static_cast<int>(k), 1, d, 1.0);
    }
    object_reader u(*ura, r.source(), r.field("ura"));
    const long long c = json_read::integer(u.require("columns"), u.field("columns"), r.source());
    const long long rows = json_read::integer(u.require("rows"), u.field("rows"), r.source());
    check_count(c, r.source(), u.field("columns"));
    check_count(rows, r.source(), u.field("rows"));
    if (c * rows > limits::max_array_elements)
        fail(r.source(), r.field("ura"), "columns × rows = " + std::to_string(c * rows) + " elements, more than the " +
                                              std::to_string(limits::max_array_elements) + " limits.h allows");
    const json& s = u.require("spacing_m");
    double dy, dz;
    if (s.is_array()) {
        object_reader::checked_array(s, u.field("spacing_m"), r.source(), 2, 2);
        dy = json_read::finite_number(s[0], u.field("spacing_m[0]"), r.source());
        dz = json_read::finite_number(s[1], u.field("spacing_m[1]"), r.source());
    } else {
        dy = dz = json_read::finite_number(s, u.field("spacing_m"), r.source());
    }
    check_spacing(dy, r.source(), u.field("spacing_m") + (s.is_array() ? "[0]" : ""));
    check_spacing(dz, r.source(), u.field("spacing_m") + (s.is_array() ? "[1]" : ""));
    u.finish();
    return grid(static_cast<int>(c), static_cast<int>(rows), dy, dz);
}

json positions_json(const std::vector<position3>& e)
{
    json a = json::array();
    for (const auto& p : e)
        a.push_back({ p[0], p[1], p[2] });
    return a;
}

} // namespace

std::string element_pattern_name(element_pattern p)
{
    switch (p) {
    case element_pattern::isotropic:
        return "isotropic";
    case element_pattern::cosine:
        return "cosine";
    }
    throw std::invalid_argument("unknown element pattern " + std::to_string(static_cast<int>(p)));
}

element_pattern element_pattern_from_name(const std::string& name)
{
    if (name == "isotropic")
        return element_pattern::isotropic;
    if (name == "cosine")
        return element_pattern::cosine;
    throw std::invalid_argument("unknown element pattern \"" + name + "\" (known: isotropic, cosine)");
}

array_geometry::array_geometry() : d_rx{ position3{ 0.0, 0.0, 0.0 } }, d_tx{ position3{ 0.0, 0.0, 0.0 } } {}

array_geometry array_geometry::ula(int elements, double spacing_m, element_pattern pattern)
{
    check_count(elements, "array_geometry::ula", "elements");
    check_spacing(spacing_m, "array_geometry::ula", "spacing_m");
    return from_positions(grid(elements, 1, spacing_m, 1.0), { position3{ 0.0, 0.0, 0.0 } }, pattern,
                          "array_geometry::ula");
}

array_geometry array_geometry::ura(int columns, int rows, double spacing_y_m, double spacing_z_m, element_pattern pattern)
{
    const std::string src = "array_geometry::ura";
    check_count(columns, src, "columns");
    check_count(rows, src, "rows");
    if (static_cast<long long>(columns) * rows > limits::max_array_elements)
        fail(src, "columns × rows", std::to_string(static_cast<long long>(columns) * rows) +
                                        " elements, more than the " + std::to_string(limits::max_array_elements) +
                                        " limits.h allows");
    check_spacing(spacing_y_m, src, "spacing_y_m");
    check_spacing(spacing_z_m, src, "spacing_z_m");
    return from_positions(grid(columns, rows, spacing_y_m, spacing_z_m), { position3{ 0.0, 0.0, 0.0 } }, pattern, src);
}

array_geometry array_geometry::from_positions(std::vector<position3> receive,
                                              std::vector<position3> transmit,
                                              element_pattern pattern,
                                              const std::string& source)
{
    check_elements(receive, source, "receive");
    check_elements(transmit, source, "transmit");
    element_pattern_name(pattern); // refuses a value outside the enumeration
    array_geometry a;
    a.d_rx = std::move(receive);
    a.d_tx = std::move(transmit);
    a.d_pattern = pattern;
    return a;
}

array_geometry array_geometry::load(const std::string& path) { return from_json(json_read::parse_file(path), path); }

array_geometry array_geometry::find(const std::string& name_or_path)
{
    std::string searched;
    const std::string path = detail::find_named_file(name_or_path, "SEMS_ARRAYS_PATH", "arrays",
                                                     { SEMS_SOURCE_ARRAYS_DIR, SEMS_INSTALLED_ARRAYS_DIR }, searched);
    if (!path.empty())
        return load(path);
    throw std::invalid_argument("array \"" + name_or_path + "\": no such file (searched " + searched +
                                "; SEMS_ARRAYS_PATH adds folders)");
}

array_geometry array_geometry::from_json(const json& j, const std::string& source, const std::string& field, bool top_level)
{
    object_reader r = top_level ? json_read::file_object(j, format_name, format_version, source)
                                : object_reader(j, source, field);
    const auto rx = read_elements(r.object("receive"));
    std::vector<position3> tx{ position3{ 0.0, 0.0, 0.0 } };
    if (r.has("transmit"))
        tx = read_elements(r.object("transmit"));
    (void)r.string_or("description", ""); // free text for people (the presets have one)
    element_pattern pattern = element_pattern::isotropic;
    if (r.has("pattern")) {
        const std::string name = r.string("pattern");
        try {
            pattern = element_pattern_from_name(name);
        } catch (const std::invalid_argument& e) {
            fail(source, r.field("pattern"), e.what());
        }
    }
    r.finish();
    check_elements(rx, source, r.field("receive"));
    check_elements(tx, source, r.field("transmit"));
    return from_positions(rx, tx, pattern, source);
}

json array_geometry::to_json() const
{
    return { { "format", format_name },
             { "version", format_version },
             { "receive", { { "positions_m", positions_json(d_rx) } } },
             { "transmit", { { "positions_m", positions_json(d_tx) } } },
             { "pattern", element_pattern_name(d_pattern) } };
}

void array_geometry::save(const std::string& path) const { json_read::write_file(path, to_json()); }

bool array_geometry::is_single_antenna() const
{
    const position3 origin{ 0.0, 0.0, 0.0 };
    return d_rx.size() == 1 && d_tx.size() == 1 && d_rx[0] == origin && d_tx[0] == origin &&
           d_pattern == element_pattern::isotropic;
}

double array_geometry::reach_m() const
{
    double r = 0.0;
    for (const auto* set : { &d_rx, &d_tx })
        for (const auto& p : *set)
            r = std::max(r, std::hypot(p[0], p[1], p[2]));
    return r;
}

std::vector<position3> array_geometry::virtual_offsets() const
{
    std::vector<position3> o;
    o.reserve(d_rx.size() * d_tx.size());
    for (const auto& p : d_rx)
        for (const auto& q : d_tx)
            o.push_back({ p[0] + q[0], p[1] + q[1], p[2] + q[2] });
    return o;
}

bool operator==(const array_geometry& a, const array_geometry& b)
{
    return a.receive() == b.receive() && a.transmit() == b.transmit() && a.pattern() == b.pattern();
}

} // namespace sems
} // namespace gr
