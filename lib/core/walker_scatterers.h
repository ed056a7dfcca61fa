// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the walker micro-motion model as the channel model sees it (internal): the 16
 * body segments of the Boulic–Thalmann walking model (core/walker_model.h) as point
 * scatterers — radial displacement and amplitude at a time — and the model's bounds. */
#ifndef INCLUDED_SEMS_LIB_CORE_WALKER_SCATTERERS_H
#define INCLUDED_SEMS_LIB_CORE_WALKER_SCATTERERS_H

#include <string>

namespace gr {
namespace sems {
namespace detail {

constexpr int walker_segments = 16;

double walker_min_height_m();
double walker_max_height_m();
/* The largest |r_s| a segment of a person of this height reaches (m). */
double walker_extent_m(double height_m);
/* The largest radial speed of a segment relative to the body (m/s). */
double walker_peak_speed_mps(double height_m, double speed_mps);
/* Refuses a speed outside the model's valid range, naming it, the height and the range. */
void walker_check_speed(double height_m, double speed_mps, const std::string& source, const std::string& field);
/* Segment s's radial displacement r[s] (m, + = away from the radar, relative to the point
 * moving with the body's mean velocity) and amplitude a[s] (sqrt of its RCS, normalised so
 * Σ_s mean a_s² over a cycle = 1) at time t, for a person walking at speed_mps along
 * heading θ (0 = straight at the radar). */
void walker_scatterers(double height_m, double speed_mps, double heading_rad, double phase_rad, double t_s,
                       double* r, double* a);

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_WALKER_SCATTERERS_H */
