// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the frame flags the programs that draw frames share (sems_train, sems_eval,
 * sems_bench_channel, sems_bench_array), spelled
 * once: --frame (a frame file or a preset's name) and one override per field.
 *
 *   sems_train --frame sdr_2g4_20mhz ...              (the preset as it is)
 *   sems_train --frame nr_30khz --symbols 4 ...       (the preset with fewer symbols)
 *   sems_train --subcarriers 128 --guards 0,62-66 ... (the paper's frame, changed)
 *
 * The frame used is printed when the program starts (describe()) and recorded in the
 * bundles it writes. docs/reference/frame_files.md lists the fields.
 */
#ifndef INCLUDED_SEMS_APPS_FRAME_OPTIONS_H
#define INCLUDED_SEMS_APPS_FRAME_OPTIONS_H

#include <gnuradio/sems/core/frame/frame_settings.h>
#include <boost/program_options.hpp>
#include <algorithm>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace apps {

/*! The frame flags; add_to() registers them, resolve() reads them after notify(). */
class frame_options
{
public:
    //! Registers --frame, --symbols, --subcarriers, --bandwidth-hz, --carrier-hz,
    //! --symbol-interval-s, --cp and --guards in `o`.
    void add_to(boost::program_options::options_description& o)
    {
        namespace po = boost::program_options;
        po::options_description f("Frame (a frame file or preset, then per-field overrides)");
        // clang-format off
        f.add_options()
            ("frame", po::value(&d_frame)->default_value("paper"),
             "the frame: a preset's name (paper, sdr_2g4_20mhz, wifi_5g_80mhz, nr_30khz, nr_sensing_120khz, "
             "auto_77g) or a frame file (format sems.frame)")
            ("symbols", po::value<int>(), "override N, OFDM symbols per frame")
            ("subcarriers", po::value<int>(), "override M, subcarriers per symbol (clears the frame's guards unless --guards is given)")
            ("bandwidth-hz", po::value<double>(), "override B, the bandwidth in Hz")
            ("carrier-hz", po::value<double>(), "override f_c, the carrier in Hz")
            ("symbol-interval-s", po::value<double>(), "override T, the symbol interval in s")
            ("cp", po::value<int>(), "override the cyclic prefix in samples")
            ("guards", po::value<std::string>(),
             "override the guard subcarriers: comma-separated m and first-last runs (e.g. 0,28-36), or none");
        // clang-format on
        o.add(f);
    }

    /*!
     * The frame file named by --frame with every override applied and validated.
     * Throws std::invalid_argument naming the flag.
     */
    frame_file resolve(const boost::program_options::variables_map& vm) const
    {
        frame_file f = frame_file::find(d_frame);
        frame_settings& fs = f.frame;
        bool changed = false;
        auto set = [&](const char* flag, auto& field) {
            if (vm.count(flag)) {
                field = vm[flag].as<std::decay_t<decltype(field)>>();
                changed = true;
            }
        };
        set("symbols", fs.n_symbols);
        if (vm.count("subcarriers") && !vm.count("guards"))
            fs.guard_subcarriers.clear(); // the guards were indices of the other M
        set("subcarriers", fs.n_subcarriers);
        set("bandwidth-hz", fs.bandwidth_hz);
        set("carrier-hz", fs.carrier_hz);
        set("symbol-interval-s", fs.symbol_interval_s);
        set("cp", fs.cp_len);
        if (vm.count("guards")) {
            fs.guard_subcarriers = parse_guards(vm["guards"].as<std::string>());
            changed = true;
        }
        try {
            fs.validate();
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(std::string("--frame ") + d_frame + (changed ? " with the overrides" : "") +
                                        ": " + e.what());
        }
        if (changed)
            f.name += " (changed by flags)";
        return f;
    }

    //! True if any frame flag was given on the command line.
    static bool given(const boost::program_options::variables_map& vm)
    {
        for (const char* k : { "symbols", "subcarriers", "bandwidth-hz", "carrier-hz", "symbol-interval-s", "cp",
                               "guards" })
            if (vm.count(k))
                return true;
        return vm.count("frame") && !vm["frame"].defaulted();
    }

    //! "0,28-36,63" or "none" -> the sorted subcarriers; a repeated one is refused.
    static std::vector<int> parse_guards(const std::string& text)
    {
        std::vector<int> out;
        if (text == "none" || text.empty())
            return out;
        std::stringstream ss(text);
        std::string item;
        while (std::getline(ss, item, ',')) {
            const auto dash = item.find('-', 1);
            const int lo = to_int(item.substr(0, dash), text);
            const int hi = dash == std::string::npos ? lo : to_int(item.substr(dash + 1), text);
            if (hi < lo)
                throw std::invalid_argument("--guards " + text + ": the run " + item + " needs first <= last");
            for (int m = lo; m <= hi; ++m)
                out.push_back(m);
        }
        std::sort(out.begin(), out.end());
        const auto dup = std::adjacent_find(out.begin(), out.end());
        if (dup != out.end())
            throw std::invalid_argument("--guards " + text + ": subcarrier " + std::to_string(*dup) +
                                        " is listed twice");
        return out;
    }

private:
    static int to_int(const std::string& s, const std::string& text)
    {
        size_t used = 0;
        int v = 0;
        try {
            v = std::stoi(s, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != s.size())
            throw std::invalid_argument("--guards " + text + ": \"" + s + "\" is not a subcarrier index");
        return v;
    }

    std::string d_frame;
};

//! One line for people: the frame's name, its fields and what they allow.
inline std::string describe(const frame_file& f)
{
    const frame_settings& fs = f.frame;
    std::ostringstream s;
    s << "frame " << (f.name.empty() ? std::string("(unnamed)") : f.name) << ": N = " << fs.n_symbols
      << " symbols x M = " << fs.n_subcarriers << " subcarriers";
    if (!fs.guard_subcarriers.empty())
        s << " (" << fs.guard_subcarriers.size() << " guards, " << fs.usable_subcarriers().size() << " usable)";
    s << std::setprecision(6) << ", B = " << fs.bandwidth_hz / 1e6 << " MHz (spacing " << fs.subcarrier_spacing_hz() / 1e3
      << " kHz), f_c = " << fs.carrier_hz / 1e9 << " GHz, T = " << fs.symbol_interval_s * 1e6 << " us, CP = "
      << fs.cp_len << " samples; unambiguous range " << fs.max_range_m() << " m, Doppler +/-" << fs.max_doppler_hz()
      << " Hz (+/-" << fs.max_speed_mps() << " m/s)";
    return s.str();
}

} // namespace apps
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_APPS_FRAME_OPTIONS_H */
