// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: micro-motion models — names, validation, bounds, JSON (micro_motion.h). */
#include "core/common/checks.h"
#include "core/common/math_constants.h"
#include "core/common/json_read.h"
#include "core/scene/walker_scatterers.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/core/scene/micro_motion.h>
#include <algorithm>
#include <cmath>
#include <tuple>

namespace gr {
namespace sems {

using json = nlohmann::json;
using json_read::fail;

namespace {


struct checker {
    const std::string& source;
    const std::string& field;
    void non_negative(double v, const char* key, const char* unit) const
    {
        if (!checks::non_negative(v))
            fail(source, field + "." + key, std::string("must be a finite number >= 0 ") + unit + ", got " + std::to_string(v));
    }
    void positive(double v, const char* key, const char* unit) const
    {
        if (!checks::positive(v))
            fail(source, field + "." + key, std::string("must be a finite number > 0 ") + unit + ", got " + std::to_string(v));
    }
    void finite(double v, const char* key) const
    {
        if (!checks::finite(v))
            fail(source, field + "." + key, "must be finite, got " + std::to_string(v));
    }
    void share(double v, const char* key) const
    {
        if (!(checks::finite(v) && v >= 0.0 && v <= 1.0))
            fail(source, field + "." + key, "must be a power share in [0, 1], got " + std::to_string(v));
    }
    void count(int v, const char* key, int lo, int hi) const
    {
        if (v < lo || v > hi)
            fail(source, field + "." + key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                                             std::to_string(v));
    }
};

struct validate_visitor {
    checker c;
    void operator()(const rotor_motion& m) const
    {
        c.count(m.rotors, "rotors", 1, limits::max_rotors);
        c.count(m.blades, "blades", 1, limits::max_blades);
        c.positive(m.blade_length_m, "blade_length_m", "m");
        auto per_rotor = [&](const std::vector<double>& v, const char* key) {
            if (v.size() != 1 && v.size() != static_cast<size_t>(m.rotors))
                fail(c.source, c.field + "." + key, "give one value or one per rotor (" + std::to_string(m.rotors) +
                                                        "), got " + std::to_string(v.size()));
        };
        per_rotor(m.rotation_hz, "rotation_hz");
        per_rotor(m.phase_rad, "phase_rad");
        for (double f : m.rotation_hz)
            c.non_negative(f, "rotation_hz", "rev/s");
        for (double p : m.phase_rad)
            c.finite(p, "phase_rad");
        if (!(checks::finite(m.elevation_rad) && std::fabs(m.elevation_rad) <= M_PI / 2))
            fail(c.source, c.field + ".elevation_rad", "must be in [-π/2, π/2] rad, got " + std::to_string(m.elevation_rad));
        c.share(m.body_power, "body_power");
    }
    void operator()(const walker_motion& m) const
    {
        c.finite(m.phase_rad, "phase_rad");
        if (!(checks::finite(m.height_m) && m.height_m >= detail::walker_min_height_m() && m.height_m <= detail::walker_max_height_m()))
            fail(c.source, c.field + ".height_m", "must be in [" + std::to_string(detail::walker_min_height_m()) + ", " +
                                                      std::to_string(detail::walker_max_height_m()) + "] m, got " +
                                                      std::to_string(m.height_m));
    }
    void operator()(const wheels_motion& m) const
    {
        c.count(m.wheels, "wheels", 1, limits::max_wheels);
        c.positive(m.wheel_radius_m, "wheel_radius_m", "m");
        c.count(m.rim_points, "rim_points", 0, limits::max_rim_points);
        c.count(m.spokes, "spokes", 0, limits::max_spokes);
        c.share(m.body_power, "body_power");
        if (m.rim_points + m.spokes == 0 && m.body_power < 1.0)
            fail(c.source, c.field, "wheels with no rim_points and no spokes return nothing: give some, or body_power 1");
        c.non_negative(m.wheelbase_m, "wheelbase_m", "m");
        c.non_negative(m.track_m, "track_m", "m");
        c.finite(m.phase_rad, "phase_rad");
    }
    void operator()(const scatterers_motion& m) const
    {
        if (m.scatterers.empty() || m.scatterers.size() > static_cast<size_t>(limits::max_scatterers))
            fail(c.source, c.field + ".scatterers", "must have 1 to " + std::to_string(limits::max_scatterers) +
                                                        " scatterers, got " + std::to_string(m.scatterers.size()));
        double total = 0.0;
        for (size_t i = 0; i < m.scatterers.size(); ++i) {
            const auto& s = m.scatterers[i];
            const std::string f = c.field + ".scatterers[" + std::to_string(i) + "]";
            const checker cs{ c.source, f };
            cs.non_negative(s.power, "power", "");
            if (s.power > limits::max_relative_power)
                fail(c.source, f + ".power", "must be at most 1e30 (a relative power), got " + std::to_string(s.power));
            total += s.power;
            if (s.harmonics.size() > static_cast<size_t>(limits::max_harmonics))
                fail(c.source, f + ".harmonics", "has more than " + std::to_string(limits::max_harmonics) + " harmonics");
            for (size_t h = 0; h < s.harmonics.size(); ++h) {
                const checker ch{ c.source, f + ".harmonics[" + std::to_string(h) + "]" };
                ch.non_negative(s.harmonics[h].amplitude_m, "amplitude_m", "m");
                ch.non_negative(s.harmonics[h].rate_hz, "rate_hz", "Hz");
                ch.finite(s.harmonics[h].phase_rad, "phase_rad");
            }
        }
        if (!(total > 0.0) || !std::isfinite(total))
            fail(c.source, c.field + ".scatterers", "the scatterers' powers must sum to a finite number > 0");
    }
};

} // namespace

bool operator==(const rotor_motion& a, const rotor_motion& b)
{
    return std::tie(a.rotors, a.blades, a.blade_length_m, a.rotation_hz, a.phase_rad, a.elevation_rad, a.body_power) ==
           std::tie(b.rotors, b.blades, b.blade_length_m, b.rotation_hz, b.phase_rad, b.elevation_rad, b.body_power);
}
bool operator==(const walker_motion& a, const walker_motion& b)
{
    return a.height_m == b.height_m && a.phase_rad == b.phase_rad;
}
bool operator==(const wheels_motion& a, const wheels_motion& b)
{
    return std::tie(a.wheels, a.wheel_radius_m, a.rim_points, a.spokes, a.body_power, a.wheelbase_m, a.track_m, a.phase_rad) ==
           std::tie(b.wheels, b.wheel_radius_m, b.rim_points, b.spokes, b.body_power, b.wheelbase_m, b.track_m, b.phase_rad);
}
bool operator==(const scatterers_motion& a, const scatterers_motion& b)
{
    if (a.scatterers.size() != b.scatterers.size())
        return false;
    for (size_t i = 0; i < a.scatterers.size(); ++i) {
        const auto &x = a.scatterers[i], &y = b.scatterers[i];
        if (x.power != y.power || x.harmonics.size() != y.harmonics.size())
            return false;
        for (size_t h = 0; h < x.harmonics.size(); ++h)
            if (x.harmonics[h].amplitude_m != y.harmonics[h].amplitude_m || x.harmonics[h].rate_hz != y.harmonics[h].rate_hz ||
                x.harmonics[h].phase_rad != y.harmonics[h].phase_rad)
                return false;
    }
    return true;
}

std::string micro_motion_model(const micro_motion& m)
{
    struct {
        std::string operator()(const rotor_motion&) const { return "rotor"; }
        std::string operator()(const walker_motion&) const { return "walker"; }
        std::string operator()(const wheels_motion&) const { return "wheels"; }
        std::string operator()(const scatterers_motion&) const { return "scatterers"; }
    } name;
    return std::visit(name, m);
}

void validate_micro_motion(const micro_motion& m, const std::string& source, const std::string& field)
{
    std::visit(validate_visitor{ checker{ source, field } }, m);
}

double micro_motion_extent_m(const micro_motion& m)
{
    struct {
        double operator()(const rotor_motion& r) const { return r.blade_length_m * std::cos(r.elevation_rad); }
        double operator()(const walker_motion& w) const { return detail::walker_extent_m(w.height_m); }
        double operator()(const wheels_motion& w) const { return 0.5 * w.wheelbase_m + 0.5 * w.track_m + w.wheel_radius_m; }
        double operator()(const scatterers_motion& s) const
        {
            double e = 0.0;
            for (const auto& p : s.scatterers) {
                double a = 0.0;
                for (const auto& h : p.harmonics)
                    a += h.amplitude_m;
                e = std::max(e, a);
            }
            return e;
        }
    } extent;
    return std::visit(extent, m);
}

double micro_motion_peak_speed_mps(const micro_motion& m, double speed_mps)
{
    const double v = std::fabs(speed_mps);
    struct {
        double v;
        double operator()(const rotor_motion& r) const
        {
            double f = 0.0;
            for (double x : r.rotation_hz)
                f = std::max(f, x);
            return two_pi * f * r.blade_length_m * std::cos(r.elevation_rad);
        }
        double operator()(const walker_motion& w) const { return detail::walker_peak_speed_mps(w.height_m, v); }
        double operator()(const wheels_motion&) const { return v; } // rim speed v/R·R relative to the hub
        double operator()(const scatterers_motion& s) const
        {
            double peak = 0.0;
            for (const auto& p : s.scatterers) {
                double a = 0.0;
                for (const auto& h : p.harmonics)
                    a += two_pi * h.rate_hz * h.amplitude_m;
                peak = std::max(peak, a);
            }
            return peak;
        }
    } peak{ v };
    return std::visit(peak, m);
}

json micro_motion_to_json(const micro_motion& m)
{
    struct {
        json operator()(const rotor_motion& r) const
        {
            auto per_rotor = [](const std::vector<double>& v) { return v.size() == 1 ? json(v[0]) : json(v); };
            return { { "model", "rotor" },
                     { "rotors", r.rotors },
                     { "blades", r.blades },
                     { "blade_length_m", r.blade_length_m },
                     { "rotation_hz", per_rotor(r.rotation_hz) },
                     { "phase_rad", per_rotor(r.phase_rad) },
                     { "elevation_rad", r.elevation_rad },
                     { "body_power", r.body_power } };
        }
        json operator()(const walker_motion& w) const
        {
            return { { "model", "walker" }, { "height_m", w.height_m }, { "phase_rad", w.phase_rad } };
        }
        json operator()(const wheels_motion& w) const
        {
            return { { "model", "wheels" },           { "wheels", w.wheels },
                     { "wheel_radius_m", w.wheel_radius_m }, { "rim_points", w.rim_points },
                     { "spokes", w.spokes },           { "body_power", w.body_power },
                     { "wheelbase_m", w.wheelbase_m }, { "track_m", w.track_m },
                     { "phase_rad", w.phase_rad } };
        }
        json operator()(const scatterers_motion& s) const
        {
            json list = json::array();
            for (const auto& p : s.scatterers) {
                json hs = json::array();
                for (const auto& h : p.harmonics)
                    hs.push_back({ { "amplitude_m", h.amplitude_m }, { "rate_hz", h.rate_hz }, { "phase_rad", h.phase_rad } });
                list.push_back({ { "power", p.power }, { "harmonics", hs } });
            }
            return { { "model", "scatterers" }, { "scatterers", list } };
        }
    } to;
    return std::visit(to, m);
}

} // namespace sems
} // namespace gr
