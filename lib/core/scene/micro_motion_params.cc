// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: micro-motion parameters — the one list per model, its reader and its drawers. */
#include "core/scene/micro_motion_params.h"
#include "core/common/math_constants.h"
#include "core/common/json_object.h"
#include <gnuradio/sems/core/common/limits.h>
#include <cmath>
#include <limits>

namespace gr {
namespace sems {
namespace detail {

using json = nlohmann::json;
using json_read::fail;
using json_read::object_reader;

namespace {


// --- the one parameter list per model -------------------------------------------
// Every visitor V has:
//   number(key, ref, fallback, required, is_phase)
//   integer(key, ref, fallback, lo, hi)
//   per_item(key, vector& ref, fallback, count, is_phase)   one value per rotor
//   list(key, vector<T>& items, min, max, fn(T&, V&))          a JSON list of objects
// A phase absent from a class library is drawn over [0, 2π) per frame (is_phase).

template <class V>
void visit(micro_doppler& m, V& v)
{
    v.number("rate_hz", m.rate_hz, 0.0, true, false);
    v.number("amplitude_m", m.amplitude_m, 0.0, true, false);
    v.number("phase_rad", m.phase_rad, 0.0, false, true);
}

template <class V>
void visit(rotor_motion& m, V& v)
{
    const rotor_motion d;
    v.integer("rotors", m.rotors, d.rotors, 1, limits::max_rotors);
    v.integer("blades", m.blades, d.blades, 1, limits::max_blades);
    v.number("blade_length_m", m.blade_length_m, d.blade_length_m, true, false);
    v.per_item("rotation_hz", m.rotation_hz, d.rotation_hz[0], m.rotors, false, true);
    v.per_item("phase_rad", m.phase_rad, 0.0, m.rotors, true, false);
    v.number("elevation_rad", m.elevation_rad, d.elevation_rad, false, false);
    v.number("body_power", m.body_power, d.body_power, false, false);
}

template <class V>
void visit(walker_motion& m, V& v)
{
    const walker_motion d;
    v.number("height_m", m.height_m, d.height_m, true, false);
    v.number("phase_rad", m.phase_rad, 0.0, false, true);
}

template <class V>
void visit(wheels_motion& m, V& v)
{
    const wheels_motion d;
    v.integer("wheels", m.wheels, d.wheels, 1, limits::max_wheels);
    v.number("wheel_radius_m", m.wheel_radius_m, d.wheel_radius_m, true, false);
    v.integer("rim_points", m.rim_points, d.rim_points, 0, limits::max_rim_points);
    v.integer("spokes", m.spokes, d.spokes, 0, limits::max_spokes);
    v.number("body_power", m.body_power, d.body_power, false, false);
    v.number("wheelbase_m", m.wheelbase_m, d.wheelbase_m, false, false);
    v.number("track_m", m.track_m, d.track_m, false, false);
    v.number("phase_rad", m.phase_rad, 0.0, false, true);
}

template <class V>
void visit(scatterers_motion& m, V& v)
{
    v.list("scatterers", m.scatterers, 1, limits::max_scatterers, [](point_scatterer& s, V& vs) {
        vs.number("power", s.power, 1.0, false, false);
        vs.list("harmonics", s.harmonics, 0, limits::max_harmonics, [](harmonic& h, V& vh) {
            vh.number("amplitude_m", h.amplitude_m, 0.0, true, false);
            vh.number("rate_hz", h.rate_hz, 0.0, true, false);
            vh.number("phase_rad", h.phase_rad, 0.0, false, true);
        });
    });
}

// --- the reader -------------------------------------------------------------------

class reader
{
public:
    reader(object_reader& r, motion_template& t, bool intervals) : d_r(r), d_t(t), d_intervals(intervals) {}

    void number(const char* key, double& ref, double fallback, bool required, bool is_phase)
    {
        motion_param p;
        const json* v = d_r.find(key);
        if (!v) {
            if (required)
                fail(d_r.source(), d_r.field(key), "missing");
            p.lo = p.hi = fallback;
            if (is_phase && d_intervals) { // a library's phases are random unless given
                p.lo = 0.0;
                p.hi = two_pi;
                p.interval = true;
            }
        } else {
            p = read_value(*v, d_r.field(key));
        }
        ref = p.lo;
        push(p);
    }

    void integer(const char* key, int& ref, int fallback, int lo, int hi)
    {
        motion_param p;
        p.integer = true;
        p.lo = p.hi = fallback;
        if (const json* v = d_r.find(key)) {
            const std::string f = d_r.field(key);
            if (v->is_object())
                fail(d_r.source(), f, "a count cannot follow the speed: give an integer or an interval [min, max]");
            if (v->is_array()) {
                require_interval_allowed(f);
                object_reader::checked_array(*v, f, d_r.source(), 2, 2);
                p.lo = json_read::int_in((*v)[0], f + "[0]", d_r.source(), lo, hi);
                p.hi = json_read::int_in((*v)[1], f + "[1]", d_r.source(), lo, hi);
                check_order(p, f);
                p.interval = true;
            } else {
                p.lo = p.hi = json_read::int_in(*v, f, d_r.source(), lo, hi);
            }
        }
        ref = static_cast<int>(p.lo);
        push(p);
    }

