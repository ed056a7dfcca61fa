// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: validated reads from parsed JSON (internal).
 *
 * Every reader of a project file (mask, scene, bundle) goes through these, so a bad
 * field always produces the same kind of message: "<source>: <field>: <problem>".
 */
#ifndef INCLUDED_SEMS_LIB_CORE_JSON_READ_H
#define INCLUDED_SEMS_LIB_CORE_JSON_READ_H

#include "core/common/checks.h"
#include <nlohmann/json.hpp>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace gr {
namespace sems {
namespace json_read {

[[noreturn]] inline void fail(const std::string& source, const std::string& field, const std::string& problem)
{
    throw std::invalid_argument(source + ": " + (field.empty() ? "" : field + ": ") + problem);
}

// Parses text; a syntax error names the source.
inline nlohmann::json parse_text(const std::string& text, const std::string& source)
{
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        // parse_error, and out_of_range for a number beyond double (61e394): found by fuzz_mask.
        fail(source, "", std::string("not valid JSON (") + e.what() + ")");
    }
}

inline nlohmann::json parse_file(const std::string& path)
{
    std::ifstream in(path);
    if (!in)
        fail(path, "", "cannot open file");
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_text(ss.str(), path);
}

inline void write_file(const std::string& path, const nlohmann::json& j)
{
    std::ofstream out(path);
    if (!out)
        fail(path, "", "cannot open file for writing");
    out << j.dump(2) << "\n";
    if (!out)
        fail(path, "", "write failed");
}

inline const nlohmann::json& require(const nlohmann::json& j, const char* key, const std::string& source)
{
    if (!j.is_object())
        fail(source, "", "expected a JSON object");
    auto it = j.find(key);
    if (it == j.end())
        fail(source, key, "missing");
    return *it;
}

inline double finite_number(const nlohmann::json& v, const std::string& field, const std::string& source)
{
    if (!v.is_number())
        fail(source, field, "expected a number, got " + v.dump());
    const double x = v.get<double>();
    if (!checks::finite(x))
        fail(source, field, "must be finite");
    return x;
}

inline double number_or(const nlohmann::json& j, const char* key, double fallback, const std::string& source)
{
    auto it = j.find(key);
    return it == j.end() ? fallback : finite_number(*it, key, source);
}

inline long long integer(const nlohmann::json& v, const std::string& field, const std::string& source)
{
    if (!v.is_number_integer())
        fail(source, field, "expected an integer, got " + v.dump());
    // Beyond 64-bit signed, get<long long>() would wrap: refuse before the cast.
    if (v.is_number_unsigned() && v.get<unsigned long long>() > 9223372036854775807ULL)
        fail(source, field, "integer " + v.dump() + " is out of range");
    return v.get<long long>();
}

inline std::string string(const nlohmann::json& v, const std::string& field, const std::string& source)
{
    if (!v.is_string())
        fail(source, field, "expected a string, got " + v.dump());
    return v.get<std::string>();
}

// Checks {"format": name, "version": version}.
inline void check_format(const nlohmann::json& j, const char* name, int version, const std::string& source)
{
    const auto fmt = string(require(j, "format", source), "format", source);
    if (fmt != name)
        fail(source, "format", "expected \"" + std::string(name) + "\", got \"" + fmt + "\"");
    const auto ver = integer(require(j, "version", source), "version", source);
    if (ver != version)
        fail(source, "version", "unsupported version " + std::to_string(ver) + " (this build reads " +
                                    std::to_string(version) + ")");
}

} // namespace json_read
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_JSON_READ_H */
