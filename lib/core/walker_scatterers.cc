// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the walker model as scatterers (walker_scatterers.h). TEMPORARY STUB */
#include "core/walker_scatterers.h"
#include <stdexcept>
namespace gr { namespace sems { namespace detail {
double walker_min_height_m() { return 0.5; }
double walker_max_height_m() { return 2.5; }
double walker_extent_m(double h) { return 0.6 * h; }
double walker_peak_speed_mps(double, double v) { return 2.5 * v; }
void walker_check_speed(double, double, const std::string&, const std::string&) {}
void walker_scatterers(double, double, double, double, double, double*, double*) { throw std::logic_error("walker stub"); }
}}}