    void per_item(const char* key, std::vector<double>& ref, double fallback, int count, bool is_phase, bool required)
    {
        const json* v = d_r.find(key);
        const std::string f = d_r.field(key);
        if (v && v->is_array() && !d_intervals) { // a scene: one value per rotor
            object_reader::checked_array(*v, f, d_r.source(), static_cast<size_t>(count), static_cast<size_t>(count));
            motion_param p;
            for (size_t i = 0; i < v->size(); ++i)
                p.per_item.push_back(json_read::finite_number((*v)[i], f + "[" + std::to_string(i) + "]", d_r.source()));
            p.lo = p.hi = p.per_item[0];
            ref = p.per_item;
            push(p);
            return;
        }
        if (!v && required)
            fail(d_r.source(), f, "missing");
        double first = 0.0;
        number(key, first, fallback, false, is_phase);
        ref.assign(static_cast<size_t>(count), first);
    }

    template <class T, class F>
    void list(const char* key, std::vector<T>& items, size_t min, size_t max, F fn)
    {
        if (min == 0 && !d_r.has(key)) { // an optional list: absent is empty
            d_t.list_sizes.push_back(0);
            items.clear();
            return;
        }
        const json& arr = d_r.array(key, min, max);
        d_t.list_sizes.push_back(arr.size());
        items.assign(arr.size(), T{});
        for (size_t i = 0; i < arr.size(); ++i) {
            object_reader child(arr[i], d_r.source(), d_r.field(key) + "[" + std::to_string(i) + "]");
            reader rc(child, d_t, d_intervals);
            fn(items[i], rc);
            child.finish();
        }
    }

private:
    motion_param read_value(const json& v, const std::string& f)
    {
        if (v.is_object())
            return read_per_speed(v, f);
        if (v.is_array())
            require_interval_allowed(f);
        return read_number_or_interval(v, f, d_r.source());
    }

    // {"per_speed": k or [k_lo, k_hi], "offset": c}: offset + k·speed, the target's speed.
    motion_param read_per_speed(const json& v, const std::string& f)
    {
        if (!d_intervals)
            fail(d_r.source(), f, "a value coupled to the speed ({\"per_speed\": ...}) is drawn in a class library only; a scene gives one value");
        object_reader o(v, d_r.source(), f);
        motion_param p = read_number_or_interval(o.require("per_speed"), o.field("per_speed"), d_r.source());
        p.per_speed = true;
        p.offset = o.number_or("offset", 0.0);
        o.finish();
        return p;
    }

    void require_interval_allowed(const std::string& f) const
    {
        if (!d_intervals)
            fail(d_r.source(), f, "an interval [min, max] is drawn per frame in a class library only; a scene gives one value");
    }

    void check_order(const motion_param& p, const std::string& f) const
    {
        if (p.lo > p.hi)
            fail(d_r.source(), f, "empty interval: min " + std::to_string(p.lo) + " exceeds max " + std::to_string(p.hi));
    }

    void push(const motion_param& p)
    {
        d_t.has_intervals = d_t.has_intervals || p.interval || p.per_speed;
        d_t.params.push_back(p);
    }

    object_reader& d_r;
    motion_template& d_t;
    bool d_intervals;
};

// --- the drawers ------------------------------------------------------------------

// Sets every value from the recorded parameters in visit order: a draw from g for an
// interval (g non-null), or an end of it (g null).
class drawer
{
public:
    drawer(const motion_template& t, rng* g, endpoint e, double speed_mps) : d_t(t), d_g(g), d_e(e), d_speed(speed_mps) {}

    void number(const char*, double& ref, double, bool, bool) { ref = value(next()); }
    void integer(const char*, int& ref, int, int, int) { ref = static_cast<int>(value(next())); }
    void per_item(const char*, std::vector<double>& ref, double, int count, bool, bool)
    {
        const motion_param& p = next();
        if (!p.per_item.empty()) {
            ref = p.per_item;
            return;
        }
        ref.resize(static_cast<size_t>(count));
        for (auto& x : ref) // each rotor its own draw
            x = value(p);
    }
    template <class T, class F>
    void list(const char*, std::vector<T>& items, size_t, size_t, F fn)
    {
        items.resize(d_t.list_sizes.at(d_list++));
        for (auto& it : items)
            fn(it, *this);
    }

private:
    const motion_param& next() { return d_t.params.at(d_next++); }
    double value(const motion_param& p)
    {
        if (p.per_speed && !d_g) { // an end: the extreme of offset + k·v over k and the class's speeds
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (double k : { p.lo, p.hi })
                for (double v : { d_t.speed_min_mps, d_t.speed_max_mps }) {
                    lo = std::min(lo, p.offset + k * v);
                    hi = std::max(hi, p.offset + k * v);
                }
            return d_e == endpoint::low ? lo : hi;
        }
        double x = p.lo;
        if (p.interval) {
            if (!d_g)
                return d_e == endpoint::low ? p.lo : p.hi;
            x = p.integer ? p.lo + static_cast<double>(d_g->below(static_cast<uint64_t>(p.hi - p.lo) + 1))
                          : d_g->uniform(p.lo, p.hi);
        }
        return p.per_speed ? p.offset + x * d_speed : x;
    }

