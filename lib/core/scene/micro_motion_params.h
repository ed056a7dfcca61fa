// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the parameters of a micro-motion model, read once and drawn per frame (internal).
 *
 * Each model lists its parameters once, in visit_params() (micro_motion_params.cc), in a
 * fixed order. Three visitors walk that list:
 *   - the reader takes every value from JSON: a number, or (in a class library) an
 *     interval [lo, hi] to draw from; absent keys take the model's default;
 *   - the drawer sets every value of a concrete motion from what the reader recorded:
 *     numbers as given, intervals drawn uniformly (integers uniformly among lo..hi), in the
 *     list's order, so a seed names the same targets on every platform;
 *   - the endpoint visitor sets every value to its interval's low or high end, so a class
 *     library is validated at both ends of each parameter (every check is per parameter,
 *     so the ends bound every draw).
 */
#ifndef INCLUDED_SEMS_LIB_CORE_MICRO_MOTION_PARAMS_H
#define INCLUDED_SEMS_LIB_CORE_MICRO_MOTION_PARAMS_H

#include "core/kernels/rng.h"
#include <gnuradio/sems/core/scene/micro_motion.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace detail {

/*! One recorded parameter: a value, or an interval to draw from. */
struct motion_param {
    double lo = 0.0, hi = 0.0;
    bool interval = false;          // drawn per frame (class libraries only)
    bool integer = false;           // drawn among the integers lo..hi
    std::vector<double> per_item;   // a scene's one-value-per-rotor list (not drawn)
    // Coupled to the target's speed (class libraries only): value = offset + k·speed, k the
    // number or interval above, so a bicyclist's cadence and wheel rate follow its speed.
    bool per_speed = false;
    double offset = 0.0;
};

/*! What a "micro_motion" object holds: the sinusoid or a scatterer model, with its parameters. */
struct motion_template {
    std::string model;                 // "sinusoid", "rotor", "walker", "wheels", "scatterers"
    std::vector<motion_param> params;  // in visit order
    std::vector<size_t> list_sizes;    // the JSON lists' lengths (scatterers, harmonics), in visit order
    nlohmann::json source_json;        // as written (to_json gives it back)
    bool has_intervals = false;
    double speed_min_mps = 0.0, speed_max_mps = 0.0; // the class's speed interval (per_speed parameters' ends)
};

enum class endpoint { low, high };

/*! A number, or an interval [lo, hi] (lo <= hi, both finite): the one reader of both forms. */
motion_param read_number_or_interval(const nlohmann::json& v, const std::string& field, const std::string& source);

/*!
 * Reads a "micro_motion" object.
 * intervals_allowed: class libraries draw from [lo, hi] and may couple a number to the
 * target's speed ({"per_speed": k or [lo, hi], "offset": c}); scenes give values. A class
 * library's phases absent from it are drawn over [0, 2π) (a scene's are 0).
 * speed_min_mps, speed_max_mps: the class's speed interval, the range of a per_speed
 * parameter's speed (both ends are validated).
 */
motion_template read_motion_template(const nlohmann::json& j,
                                     const std::string& source,
                                     const std::string& field,
                                     bool intervals_allowed,
                                     double speed_min_mps = 0.0,
                                     double speed_max_mps = 0.0);

/*! A concrete sinusoid from a template (model "sinusoid"); draws from g when it has intervals;
 *  speed_mps, the target's speed, sets per_speed parameters. */
micro_doppler draw_sinusoid(const motion_template& t, rng* g, double speed_mps = 0.0);
/*! A concrete scatterer model from a template; draws from g when it has intervals; speed_mps,
 *  the target's speed, sets per_speed parameters. */
micro_motion draw_motion(const motion_template& t, rng* g, double speed_mps = 0.0);
/*! The template with every interval at one end, and every per_speed parameter at the lowest or
 *  highest value it takes over the class's speeds (for validation and bounds). */
micro_doppler sinusoid_at(const motion_template& t, endpoint e);
micro_motion motion_at(const motion_template& t, endpoint e);

/*! Writes a concrete motion's keys in the reader's format. */
nlohmann::json sinusoid_to_json(const micro_doppler& md);

/*! Whether a body of this micro-motion model (class_definition::motion_model()) is modelled from
 *  any elevation: a point, a sinusoid and a walker are; rotors, wheels and user scatterers are
 *  seen from the ground plane, so they take no elevation but 0. */
inline bool modelled_from_any_elevation(const std::string& model)
{
    return model == "none" || model == "sinusoid" || model == "walker";
}
/*! Those models as error messages name them (kept beside the rule). */
constexpr const char* models_from_any_elevation = "point, sinusoid and walker";

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_MICRO_MOTION_PARAMS_H */
