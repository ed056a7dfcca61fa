// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the circle constants of the core and the blocks (internal).
 *
 * Defined once: the library compiles its files in batches (SEMS_UNITY_BUILD), where a copy
 * in each file would be a second definition.
 */
#ifndef INCLUDED_SEMS_LIB_CORE_MATH_CONSTANTS_H
#define INCLUDED_SEMS_LIB_CORE_MATH_CONSTANTS_H

#include <cmath>

namespace gr {
namespace sems {

inline constexpr double pi = M_PI;
inline constexpr double two_pi = 2.0 * M_PI;

} // namespace sems
} // namespace gr

#endif
