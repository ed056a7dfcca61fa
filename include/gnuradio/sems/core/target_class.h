// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the target classes and their kinematics (DESIGN §1, the paper's table).
 *
 * Micro-Doppler displacement A is not in the paper; the defaults below keep every
 * class inside the unambiguous ±1/(2T) = ±500 Hz of instantaneous Doppler at the
 * default frame: peak Doppler = 2/λ · (v + 2π f_md A).
 *   pedestrian: A = 0.10 m  (limb swing)   -> peak 2/0.1·(2 + 2π·3·0.10)  ≈  78 Hz
 *   car:        no micro-Doppler            -> peak 2/0.1·20               = 400 Hz
 *   drone:      A = 0.01 m  (rotor blades)  -> peak 2/0.1·(10 + 2π·120·0.01) ≈ 351 Hz
 */
#ifndef INCLUDED_SEMS_CORE_TARGET_CLASS_H
#define INCLUDED_SEMS_CORE_TARGET_CLASS_H

#include <gnuradio/sems/api.h>
#include <string>
#include <vector>

namespace gr {
namespace sems {

enum class target_class : int { pedestrian = 0, car = 1, drone = 2 };

struct SEMS_API class_spec {
    target_class id;
    std::string name;
    double range_min_m, range_max_m;
    double speed_min_mps, speed_max_mps;
    double md_rate_min_hz, md_rate_max_hz; // 0, 0: no micro-Doppler
    double md_amplitude_m;                 // displacement A
    bool has_micro_doppler() const { return md_rate_max_hz > 0.0; }
};

// The class table, indexed by class id.
SEMS_API const std::vector<class_spec>& class_table();
SEMS_API const class_spec& class_info(target_class c);
SEMS_API const class_spec& class_info(int class_id); // throws on an unknown id
// Throws std::invalid_argument listing the known names.
SEMS_API target_class class_from_name(const std::string& name);
SEMS_API std::vector<std::string> class_names();

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_TARGET_CLASS_H */
