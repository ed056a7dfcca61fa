// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: strict reading of one JSON object of a project file (internal).
 *
 * object_reader wraps one JSON object and records every key it is asked about;
 * finish() then rejects the keys nobody read, naming their full path
 * ("targets[0].powr: unknown key"). A field added later and read through the
 * reader is therefore allowed automatically, and a typo never passes silently.
 *
 * Integers are range-checked before any narrowing cast (a JSON integer is up to
 * 64 bits; 4294967328 must not become 32), and numbers meant for a float are
 * checked against the float range. Messages: "<source>: <path>: <problem>".
 */
#ifndef INCLUDED_SEMS_JSON_OBJECT_H
#define INCLUDED_SEMS_JSON_OBJECT_H

#include "core/common/json_read.h"
#include <cstdint>
#include <limits>
#include <set>
#include <string>

namespace gr {
namespace sems {
namespace json_read {

// A JSON integer in [lo, hi], checked before any cast (also for integers beyond 64-bit signed).
inline long long integer_in(
    const nlohmann::json& v, const std::string& field, const std::string& source, long long lo, long long hi)
{
    if (!v.is_number_integer())
        fail(source, field, "expected an integer, got " + v.dump());
    const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (v.is_number_unsigned() &&
        v.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<long long>::max()))
        fail(source, field, "must be in " + range + ", got " + v.dump());
    const long long x = v.get<long long>();
    if (x < lo || x > hi)
        fail(source, field, "must be in " + range + ", got " + std::to_string(x));
    return x;
}

// An int-valued JSON integer in [lo, hi] (the bounds are ints, so the cast is safe).
inline int int_in(const nlohmann::json& v, const std::string& field, const std::string& source, int lo, int hi)
{
    return static_cast<int>(integer_in(v, field, source, lo, hi));
}

// A finite double converted to float: refused when beyond the float range (the cast
// would be undefined behaviour); tiny values round towards 0 as IEEE does.
inline float to_float(double x, const std::string& field, const std::string& source)
{
    if (!std::isfinite(x) || std::fabs(x) > static_cast<double>(std::numeric_limits<float>::max()))
        fail(source, field, "must be a finite number within the float range (|x| <= 3.4e38), got " + std::to_string(x));
    return static_cast<float>(x);
}

class object_reader
{
public:
    // `j` must be an object (else "<source>: <path>: expected a JSON object"); `path` is
    // the object's own position in the file ("" for the top level, "targets[0]", ...).
    object_reader(const nlohmann::json& j, std::string source, std::string path = "")
        : d_j(j), d_source(std::move(source)), d_path(std::move(path))
    {
        if (!d_j.is_object())
            fail(d_source, d_path, "expected a JSON object, got " + short_dump(d_j));
    }

    const std::string& source() const { return d_source; }
    const std::string& path() const { return d_path; }
    // The full path of `key` in this object, for messages.
    std::string field(const std::string& key) const { return d_path.empty() ? key : d_path + "." + key; }

    // Marks `key` as known (read elsewhere or deliberately ignored, e.g. a free-text description).
    void allow(const char* key) { d_used.insert(key); }

    // The value of `key`, or nullptr when absent. Either way the key is known.
    const nlohmann::json* find(const char* key)
    {
        d_used.insert(key);
        auto it = d_j.find(key);
        return it == d_j.end() ? nullptr : &*it;
    }
    bool has(const char* key) { return find(key) != nullptr; }

    const nlohmann::json& require(const char* key)
    {
        const auto* v = find(key);
        if (!v)
            fail(d_source, field(key), "missing");
        return *v;
    }

    long long integer(const char* key, long long lo, long long hi)
    {
        return integer_in(require(key), field(key), d_source, lo, hi);
    }
    long long integer_or(const char* key, long long fallback, long long lo, long long hi)
    {
        const auto* v = find(key);
        return v ? integer_in(*v, field(key), d_source, lo, hi) : fallback;
    }
    int int_or(const char* key, int fallback, int lo, int hi)
    {
        return static_cast<int>(integer_or(key, fallback, lo, hi));
    }
    int int_required(const char* key, int lo, int hi) { return static_cast<int>(integer(key, lo, hi)); }

    double number(const char* key) { return finite_number(require(key), field(key), d_source); }
    double number_or(const char* key, double fallback)
    {
        const auto* v = find(key);
        return v ? finite_number(*v, field(key), d_source) : fallback;
    }
    // A finite number in [lo, hi] (the bounds are named in the message).
    double number_in(const char* key, double fallback, double lo, double hi, bool required = false)
    {
        const double x = required ? number(key) : number_or(key, fallback);
        if (x < lo || x > hi)
            fail(d_source, field(key),
                 "must be in [" + num(lo) + ", " + num(hi) + "], got " + num(x));
        return x;
    }

    std::string string(const char* key) { return json_read::string(require(key), field(key), d_source); }
    std::string string_or(const char* key, const std::string& fallback)
    {
        const auto* v = find(key);
        return v ? json_read::string(*v, field(key), d_source) : fallback;
    }

    bool boolean_or(const char* key, bool fallback)
    {
        const auto* v = find(key);
        if (!v)
            return fallback;
        if (!v->is_boolean())
            fail(d_source, field(key), "expected true or false, got " + short_dump(*v));
        return v->get<bool>();
    }

    // A reader for the object under `key` (which must be finished by the caller).
    object_reader object(const char* key) { return object_reader(require(key), d_source, field(key)); }

    // A list under `key` with at most `max_size` entries (the bound is in the message).
    const nlohmann::json& array(const char* key, size_t min_size, size_t max_size)
    {
        return checked_array(require(key), field(key), d_source, min_size, max_size);
    }

    // Rejects every key no one asked about: "<source>: <path.key>: unknown key (known: ...)".
    void finish() const
    {
        for (auto it = d_j.begin(); it != d_j.end(); ++it)
            if (!d_used.count(it.key())) {
                std::string known;
                for (const auto& k : d_used)
                    known += (known.empty() ? "" : ", ") + k;
                fail(d_source, field(it.key()), "unknown key (known here: " + known + ")");
            }
    }

    static const nlohmann::json& checked_array(const nlohmann::json& v,
                                               const std::string& field,
                                               const std::string& source,
                                               size_t min_size,
                                               size_t max_size)
    {
        if (!v.is_array())
            fail(source, field, "expected a list, got " + short_dump(v));
        if (v.size() < min_size || v.size() > max_size)
            fail(source, field, "must have " + std::to_string(min_size) + " to " + std::to_string(max_size) +
                                    " entries, got " + std::to_string(v.size()));
        return v;
    }

    static std::string short_dump(const nlohmann::json& v)
    {
        std::string s = v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
        return s.size() > 60 ? s.substr(0, 57) + "..." : s;
    }

private:
    static std::string num(double x)
    {
        std::ostringstream s;
        s << x;
        return s.str();
    }

    const nlohmann::json& d_j;
    std::string d_source;
    std::string d_path;
    std::set<std::string> d_used;
};

// The top level of a project file: checks {"format": format, "version": version} and knows
// those keys and "description" (free text for people).
inline object_reader file_object(const nlohmann::json& j, const char* format, int version, const std::string& source)
{
    check_format(j, format, version, source);
    object_reader top(j, source);
    top.allow("format");
    top.allow("version");
    top.allow("description");
    return top;
}

} // namespace json_read
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_JSON_OBJECT_H */
