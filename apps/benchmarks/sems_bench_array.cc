// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what an array costs the frequency-domain emulator per frame, against one antenna in
 * the same run. The block itself in a flowgraph:
 *     vector_source (repeat) -> head(n) -> target_channel (N_r outputs) -> N_r null_sinks,
 * with noise, for a 3-path point target, a walker and a quadcopter on one antenna (no array: the
 * single-antenna path) and on ULAs of 2 to 16 elements. Per frame the block draws the frame,
 * computes every stream's factors (array_channel: the bodies' kinematics once, each element's
 * steering, expansion and rows), and per symbol H ⊙ X and noise on every output. Each row is
 * measured --repeat times interleaved with the others, the best kept (a shared machine's least
 * disturbed run); the ratio is to the same scene on one antenna, and over N_r times it (N_r
 * single-antenna emulators). Wall time, and CPU time of all the flowgraph's threads.
 */
#include <gnuradio/blocks/head.h>
#include <gnuradio/blocks/null_sink.h>
#include <gnuradio/blocks/vector_source.h>
#include <gnuradio/sems/blocks/target_channel.h>
#include <gnuradio/sems/core/array/array_geometry.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/top_block.h>
#include <boost/program_options.hpp>
#include <sys/resource.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "count_list.h"
#include "frame_options.h"

namespace po = boost::program_options;
using namespace gr::sems;

namespace {

const char* const scenes[][2] = {
    { "3-path point target",
      R"({"format": "sems.scene", "version": 1, "targets": [{"class": "car", "range_m": 60, "velocity_mps": 15,
          "azimuth_rad": 0.3, "paths": [{}, {"excess_range_m": 7, "power": 0.8}, {"excess_range_m": 14, "power": 0.6}]}]})" },
    { "walker (16 segments)",
      R"({"format": "sems.scene", "version": 1, "targets": [{"class": "pedestrian", "range_m": 30, "speed_mps": 1.4,
          "heading_rad": 1.2, "azimuth_rad": 0.3, "micro_motion": {"model": "walker", "height_m": 1.8}}]})" },
    { "quadcopter (4 x 2 blades)",
      R"({"format": "sems.scene", "version": 1, "targets": [{"class": "drone", "range_m": 60, "velocity_mps": 5,
          "azimuth_rad": 0.3, "micro_motion": {"model": "rotor", "rotors": 4, "blades": 2, "blade_length_m": 0.12,
          "rotation_hz": 100}}]})" },
};

// CPU time of the whole process (all flowgraph threads), user + system, in seconds.
double process_cpu_seconds()
{
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct cost {
    double wall = 0.0; // s per frame
    double cpu = 0.0;  // CPU-s per frame, all threads
};

// The block on `frames` frames of the scene (its array's streams into null sinks).
cost per_frame(const frame_file& frame, const scene& sc, int frames, double snr_db, const std::vector<gr_complex>& x)
{
    const frame_settings& fs = frame.frame;
    const int rx = sc.array() ? sc.array()->n_receive() : 1;
    const size_t item = sizeof(gr_complex) * fs.n_subcarriers;
    auto tb = gr::make_top_block("sems_bench_array");
    auto src = gr::blocks::vector_source_c::make(x, true, fs.n_subcarriers);
    auto head = gr::blocks::head::make(item, uint64_t(frames) * fs.n_symbols);
    auto ch = gr::sems::target_channel::make(sc.to_json_string(), {}, 1, 1, true, "approaching", 0, 0.0, snr_db, 1,
                                             fs.n_symbols, fs.n_subcarriers, fs.bandwidth_hz, fs.carrier_hz,
                                             fs.symbol_interval_s, "paper", 0, "frame",
                                             gr::sems::track_draw_spec{}.coherence_time_s, rx, 1);
    tb->connect(src, 0, head, 0);
    tb->connect(head, 0, ch, 0);
    for (int k = 0; k < rx; ++k)
        tb->connect(ch, k, gr::blocks::null_sink::make(item), 0);
    const double c0 = process_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    tb->run();
    cost c;
    c.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / frames;
    c.cpu = (process_cpu_seconds() - c0) / frames;
    return c;
}

} // namespace

