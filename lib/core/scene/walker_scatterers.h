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

/* A bound on every segment's speed relative to the body, in m/s: the norm of the velocity of
 * a segment centre in the body frame, i.e. relative to the point that moves with the walker's
 * mean velocity (the reference of r_s = −p_s·u, so the pelvis's own oscillation counts). A
 * segment's radial speed |dr_s/dt| = |ṗ_s·u| is at most that at any heading and elevation;
 * the bulk radial velocity v·cos θ·cos ε comes on top. Holds for every height in [0.5, 3] m
 * and every speed of the model's range (relative velocity RV = v/H_t in [0, 3], H_t = 0.53 H);
 * throws std::invalid_argument outside it.
 *
 *     bound = sqrt(RV) · (α(RV)·H + β(RV))   m/s,   H in m,
 *
 * α (m/s per m of height) and β (m/s) read by linear interpolation from a table over RV.
 * Derivation. At a fixed RV every segment centre is H·q(u) + T(u): the limbs scale with the
 * height, the pelvis translations T are in metres at every height, and the cycle time
 * u = t/D_c depends on RV only. So each centre's velocity is affine in H, its norm convex in
 * H, and the peak speed S(H) over the segments and the cycle (the maximum of convex functions)
 * lies below its chord between the shortest and the tallest walker, H = 0.5 and 3 m. Writing
 * that chord as sqrt(RV)·(α·H + β), α and β come from the peak speeds of those two walkers
 * (central differences of walker_model::pose, 2048 instants per cycle with every local maximum
 * refined to 1e-7 cycle, RV every 0.001, every 1e-4 below 0.001 and either side of the gait
 * boundaries). Each column was raised until its linear interpolation lies above every sample
 * (β not below 0), then 2 % added for what sampling could miss, and rounded up. sqrt(RV) takes out the rate of the gait
 * (1/D_c = sqrt(RV)/1.346); the nodes sit at the gait boundary 0.5 and at the kinks below
 * RV 0.03, where the knee's 3° control points, fixed while its swing peak 140·RV goes to 0,
 * keep a small motion whose speed falls only as sqrt(RV).
 * Margin, checked on another grid (RV = 0.0005 + 0.001 k, 500 random RVs, 3001 instants, five
 * heights 0.5 to 3 m): none of the 2 % is used up; the bound lies 2.0 % to 3.1 % above the
 * model's peak speed for RV ≥ 0.05 at every height, and at most 43 % above it below RV 0.05
 * (speeds under 0.11 m/s). The peak
 * itself is 5.9 v (0.5 m) to 5.1 v (3 m) at RV = 0.5 and falls to 2.2–2.4 v at RV = 3; at RV
 * → 0 it is a vanishing speed but an unbounded multiple of v (the knee above), so no bound of
 * the form k·v holds. qa_walker_model checks it against the model on its own grid. */
double walker_peak_speed_mps(double height_m, double speed_mps);

/* The same bound over a class of walkers: at least the largest walker_peak_speed_mps of any
 * height in [height_min_m, height_max_m] at any speed in [0, speed_max_mps], and at most 2 %
 * above it (the interval cut into 64 pieces, each bounded from its ends). Not the corners:
 * at a fixed speed the peak speed rises with the height while RV ≥ 0.5 and falls below it (the
 * amplitudes of Boulic's slow gait grow with RV), so a class can peak inside its interval.
 * Throws std::invalid_argument for heights outside [0.5, 3] m or a speed above the shortest
 * height's range. */
double walker_peak_speed_mps(double height_min_m, double height_max_m, double speed_max_mps);

/* Refuses a speed outside the model's valid range [0, 3 H_t], naming it, the height and the range. */
void walker_check_speed(double height_m, double speed_mps, const std::string& source, const std::string& field);

} // namespace detail
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_CORE_WALKER_SCATTERERS_H */
