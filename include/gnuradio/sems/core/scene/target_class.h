// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief The target classes and their kinematics (docs/design.md §1, the paper's table).
 *
 * \details Micro-Doppler displacement A is not in the paper; the defaults below keep every
 * class inside the unambiguous ±1/(2T) = ±500 Hz of instantaneous Doppler at the
 * default frame: peak Doppler = 2/λ · (v + 2π f_md A).
 * \verbatim
   pedestrian: A = 0.10 m  (limb swing)   -> peak 2/0.1·(2 + 2π·3·0.10)  ≈  78 Hz
   car:        no micro-Doppler            -> peak 2/0.1·20               = 400 Hz
   drone:      A = 0.01 m  (rotor blades)  -> peak 2/0.1·(10 + 2π·120·0.01) ≈ 351 Hz
   \endverbatim
 */
#ifndef INCLUDED_SEMS_CORE_TARGET_CLASS_H
#define INCLUDED_SEMS_CORE_TARGET_CLASS_H

#include <gnuradio/sems/api.h>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief The target classes; the value is the class id (labels, class_table() index). */
enum class target_class : int { pedestrian = 0, car = 1, drone = 2 };

/*!
 * \brief One row of the class table: the ranges random scenes draw a target of the class from.
 */
struct SEMS_API class_spec {
    target_class id;  ///< the class
    std::string name; ///< its name ("pedestrian", "car", "drone")
    double range_min_m, range_max_m;       ///< upper end of the range interval in m
    double speed_min_mps, speed_max_mps;   ///< upper end of the radial speed interval in m/s
    double md_rate_min_hz, md_rate_max_hz; ///< upper end of the micro-Doppler rate interval in Hz (0: no micro-Doppler)
    double md_amplitude_m;                 ///< micro-Doppler displacement A in m
    /*! \brief Whether the class has micro-Doppler. \return md_rate_max_hz > 0. */
    bool has_micro_doppler() const { return md_rate_max_hz > 0.0; }
};
/*! \var class_spec::range_min_m
 *  \brief lower end of the range interval in m. */
/*! \var class_spec::speed_min_mps
 *  \brief lower end of the radial speed interval in m/s. */
/*! \var class_spec::md_rate_min_hz
 *  \brief lower end of the micro-Doppler rate interval in Hz (0 with md_rate_max_hz = 0: no micro-Doppler). */

/*! \brief The class table. \return every class_spec, indexed by class id. */
SEMS_API const std::vector<class_spec>& class_table();
/*! \brief One class's row. \param c the class. \return its class_spec. */
SEMS_API const class_spec& class_info(target_class c);
/*!
 * \brief One class's row by id.
 * \param class_id the class id.
 * \return its class_spec.
 * \throws std::invalid_argument on an unknown id.
 */
SEMS_API const class_spec& class_info(int class_id);
/*!
 * \brief The class of a name.
 * \param name a class name ("pedestrian", "car", "drone").
 * \return the class.
 * \throws std::invalid_argument listing the known names.
 */
SEMS_API target_class class_from_name(const std::string& name);
/*! \brief The class names. \return the names, indexed by class id. */
SEMS_API std::vector<std::string> class_names();

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_TARGET_CLASS_H */
