// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_mimo_mask: learn which pilots each transmit element of a MIMO array sends, for a
 * target's azimuth, and write the MIMO mask (learning/array/mimo_mask_learner.h).
 *
 *   sems_mimo_mask --array mimo2x4_3g --pilots 32 --out mimo_mask.json
 *   sems_mimo_mask --array my_array.json --frame sdr_2g4_20mhz --pilots 64 --azimuth-min -0.5 --azimuth-max 0.5 --out m.json
 *
 * It ends with the learned mask's bound beside the hand forms' (same pilots, time division,
 * frequency division, each on its best standard pattern) and the virtual array's floor, all as
 * the root mean CRB of the azimuth at 0 dB per pilot over the scene's azimuths.
 */
#include "command_line.h"
#include "frame_options.h"
#include <gnuradio/sems/baselines/angle_estimators.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/learning/array/mimo_mask_learner.h>
#include <boost/program_options.hpp>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>

namespace po = boost::program_options;
using namespace gr::sems;

namespace {

// The best of one hand form over the standard patterns: its mean bound and the pattern's name.
std::pair<double, std::string> best_hand_form(const array_geometry& a, const mimo_mask_settings& s,
                                              mimo_mask (*form)(const pilot_mask&, int))
{
    std::pair<double, std::string> best{ std::numeric_limits<double>::infinity(), "none" };
    for (const std::string pattern : { "uniform", "random", "doppler", "staggered", "burst" }) {
        try {
            const auto m = form(pilot_mask::from_pattern(pattern, s.frame, s.n_pilots, s.seed), a.n_transmit());
            const double v =
                mimo_mean_crb_rad2(a, m, s.frame, s.azimuth_min_rad, s.azimuth_max_rad, s.eval_azimuths, s.elevation_rad);
            if (v < best.first)
                best = { v, pattern };
        } catch (const std::invalid_argument&) {
            // a pattern on one symbol (or subcarrier) has no time (frequency) division
        }
    }
    return best;
}

} // namespace

int main(int argc, char** argv)
{
    mimo_mask_settings s;
    std::string out;
    bool quiet = false;
    po::options_description opts("sems_mimo_mask: learn a MIMO mask (each pilot's transmit element) for a target's azimuth");
    apps::frame_options frame_flags;
    // clang-format off
    opts.add_options()
        ("help,h", "this help")
        ("array", po::value(&s.array)->default_value(s.array), "the array: a preset's name or an array file (two or more transmit elements)")
        ("pilots", po::value(&s.n_pilots)->default_value(s.n_pilots), "N_p, the pilots of all transmit elements together")
        ("azimuth-min", po::value(&s.azimuth_min_rad)->default_value(s.azimuth_min_rad), "the scene's azimuths: lower end (rad)")
        ("azimuth-max", po::value(&s.azimuth_max_rad)->default_value(s.azimuth_max_rad), "the scene's azimuths: upper end (rad)")
        ("elevation", po::value(&s.elevation_rad)->default_value(s.elevation_rad), "the targets' elevation (rad)")
        ("epochs", po::value(&s.epochs)->default_value(s.epochs), "epochs")
        ("steps", po::value(&s.steps)->default_value(s.steps), "steps per epoch")
        ("draws", po::value(&s.draws)->default_value(s.draws), "azimuths drawn per step")
        ("eval-azimuths", po::value(&s.eval_azimuths)->default_value(s.eval_azimuths), "azimuths of the grid the kept mask is chosen on")
        ("lr", po::value(&s.lr)->default_value(s.lr), "base learning rate: Adam's is --lr times --lr-scale, for every score")
        ("lr-scale", po::value(&s.encoder.lr_scale)->default_value(s.encoder.lr_scale), "Adam's learning rate over --lr (the semantic encoder's convention)")
        ("temp-start", po::value(&s.encoder.temperature_start)->default_value(s.encoder.temperature_start), "Gumbel temperature at the start")
        ("temp-floor", po::value(&s.encoder.temperature_floor)->default_value(s.encoder.temperature_floor), "Gumbel temperature floor")
        ("temp-decay", po::value(&s.encoder.temperature_decay)->default_value(s.encoder.temperature_decay), "temperature factor per epoch")
        ("seed", po::value(&s.seed)->default_value(s.seed), "seed of the draws and the initial scores (and of the random pattern it is compared with)")
        ("threads", po::value(&s.threads)->default_value(1), "LibTorch threads")
        ("quiet", po::bool_switch(&quiet), "no per-epoch progress")
        ("out", po::value(&out)->required(), "the MIMO mask file to write (format sems.mimo_mask)");
    // clang-format on
    frame_flags.add_to(opts);
    try {
        po::variables_map vm;
        po::store(po::parse_command_line(argc, argv, opts), vm);
        if (vm.count("help")) {
            std::cout << opts << std::endl;
            return 0;
        }
        po::notify(vm);
        const auto frame = frame_flags.resolve(vm);
        s.frame = frame.frame;
        s.verbose = !quiet;
        s.command_line = apps::command_of(argc, argv);
        std::cout << apps::describe(frame) << std::endl;
        const auto r = learn_mimo_mask(s, &std::cout);
        r.mask.save(out);
        const auto a = array_geometry::find(s.array);
        const double floor = mimo_floor_crb_rad2(a, s.frame, s.n_pilots, s.azimuth_min_rad, s.azimuth_max_rad,
                                                 s.eval_azimuths, s.elevation_rad);
        std::cout << "wrote " << out << "\nroot mean CRB of the azimuth at 0 dB per pilot over [" << s.azimuth_min_rad
                  << ", " << s.azimuth_max_rad << "] rad:\n"
                  << std::setprecision(4) << "  learned                " << 1e3 * std::sqrt(r.mean_crb_rad2) << " mrad\n";
        const std::pair<const char*, mimo_mask (*)(const pilot_mask&, int)> forms[] = {
            { "same pilots", &mimo_mask::same_pilots },
            { "time division", &mimo_mask::time_division },
            { "frequency division", &mimo_mask::frequency_division }
        };
        for (const auto& [name, form] : forms) {
            const auto [v, pattern] = best_hand_form(a, s, form);
            std::cout << "  " << std::left << std::setw(22) << name << " " << 1e3 * std::sqrt(v) << " mrad (" << pattern
                      << " pattern)\n";
        }
        std::cout << "  virtual array floor    " << 1e3 * std::sqrt(floor) << " mrad" << std::endl;
    } catch (const po::error& e) {
        std::cerr << "sems_mimo_mask: " << e.what() << "\n" << opts << std::endl;
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "sems_mimo_mask: " << e.what() << std::endl;
        return 1;
    }
    return 0;
}
