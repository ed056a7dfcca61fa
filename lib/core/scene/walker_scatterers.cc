// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the walker model's bounds (walker_scatterers.h). */
#include "core/scene/walker_scatterers.h"
#include "core/common/json_read.h"
#include <gnuradio/sems/core/scene/walker_model.h>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace gr {
namespace sems {
namespace detail {

namespace {

// The peak-speed bound sqrt(RV)·(α·H + β): α in m/s per m of height, β in m/s, at the relative
// velocity RV; linear in between (walker_scatterers.h says how the table was made).
struct peak_speed_node {
    double rv, alpha, beta;
};
constexpr peak_speed_node peak_speed_table[] = {
    { 0.0, 0.0663, 0.0000 },   { 0.005, 0.0493, 0.0000 }, { 0.01, 0.0382, 0.0000 },
    { 0.015, 0.0338, 0.0078 }, { 0.02, 0.0382, 0.0134 },  { 0.03, 0.0712, 0.0184 },
    { 0.05, 0.1480, 0.0345 },  { 0.1, 0.3477, 0.0712 },   { 0.2, 0.7472, 0.1307 },
    { 0.3, 1.1400, 0.1708 },   { 0.4, 1.5217, 0.1912 },   { 0.5, 1.8888, 0.1902 },
    { 0.75, 1.8869, 0.1727 },  { 1.0, 1.8880, 0.1543 },   { 1.3, 1.8905, 0.1307 },
    { 1.6, 1.9205, 0.1187 },   { 2.0, 1.9628, 0.1037 },   { 2.5, 2.0162, 0.0887 },
    { 3.0, 2.0648, 0.0812 },
};
constexpr int n_peak_speed_nodes = sizeof(peak_speed_table) / sizeof(peak_speed_table[0]);
static_assert(peak_speed_table[n_peak_speed_nodes - 1].rv == walker::max_relative_velocity,
              "the peak-speed table covers the model's whole range of RV");

// (α, β) at rv in [0, 3].
std::pair<double, double> peak_speed_coefficients(double rv)
{
    int i = 0;
    while (i + 2 < n_peak_speed_nodes && rv > peak_speed_table[i + 1].rv)
        ++i;
    const auto &a = peak_speed_table[i], &b = peak_speed_table[i + 1];
    const double w = std::clamp((rv - a.rv) / (b.rv - a.rv), 0.0, 1.0);
    return { a.alpha + w * (b.alpha - a.alpha), a.beta + w * (b.beta - a.beta) };
}

// Over RV in [0, rv]: the largest α, and a bound on the largest sqrt(RV)·β (on each piece
// [r_i, r] of the table, sqrt(r) times the larger β at its ends: β is linear there).
std::pair<double, double> peak_speed_maxima_up_to(double rv)
{
    double alpha = peak_speed_coefficients(rv).first, sqrt_rv_beta = 0.0;
    for (int i = 0; i + 1 < n_peak_speed_nodes && peak_speed_table[i].rv <= rv; ++i) {
        const auto& n = peak_speed_table[i];
        const double r = std::min(peak_speed_table[i + 1].rv, rv);
        alpha = std::max(alpha, n.alpha);
        sqrt_rv_beta = std::max(sqrt_rv_beta, std::sqrt(r) * std::max({ 0.0, n.beta, peak_speed_coefficients(r).second }));
    }
    return { alpha, sqrt_rv_beta };
}

} // namespace

double walker_min_height_m() { return walker::min_height_m; }
double walker_max_height_m() { return walker::max_height_m; }
// Feet and hands swing within about a leg length of the pelvis (hip flexion below 50°, a
// step below 0.8 H_t): 0.6 H bounds every segment's centre with margin.
double walker_extent_m(double height_m) { return 0.6 * height_m; }

double walker_peak_speed_mps(double height_m, double speed_mps)
{
    const double v = std::fabs(speed_mps);
    walker::cycle_duration_s(height_m, v); // refuses a height or speed outside the model, naming them
    const double rv = std::min(v / walker::leg_length_m(height_m), walker::max_relative_velocity);
    const auto [alpha, beta] = peak_speed_coefficients(rv);
    return std::sqrt(rv) * (alpha * height_m + beta);
}

double walker_peak_speed_mps(double height_min_m, double height_max_m, double speed_max_mps)
{
    const double v = std::fabs(speed_max_mps);
    walker::cycle_duration_s(height_max_m, 0.0);
    walker::cycle_duration_s(height_min_m, v); // the shortest walker has the highest RV
    if (!(height_min_m <= height_max_m)) {
        std::ostringstream s;
        s << "walker: the height interval [" << height_min_m << ", " << height_max_m << "] m is empty";
        throw std::invalid_argument(s.str());
    }
    // Over heights [h_a, h_b] and speeds up to v: sqrt(RV)·H = sqrt(v'·H/0.53) is at most
    // sqrt(v·h_b/0.53), RV at most v/(0.53·h_a), and α and sqrt(RV)·β at most their largest
    // values below that RV. Pieces (h_max/h_min)^(1/64) ≤ 1.03 wide keep the product within
    // about 2 % of the largest bound of a single walker of the class.
    constexpr int pieces = 64;
    const double ht = walker::proportion::hip_joint_height;
    double best = 0.0;
    for (int j = 0; j < pieces; ++j) {
        const double ha = height_min_m * std::pow(height_max_m / height_min_m, double(j) / pieces);
        const double hb = j + 1 == pieces ? height_max_m
                                          : height_min_m * std::pow(height_max_m / height_min_m, double(j + 1) / pieces);
        const double rv = std::min(v / (ht * ha), walker::max_relative_velocity);
        const auto [alpha, sqrt_rv_beta] = peak_speed_maxima_up_to(rv);
        best = std::max(best, std::sqrt(v * hb / ht) * alpha + sqrt_rv_beta);
    }
    return best;
}

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
