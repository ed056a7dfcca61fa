// SPDX-License-Identifier: GPL-3.0-or-later
/*
 * sems_gallery: the slow time of one subcarrier for one target of each class of the
 * kinematic library (docs/reference/micro_doppler_gallery.md).
 *
 * Each class's fixed scene (examples/scenes/<class>.json: one target, heading 0, fading
 * "none") runs through the channel model on the paper's frame (3 GHz, 30 MHz, 1 ms, N = 32,
 * M = 64), noiseless, over consecutive frames (frame f holds slow time f·N .. f·N + N − 1).
 * One CSV per class, <out>/<class>.csv: a header of "# key = value" lines recording the
 * scene, the frame and what the physics predicts (body line, limb / blade / wheel Doppler,
 * blade flash times), then "n,t_s,re,im" rows of H[n, m] at the chosen subcarrier m.
 * apps/figures/plot_gallery.py draws the spectrograms; apps/figures/check_gallery.py tests the predictions.
 */
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/scene/micro_motion.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sems/core/scene/walker_model.h>
#include <boost/program_options.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#ifndef SEMS_GALLERY_SCENES_DIR
#define SEMS_GALLERY_SCENES_DIR ""
#endif

namespace po = boost::program_options;
using namespace gr::sems;

namespace {

struct options {
    std::string scenes = SEMS_GALLERY_SCENES_DIR;
    std::string out = ".";
    std::vector<std::string> classes{ "adult", "child", "quadcopter", "hexacopter", "car", "bicyclist" };
    int frames = 64;
    int subcarrier = 32;
};

std::string read_text(const std::string& path)
{
    std::ifstream f(path);
    if (!f)
        throw std::runtime_error("sems_gallery: cannot read scene file " + path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

std::string num(double v)
{
    char b[64];
    std::snprintf(b, sizeof b, "%.10g", v);
    return b;
}

// "# key = value" lines: what the physics predicts for this target (Doppler in Hz, + = approaching).
struct header {
    std::vector<std::pair<std::string, std::string>> rows;
    void add(const std::string& k, const std::string& v) { rows.emplace_back(k, v); }
    void add(const std::string& k, double v) { add(k, num(v)); }
};

void predictions(const frame_settings& fs, const target_spec& t, const std::string& path, header& h)
{
    const double lambda = fs.wavelength_m();
    const double speed = std::isnan(t.speed_mps) ? std::fabs(t.velocity_mps) : t.speed_mps;
    const double body = fs.doppler_from_velocity(t.velocity_mps);
    h.add("speed_mps", speed);
    h.add("heading_rad", t.heading_rad);
    h.add("velocity_mps", t.velocity_mps);
    h.add("body_hz", body); // the body / torso line, 2v/λ
    if (!t.motion)
        throw std::runtime_error("sems_gallery: " + path + ": targets[0] has no micro_motion");
    const micro_motion& m = *t.motion;
    h.add("model", micro_motion_model(m));
    if (const auto* w = std::get_if<walker_motion>(&m)) {
        h.add("height_m", w->height_m);
        h.add("gait_cycle_s", walker::cycle_duration_s(w->height_m, speed));
        // Boulic–Thalmann: the swinging foot peaks near 4·v (docs/reference/walker_kinematics.md),
        // the stance foot rests near 0.
        h.add("feet_swing_peak_hz", 4.0 * body);
        h.add("stance_hz", 0.0);
    } else if (const auto* r = std::get_if<rotor_motion>(&m)) {
        const double f = r->rotation_hz.front(), phi = r->phase_rad.front();
        for (double x : r->rotation_hz)
            if (x != f)
                throw std::runtime_error("sems_gallery: " + path + ": the flash prediction needs one rotation_hz for every rotor");
        for (double x : r->phase_rad)
            if (x != phi)
                throw std::runtime_error("sems_gallery: " + path + ": the flash prediction needs one phase_rad for every rotor");
        const int K = r->blades;
        h.add("rotors", r->rotors);
        h.add("blades", K);
        h.add("blade_length_m", r->blade_length_m);
        h.add("rotation_hz", f);
        h.add("phase_rad", phi);
        h.add("elevation_rad", r->elevation_rad);
        h.add("body_power", r->body_power);
        // Blade tips: ±(2/λ)·2π f L cos β about the body line.
        h.add("tip_doppler_hz", 2.0 / lambda * 2.0 * M_PI * f * r->blade_length_m * std::cos(r->elevation_rad));
        // A blade flashes when perpendicular to the line of sight: cos(2π f t + φ + 2πk/K) = 0.
        // Even K: blades k and k + K/2 flash together, every 1/(K f); odd K: every 1/(2K f).
        const double period = (K % 2 == 0) ? 1.0 / (K * f) : 1.0 / (2.0 * K * f);
        double first = 1e300;
        for (int k = 0; k < K; ++k) {
            double a = std::fmod(M_PI / 2 - phi - 2.0 * M_PI * k / K, M_PI);
            if (a < 0)
                a += M_PI;
            first = std::min(first, a / (2.0 * M_PI * f));
        }
        h.add("flash_period_s", period);
        h.add("first_flash_s", first);
    } else if (const auto* w = std::get_if<wheels_motion>(&m)) {
        const double roll = fs.doppler_from_velocity(speed * std::cos(t.heading_rad));
        h.add("wheels", w->wheels);
        h.add("wheel_radius_m", w->wheel_radius_m);
        h.add("rim_points", w->rim_points);
        h.add("spokes", w->spokes);
        h.add("body_power", w->body_power);
        h.add("wheel_rev_hz", speed / (2.0 * M_PI * w->wheel_radius_m));
        h.add("wheel_top_hz", body + roll);     // the top of a rim moves at twice the body's speed
        h.add("wheel_contact_hz", body - roll); // the contact point rests on the road
    } else if (const auto* s = std::get_if<scatterers_motion>(&m)) {
        std::vector<double> rates;
        double peak = 0.0;
        for (const auto& p : s->scatterers) {
            double v = 0.0;
            for (const auto& hm : p.harmonics) {
                v += 2.0 * M_PI * hm.rate_hz * hm.amplitude_m;
                if (hm.rate_hz > 0 && std::find(rates.begin(), rates.end(), hm.rate_hz) == rates.end())
                    rates.push_back(hm.rate_hz);
            }
            peak = std::max(peak, v);
        }
        std::string list;
        for (double r : rates)
            list += (list.empty() ? "" : " ") + num(r);
        h.add("scatterers", double(s->scatterers.size()));
        h.add("sideband_rates_hz", list); // sidebands at body ± multiples of each rate
        h.add("scatterer_max_hz", body + fs.doppler_from_velocity(peak));
        h.add("scatterer_min_hz", body - fs.doppler_from_velocity(peak));
    }
}

void run_class(const options& o, const std::string& name)
{
    const std::string path = o.scenes + "/" + name + ".json";
    const scene s = scene::parse(read_text(path), path);
    if (s.targets().size() != 1)
        throw std::runtime_error("sems_gallery: " + path + ": needs exactly one target");
    const frame_settings fs; // the paper's frame: 3 GHz, 30 MHz, 1 ms, N = 32, M = 64
    if (o.subcarrier < 0 || o.subcarrier >= fs.n_subcarriers)
        throw std::runtime_error("sems_gallery: --subcarrier must be in [0, " + std::to_string(fs.n_subcarriers) + ")");
    const target_spec& t = s.targets().front();

    header h;
    h.add("class", s.class_name(t.cls));
    h.add("library", s.library().name());
    h.add("scene", path);
    h.add("carrier_hz", fs.carrier_hz);
    h.add("bandwidth_hz", fs.bandwidth_hz);
    h.add("symbol_interval_s", fs.symbol_interval_s);
    h.add("n_symbols", fs.n_symbols);
    h.add("n_subcarriers", fs.n_subcarriers);
    h.add("subcarrier", o.subcarrier);
    h.add("frames", o.frames);
    h.add("wavelength_m", fs.wavelength_m());
    h.add("range_m", t.range_m);
    predictions(fs, t, path, h);

    channel_model cm(fs, s, 1);
    std::vector<gr_complex> grid(size_t(o.frames) * fs.grid_size());
    cm.generate(size_t(o.frames), grid.data(), 0); // noiseless, consecutive frames: continuous slow time

    const std::string out = o.out + "/" + name + ".csv";
    std::ofstream f(out);
    if (!f)
        throw std::runtime_error("sems_gallery: cannot write " + out);
    f << "# sems_gallery: slow time of one subcarrier, H[n, m] (noiseless, fading none)\n";
    for (const auto& [k, v] : h.rows)
        f << "# " << k << " = " << v << "\n";
    f << "n,t_s,re,im\n";
    const size_t rows = size_t(o.frames) * fs.n_symbols;
    char line[128];
    for (size_t n = 0; n < rows; ++n) {
        const gr_complex v = grid[n * fs.n_subcarriers + o.subcarrier];
        std::snprintf(line, sizeof line, "%zu,%.6f,%.9g,%.9g\n", n, n * fs.symbol_interval_s, v.real(), v.imag());
        f << line;
    }
    if (!f)
        throw std::runtime_error("sems_gallery: error writing " + out);
    std::cout << out << ": " << s.class_name(t.cls) << ", " << rows << " symbols\n";
}

} // namespace

int main(int argc, char** argv)
{
    options o;
    po::options_description desc(
        "sems_gallery: slow time of one subcarrier per class of the kinematic library, one CSV per class\n"
        "(header: the scene, the frame and the predicted Doppler lines; rows n,t_s,re,im).\nOptions");
    desc.add_options()("help,h", "this help")(
        "scenes", po::value<std::string>(&o.scenes)->default_value(o.scenes), "folder of <class>.json fixed scenes")(
        "out", po::value<std::string>(&o.out)->default_value(o.out), "folder for <class>.csv (created if missing)")(
        "classes", po::value<std::vector<std::string>>(&o.classes)->multitoken(), "classes (default: all six of the kinematic library)")(
        "frames", po::value<int>(&o.frames)->default_value(o.frames), "consecutive frames of N = 32 symbols (T = 1 ms)")(
        "subcarrier", po::value<int>(&o.subcarrier)->default_value(o.subcarrier), "subcarrier m of the series");
    try {
        po::variables_map vm;
        po::store(po::parse_command_line(argc, argv, desc), vm);
        po::notify(vm);
        if (vm.count("help")) {
            std::cout << desc << "\n";
            return 0;
        }
        if (o.frames < 1 || o.frames > 4096)
            throw std::runtime_error("sems_gallery: --frames must be in [1, 4096], got " + std::to_string(o.frames));
        if (o.classes.empty())
            throw std::runtime_error("sems_gallery: --classes names no class");
        std::filesystem::create_directories(o.out);
        for (const auto& c : o.classes)
            run_class(o, c);
    } catch (const std::exception& e) {
        std::cerr << e.what() << "\n";
        return 1;
    }
    return 0;
}
