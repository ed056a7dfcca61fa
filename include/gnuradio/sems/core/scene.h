// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what the emulator models (DESIGN §1): targets, their paths, clutter, and
 * the target of interest; fixed (given values) or random (drawn per frame from the
 * class table). A scene models only what it has: no micro-Doppler on a target without
 * it, no clutter paths without clutter.
 *
 * Power bookkeeping: the mean path powers of one realization sum to 1 (unit mean
 * channel power per resource element). Clutter takes csr/(1+csr) of it, the targets
 * the rest, split by target power and then by path power.
 */
#ifndef INCLUDED_SEMS_SCENE_H
#define INCLUDED_SEMS_SCENE_H

#include <gnuradio/sems/api.h>
#include <gnuradio/sems/core/target_class.h>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {

struct SEMS_API micro_doppler {
    double rate_hz = 0.0;     // f_md = ω / 2π
    double amplitude_m = 0.0; // displacement A
    double phase_rad = 0.0;   // φ (random scenes draw it per frame)
};

struct SEMS_API path_spec {
    double excess_range_m = 0.0; // beyond the target's range (0 = the direct path)
    double power = 1.0;          // relative to the target's other paths
};

struct SEMS_API target_spec {
    target_class cls = target_class::car;
    double range_m = 50.0;
    double velocity_mps = 15.0; // radial, positive = Doppler > 0
    std::optional<micro_doppler> md;
    double power = 1.0;                        // relative to the scene's other targets
    std::vector<path_spec> paths{ path_spec{} }; // at least one; the first is the direct path
};

struct SEMS_API clutter_spec {
    double csr_db = 0.0;                // clutter-to-signal power ratio
    int n_paths = 4;                    // static (zero-Doppler) scatterers
    double range_min_m = 0.0;           // drawn per frame, unless ranges_m is given
    double range_max_m = 200.0;
    std::vector<double> ranges_m;       // fixed scatterer ranges (then n_paths = ranges_m.size())
};

// Direction of a random target's motion. approaching: radial velocity = +speed (the
// paper: every class in its own positive Doppler band). any: radial velocity =
// speed·cos θ with θ ~ U[0, 2π) per frame (approaching, receding and crossing targets;
// the bulk Doppler bands overlap, micro-Doppler must tell the classes apart).
enum class heading_kind { approaching, any };
/*! \brief "approaching" or "any". */
SEMS_API std::string heading_name(heading_kind h);
/*! \brief The heading of a name; throws std::invalid_argument listing the known names. */
SEMS_API heading_kind heading_from_name(const std::string& name);

// How a random scene draws a frame.
struct SEMS_API random_spec {
    std::vector<target_class> classes{ target_class::pedestrian, target_class::car, target_class::drone };
    int n_targets = 1;                 // the target of interest is target 0
    int paths_per_target = 1;          // 1 = single path
    double excess_range_min_m = 2.0;   // extra paths: excess range ~ U[min, max]
    double excess_range_max_m = 30.0;
    double path_power_decay_db = 3.0;  // path k has mean power 10^(-k·decay/10) relative to path 0
    bool micro_doppler = true;         // false: the micro-Doppler-free experiment
    heading_kind heading = heading_kind::approaching; // see heading_kind
};

enum class fading_kind { rayleigh, none };

class SEMS_API scene
{
public:
    static constexpr const char* format_name = "sems.scene";
    static constexpr int format_version = 1;

    // A fixed scene: given targets, optional clutter.
    static scene fixed(std::vector<target_spec> targets,
                       std::optional<clutter_spec> clutter = std::nullopt,
                       int target_of_interest = 0,
                       fading_kind fading = fading_kind::rayleigh);
    // A random scene drawn per frame from the class table.
    static scene random(random_spec spec,
                        std::optional<clutter_spec> clutter = std::nullopt,
                        fading_kind fading = fading_kind::rayleigh);

    static scene load(const std::string& path);
    static scene parse(const std::string& json_text, const std::string& source = "scene text");
    static scene from_json(const nlohmann::json& j, const std::string& source);
    nlohmann::json to_json() const;
    std::string to_json_string() const;
    void save(const std::string& path) const;

    bool is_random() const { return d_random.has_value(); }
    const std::vector<target_spec>& targets() const { return d_targets; }
    const std::optional<random_spec>& random_settings() const { return d_random; }
    const std::optional<clutter_spec>& clutter() const { return d_clutter; }
    int target_of_interest() const { return d_toi; }
    fading_kind fading() const { return d_fading; }
    // Classes a frame of this scene can be labelled with (the TOI's possible classes).
    std::vector<target_class> label_classes() const;

    // Throws std::invalid_argument naming `source` and the field.
    void validate(const std::string& source = "scene") const;

private:
    scene() = default;
    std::vector<target_spec> d_targets;
    std::optional<random_spec> d_random;
    std::optional<clutter_spec> d_clutter;
    int d_toi = 0;
    fading_kind d_fading = fading_kind::rayleigh;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_SCENE_H */
