// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the walker model's bounds (walker_scatterers.h). */
#include "core/scene/walker_scatterers.h"
#include "core/common/json_read.h"
#include <gnuradio/sems/core/scene/walker_model.h>
#include <cmath>
#include <sstream>

namespace gr {
namespace sems {
namespace detail {

double walker_min_height_m() { return walker::min_height_m; }
double walker_max_height_m() { return walker::max_height_m; }
// Feet and hands swing within about a leg length of the pelvis (hip flexion below 50°, a
// step below 0.8 H_t): 0.6 H bounds every segment's centre with margin.
double walker_extent_m(double height_m) { return 0.6 * height_m; }
double walker_peak_speed_mps(double, double speed_mps) { return 4.5 * std::fabs(speed_mps); }

void walker_check_speed(double height_m, double speed_mps, const std::string& source, const std::string& field)
{
    const double vmax = walker::max_speed_mps(height_m);
    if (!(speed_mps >= 0.0 && speed_mps <= vmax)) {
        std::ostringstream s;
        s << "speed " << speed_mps << " m/s is outside the walker model's valid range [0, " << vmax
          << "] m/s for a height of " << height_m << " m (relative velocity v/H_t up to "
          << walker::max_relative_velocity << ", H_t = " << walker::leg_length_m(height_m) << " m)";
        json_read::fail(source, field, s.str());
    }
}

} // namespace detail
} // namespace sems
} // namespace gr
