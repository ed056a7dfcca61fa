// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the walker model's bounds as the micro-motion readers need them (internal); the
 * kinematics and scattering are core/scene/walker_model.h. */
#ifndef INCLUDED_SEMS_LIB_CORE_WALKER_SCATTERERS_H
#define INCLUDED_SEMS_LIB_CORE_WALKER_SCATTERERS_H

#include <string>

namespace gr {
namespace sems {
namespace detail {

double walker_min_height_m();
double walker_max_height_m();
/* A bound on |r_s| for a person of this height: the limbs' reach about the pelvis (m). */
double walker_extent_m(double height_m);
/* A bound on a segment's radial speed relative to the body: the foot in swing peaks near 4 v. */
double walker_peak_speed_mps(double height_m, double speed_mps);
/* Refuses a speed outside the model's valid range [0, 3 H_t], naming it, the height and the range. */
void walker_check_speed(double height_m, double speed_mps, const std::string& source, const std::string& field);

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_WALKER_SCATTERERS_H */