int main(int argc, char** argv)
{
    double seconds = 0.5, snr_db = 20.0;
    int repeat = 3;
    std::string elements_text = "2,4,8,16";
    po::options_description desc("sems_bench_array: the channel's cost per frame with an array, against one antenna in "
                                  "the same run. Options");
    desc.add_options()("help,h", "this help")("seconds", po::value<double>(&seconds)->default_value(seconds),
                                              "wall time per measurement (s)")(
        "repeat", po::value<int>(&repeat)->default_value(repeat), "runs per row, best reported")(
        "snr", po::value<double>(&snr_db)->default_value(snr_db), "SNR in dB (inf = noiseless)")(
        "elements", po::value<std::string>(&elements_text)->default_value(elements_text),
        "ULA sizes N_r to measure, comma-separated (each 2 .. 1024)");
    apps::frame_options frame_flags;
    frame_flags.add_to(desc);
    frame_file frame;
    std::vector<int> sizes;
    try {
        po::variables_map vm;
        po::store(po::parse_command_line(argc, argv, desc), vm);
        po::notify(vm);
        if (vm.count("help")) {
            std::cout << desc << "\n";
            return 0;
        }
        frame = frame_flags.resolve(vm);
        if (!(seconds > 0.0) || !std::isfinite(seconds))
            throw std::invalid_argument("--seconds must be a finite number > 0, got " + std::to_string(seconds));
        if (repeat < 1)
            throw std::invalid_argument("--repeat must be >= 1, got " + std::to_string(repeat));
        if (std::isnan(snr_db) || snr_db == -std::numeric_limits<double>::infinity())
            throw std::invalid_argument("--snr must be a number or inf");
        sizes = apps::parse_counts(elements_text, "--elements", 2, 1024);
    } catch (const std::exception& e) {
        std::cerr << "sems_bench_array: " << e.what() << "\n";
        return 2;
    }
    const frame_settings& fs = frame.frame;
    std::cout << apps::describe(frame) << "\n";
    std::mt19937 gen(1);
    std::normal_distribution<float> g(0.0f, std::sqrt(0.5f));
    std::vector<gr_complex> x(size_t(4) * fs.grid_size()); // a few frames' worth, repeated
    for (auto& v : x)
        v = gr_complex(g(gen), g(gen));

    try {
        const size_t rows = sizes.size() + 1; // N_r = 1 first
        std::printf("sems_bench_array: M = %d, N = %d, SNR %g dB, best of %d runs of %.2f s per row\n",
                    fs.n_subcarriers, fs.n_symbols, snr_db, repeat, seconds);
        std::printf("harness: vector_source(repeat) -> head -> target_channel -> N_r null_sinks, top_block::run\n\n");
        std::printf("%-28s %5s %11s %9s %10s %13s %9s %10s\n", "scene", "N_r", "us/frame", "vs N_r=1", "vs N_r x 1",
                    "CPU-us/frame", "vs N_r=1", "vs N_r x 1");
        for (const auto& s : scenes) {
            const scene base = scene::parse(s[1], s[0]);
            std::vector<scene> variants = { base };
            for (int k : sizes)
                variants.push_back(base.with_array(array_geometry::ula(k, 0.5 * fs.wavelength_m())));
            std::vector<cost> best(rows, cost{ std::numeric_limits<double>::infinity(),
                                               std::numeric_limits<double>::infinity() });
            std::vector<int> frames(rows, 0);
            for (size_t i = 0; i < rows; ++i) { // calibrate: frames for about `seconds`
                const double t = per_frame(frame, variants[i], 20, snr_db, x).wall;
                frames[i] = std::max(20, static_cast<int>(seconds / std::max(t, 1e-9)));
            }
            for (int k = 0; k < repeat; ++k)
                for (size_t i = 0; i < rows; ++i) {
                    const cost c = per_frame(frame, variants[i], frames[i], snr_db, x);
                    best[i].wall = std::min(best[i].wall, c.wall);
                    best[i].cpu = std::min(best[i].cpu, c.cpu);
                }
            for (size_t i = 0; i < rows; ++i) {
                const int nr = i == 0 ? 1 : sizes[i - 1];
                std::printf("%-28s %5d %11.1f %8.2fx %9.2fx %13.1f %8.2fx %9.2fx\n", s[0], nr, 1e6 * best[i].wall,
                            best[i].wall / best[0].wall, best[i].wall / (nr * best[0].wall), 1e6 * best[i].cpu,
                            best[i].cpu / best[0].cpu, best[i].cpu / (nr * best[0].cpu));
            }
        }
        std::printf("\nvs N_r=1: the scene's cost per frame over its cost on one antenna, same run and harness;\n"
                    "vs N_r x 1: over N_r single-antenna emulators. CPU: all the flowgraph's threads.\n");
    } catch (const std::exception& e) {
        std::cerr << "sems_bench_array: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