    const motion_template& d_t;
    rng* d_g;
    endpoint d_e;
    double d_speed;
    size_t d_next = 0, d_list = 0;
};

template <class M>
M draw_as(const motion_template& t, rng* g, endpoint e, double speed_mps)
{
    M m;
    drawer d(t, g, e, speed_mps);
    visit(m, d);
    return m;
}

micro_motion draw_any(const motion_template& t, rng* g, endpoint e, double speed_mps)
{
    if (t.model == "rotor")
        return draw_as<rotor_motion>(t, g, e, speed_mps);
    if (t.model == "walker")
        return draw_as<walker_motion>(t, g, e, speed_mps);
    if (t.model == "wheels")
        return draw_as<wheels_motion>(t, g, e, speed_mps);
    if (t.model == "scatterers")
        return draw_as<scatterers_motion>(t, g, e, speed_mps);
    throw std::logic_error("micro-motion model \"" + t.model + "\" is not a scatterer model");
}

} // namespace

motion_param read_number_or_interval(const json& v, const std::string& field, const std::string& source)
{
    motion_param p;
    if (v.is_array()) {
        object_reader::checked_array(v, field, source, 2, 2);
        p.lo = json_read::finite_number(v[0], field + "[0]", source);
        p.hi = json_read::finite_number(v[1], field + "[1]", source);
        if (p.lo > p.hi)
            fail(source, field, "empty interval: min " + std::to_string(p.lo) + " exceeds max " + std::to_string(p.hi));
        p.interval = true;
    } else {
        p.lo = p.hi = json_read::finite_number(v, field, source);
    }
    return p;
}

motion_template read_motion_template(const json& j,
                                     const std::string& source,
                                     const std::string& field,
                                     bool intervals,
                                     double speed_min_mps,
                                     double speed_max_mps)
{
    object_reader r(j, source, field);
    motion_template t;
    t.speed_min_mps = speed_min_mps;
    t.speed_max_mps = speed_max_mps;
    t.model = r.string("model");
    t.source_json = j;
    reader rd(r, t, intervals);
    if (t.model == "sinusoid") {
        micro_doppler m;
        visit(m, rd);
    } else if (t.model == "rotor") {
        rotor_motion m;
        visit(m, rd);
    } else if (t.model == "walker") {
        walker_motion m;
        visit(m, rd);
    } else if (t.model == "wheels") {
        wheels_motion m;
        visit(m, rd);
    } else if (t.model == "scatterers") {
        scatterers_motion m;
        visit(m, rd);
    } else {
        fail(source, r.field("model"),
             "unknown micro-motion model \"" + t.model + "\" (known: sinusoid, rotor, walker, wheels, scatterers)");
    }
    r.finish();
    // Both ends of every parameter must be valid (each check is per parameter).
    for (endpoint e : { endpoint::low, endpoint::high }) {
        if (t.model == "sinusoid") {
            const micro_doppler m = sinusoid_at(t, e);
            if (!(m.rate_hz >= 0.0))
                fail(source, field + ".rate_hz", "must be >= 0 Hz, got " + std::to_string(m.rate_hz));
            if (!(m.amplitude_m >= 0.0))
                fail(source, field + ".amplitude_m", "must be >= 0 m, got " + std::to_string(m.amplitude_m));
        } else {
            validate_micro_motion(motion_at(t, e), source, field);
        }
    }
    return t;
}

micro_doppler draw_sinusoid(const motion_template& t, rng* g, double speed_mps)
{
    return draw_as<micro_doppler>(t, g, endpoint::low, speed_mps);
}
micro_motion draw_motion(const motion_template& t, rng* g, double speed_mps)
{
    return draw_any(t, g, endpoint::low, speed_mps);
}
micro_doppler sinusoid_at(const motion_template& t, endpoint e) { return draw_as<micro_doppler>(t, nullptr, e, 0.0); }
micro_motion motion_at(const motion_template& t, endpoint e) { return draw_any(t, nullptr, e, 0.0); }

json sinusoid_to_json(const micro_doppler& md)
{
    return { { "model", "sinusoid" },
             { "rate_hz", md.rate_hz },
             { "amplitude_m", md.amplitude_m },
             { "phase_rad", md.phase_rad } };
}

} // namespace detail
} // namespace sems
} // namespace gr
