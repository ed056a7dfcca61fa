// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: throughput of the target_channel emulator in OFDM symbols/s, for fixed
 * scenes of 1, 3 and 10 paths, a walker and a quadcopter, with noise, next to GNU Radio's
 * multiply_const_vcc on the same vector size, all in the same harness and run (and, with
 * --scatterers, the cost per frame of a point-scatterer target against its scatterer count):
 *     vector_source (repeat) -> block -> head -> null_sink, top_block::run, wall time.
 * Each row is measured --repeat times, interleaved with the other rows, and the best
 * run is reported: on a shared machine the best run is the one least disturbed. Two
 * figures per row: symbols per wall second, and symbols per CPU second of the whole
 * process (all flowgraph threads), which a loaded machine disturbs less.
 */
#include <gnuradio/blocks/head.h>
#include <gnuradio/blocks/multiply_const_v.h>
#include <gnuradio/blocks/null_sink.h>
#include <gnuradio/blocks/vector_source.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sems/blocks/target_channel.h>
#include <gnuradio/top_block.h>
#include <boost/program_options.hpp>
#include <sys/resource.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "frame_options.h"

namespace po = boost::program_options;
using namespace gr::sems;

namespace {

struct options {
    double seconds = 1.0;
    int repeat = 3;
    double snr_db = 20.0;
    bool scatterer_table = false;
    int n_symbols = 0;     // from the frame flags
    int n_subcarriers = 0; // from the frame flags
};

// One car with `paths` paths (excess ranges 0, 7, 14, ... m, 1 dB weaker each);
// optionally a drone with micro-Doppler instead, to show what that term costs.
std::string scene_json(int paths, bool micro_doppler)
{
    target_spec t;
    if (micro_doppler) {
        t.cls = target_class::drone;
        t.velocity_mps = 7.0;
        t.md = gr::sems::micro_doppler{ 100.0, 0.01, 0.0 };
    } else {
        t.cls = target_class::car;
        t.velocity_mps = 15.0;
    }
    t.range_m = 60.0;
    t.paths.clear();
    for (int k = 0; k < paths; ++k)
        t.paths.push_back(path_spec{ 7.0 * k, std::pow(10.0, -0.1 * k) });
    return scene::fixed({ t }).to_json_string();
}

// One target with a micro-motion model (JSON of "micro_motion"), single path.
std::string motion_scene_json(const std::string& motion, double velocity)
{
    return R"({"format": "sems.scene", "version": 1, "targets": [{"class": "pedestrian", "range_m": 60, "velocity_mps": )" +
           std::to_string(velocity) + R"(, "micro_motion": )" + motion + "}]}";
}

// `count` point scatterers, one harmonic each (0.05-0.3 m, 0.5-5 Hz: limb-like motion).
std::string scatterers_json(int count)
{
    std::string j = R"({"model": "scatterers", "scatterers": [)";
    for (int i = 0; i < count; ++i)
        j += std::string(i ? "," : "") + R"({"power": 1, "harmonics": [{"amplitude_m": )" +
             std::to_string(0.05 + 0.25 * (i % 7) / 6.0) + R"(, "rate_hz": )" + std::to_string(0.5 + 4.5 * (i % 5) / 4.0) +
             R"(, "phase_rad": )" + std::to_string(0.7 * i) + "}]}";
    return j + "]}";
}

// CPU time of the whole process (all flowgraph threads), user + system, in seconds.
double process_cpu_seconds()
{
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct timing {
    double wall = 0.0; // s
    double cpu = 0.0;  // s, all threads
};

// Runs source -> block -> head(n) -> sink and returns its wall and CPU time.
timing time_run(const options& o, const std::vector<gr_complex>& data, gr::basic_block_sptr block, uint64_t n)
{
    const size_t item = sizeof(gr_complex) * o.n_subcarriers;
    auto tb = gr::make_top_block("sems_bench_channel");
    auto src = gr::blocks::vector_source_c::make(data, true, o.n_subcarriers);
    auto head = gr::blocks::head::make(item, n);
    auto sink = gr::blocks::null_sink::make(item);
    tb->connect(src, 0, block, 0);
    tb->connect(block, 0, head, 0);
    tb->connect(head, 0, sink, 0);
    const double c0 = process_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    tb->run();
    timing t;
    t.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    t.cpu = process_cpu_seconds() - c0;
    return t;
}

struct rate {
    double wall = 0.0; // symbols per wall second
    double cpu = 0.0;  // symbols per CPU second (all threads of the flowgraph)
};

// Symbols/s for a block made fresh per run: a short calibration run, then one of ~seconds.
rate symbols_per_second(const options& o,
                        const std::vector<gr_complex>& data,
                        const std::function<gr::basic_block_sptr()>& make)
{
    uint64_t n = 1 << 14;
    double t = time_run(o, data, make(), n).wall;
    while (t < 0.05 && n < (uint64_t(1) << 40)) { // grow until the calibration is measurable
        n *= 4;
        t = time_run(o, data, make(), n).wall;
    }
    const uint64_t target = static_cast<uint64_t>(std::max(1.0, o.seconds * n / t));
    const timing r = time_run(o, data, make(), target);
    return { target / r.wall, target / r.cpu };
}

} // namespace

int main(int argc, char** argv)
{
    options o;
    po::options_description desc(
        "sems_bench_channel: target_channel throughput (OFDM symbols/s) for 1-, 3- and 10-path fixed\n"
        "scenes next to blocks::multiply_const_vcc, same harness, same run. Options");
    desc.add_options()("help,h", "this help")(
        "seconds", po::value<double>(&o.seconds)->default_value(o.seconds), "wall time per measurement (s)")(
        "repeat", po::value<int>(&o.repeat)->default_value(o.repeat), "runs per row, best reported")(
        "snr", po::value<double>(&o.snr_db)->default_value(o.snr_db), "SNR in dB for the channel runs (inf = noiseless)")(
        "scatterers", po::bool_switch(&o.scatterer_table), "also: cost per frame of a point-scatterer target, 1 to 256 scatterers");
    apps::frame_options frame_flags;
    frame_flags.add_to(desc);
    frame_file frame;
    try {
        po::variables_map vm;
        po::store(po::parse_command_line(argc, argv, desc), vm);
        po::notify(vm);
        frame = frame_flags.resolve(vm);
        o.n_symbols = frame.frame.n_symbols;
        o.n_subcarriers = frame.frame.n_subcarriers;
        if (vm.count("help")) {
            std::cout << desc << "\n";
            return 0;
        }
        if (!(o.seconds > 0.0) || !std::isfinite(o.seconds))
            throw std::invalid_argument("--seconds must be a finite number > 0");
        if (std::isnan(o.snr_db) || o.snr_db == -std::numeric_limits<double>::infinity())
            throw std::invalid_argument("--snr must be a number or inf");
        if (o.repeat < 1)
            throw std::invalid_argument("--repeat must be >= 1");
    } catch (const std::exception& e) {
        std::cerr << "sems_bench_channel: " << e.what() << "\n";
        return 2;
    }

    // Random input symbols, a few frames' worth, repeated.
    std::mt19937 gen(1);
    std::normal_distribution<float> g(0.0f, std::sqrt(0.5f));
    std::vector<gr_complex> data(size_t(4) * o.n_symbols * o.n_subcarriers);
    for (auto& x : data)
        x = gr_complex(g(gen), g(gen));

    const frame_settings& fs = frame.frame;
    std::cout << apps::describe(frame) << "\n";
    auto channel = [&](int paths, bool md, double snr) {
        return [=, &o]() -> gr::basic_block_sptr {
            return target_channel::make(scene_json(paths, md), {}, 1, 1, true, "approaching", 0, 0.0, snr, 1, o.n_symbols,
                                        o.n_subcarriers, fs.bandwidth_hz, fs.carrier_hz, fs.symbol_interval_s);
        };
    };
    auto motion_channel = [&](const std::string& motion, double velocity, double snr) {
        return [=, &o]() -> gr::basic_block_sptr {
            return target_channel::make(motion_scene_json(motion, velocity), {}, 1, 1, true, "approaching", 0, 0.0, snr, 1,
                                        o.n_symbols, o.n_subcarriers, fs.bandwidth_hz, fs.carrier_hz, fs.symbol_interval_s);
        };
    };
    struct row {
        std::string name;
        std::function<gr::basic_block_sptr()> make;
    };
    char snr_text[32];
    std::snprintf(snr_text, sizeof snr_text, "SNR %g dB", o.snr_db);
    const std::vector<row> rows = {
        { "blocks.multiply_const_vcc",
          [&]() -> gr::basic_block_sptr {
              return gr::blocks::multiply_const_vcc::make(std::vector<gr_complex>(o.n_subcarriers, 0.5f));
          } },
        { "target_channel,  1 path,  " + std::string(snr_text), channel(1, false, o.snr_db) },
        { "target_channel,  3 paths, " + std::string(snr_text), channel(3, false, o.snr_db) },
        { "target_channel, 10 paths, " + std::string(snr_text), channel(10, false, o.snr_db) },
        { "target_channel,  1 path + micro-Doppler, " + std::string(snr_text), channel(1, true, o.snr_db) },
        { "target_channel, walker (16 segments), " + std::string(snr_text),
          motion_channel(R"({"model": "walker", "height_m": 1.8})", 1.4, o.snr_db) },
        { "target_channel, quadcopter (4 x 2 blades), " + std::string(snr_text),
          motion_channel(R"({"model": "rotor", "rotors": 4, "blades": 2, "blade_length_m": 0.12, "rotation_hz": 100})",
                         5.0, o.snr_db) },
        { "target_channel,  3 paths, noiseless", channel(3, false, std::numeric_limits<double>::infinity()) },
        { "target_channel, 10 paths, noiseless", channel(10, false, std::numeric_limits<double>::infinity()) },
    };

    std::printf("sems_bench_channel: M = %d subcarriers, N = %d symbols/frame, best of %d runs of %.1f s per row\n",
                o.n_subcarriers, o.n_symbols, o.repeat, o.seconds);
    std::printf("harness: vector_source(repeat) -> block -> head -> null_sink, top_block::run, wall time\n\n");
    std::vector<rate> best(rows.size());
    try {
        for (int k = 0; k < o.repeat; ++k)
            for (size_t i = 0; i < rows.size(); ++i) {
                const rate r = symbols_per_second(o, data, rows[i].make);
                best[i].wall = std::max(best[i].wall, r.wall);
                best[i].cpu = std::max(best[i].cpu, r.cpu);
            }
        std::printf("%-52s %12s %12s %9s %14s %9s\n", "block", "symbols/s", "samples/s", "vs mult.",
                    "symbols/CPU-s", "vs mult.");
        for (size_t i = 0; i < rows.size(); ++i)
            std::printf("%-52s %12.4g %12.4g %8.2fx %14.4g %8.2fx\n", rows[i].name.c_str(), best[i].wall,
                        best[i].wall * o.n_subcarriers, best[i].wall / best[0].wall, best[i].cpu,
                        best[i].cpu / best[0].cpu);
        std::printf("\nwall: symbols per second of wall time (the harness's throughput); CPU-s: symbols per\n"
                    "second of CPU time summed over the flowgraph's threads (steadier on a shared machine).\n");
        if (o.scatterer_table) {
            // A point-scatterer target's cost per frame against its scatterer count, same harness.
            std::printf("\npoint-scatterer target (one harmonic each), %s: cost per frame of %d symbols\n", snr_text,
                        o.n_symbols);
            std::printf("%12s %14s %14s %12s %16s %12s\n", "scatterers", "us/frame", "us/frame mult.", "vs mult.",
                        "CPU-us/frame", "vs mult.");
            // Interleaved like the rows above: the anchor again and every count once per round, the
            // best of the rounds (the anchor measured beside the table, not only before it).
            const std::vector<int> counts = { 1, 2, 4, 8, 16, 32, 64, 128, 256 };
            std::vector<rate> table(counts.size());
            rate anchor{};
            for (int k = 0; k < o.repeat; ++k) {
                const rate a = symbols_per_second(o, data, rows[0].make);
                anchor.wall = std::max(anchor.wall, a.wall);
                anchor.cpu = std::max(anchor.cpu, a.cpu);
                for (size_t c = 0; c < counts.size(); ++c) {
                    const std::string sc = motion_scene_json(scatterers_json(counts[c]), 1.0);
                    const rate x = symbols_per_second(o, data, [&]() -> gr::basic_block_sptr {
                        return target_channel::make(sc, {}, 1, 1, true, "approaching", 0, 0.0, o.snr_db, 1, o.n_symbols,
                                                    o.n_subcarriers, fs.bandwidth_hz, fs.carrier_hz, fs.symbol_interval_s);
                    });
                    table[c].wall = std::max(table[c].wall, x.wall);
                    table[c].cpu = std::max(table[c].cpu, x.cpu);
                }
            }
            for (size_t c = 0; c < counts.size(); ++c)
                std::printf("%12d %14.2f %14.2f %11.3fx %16.2f %11.3fx\n", counts[c], 1e6 * o.n_symbols / table[c].wall,
                            1e6 * o.n_symbols / anchor.wall, table[c].wall / anchor.wall,
                            1e6 * o.n_symbols / table[c].cpu, table[c].cpu / anchor.cpu);
            std::printf("(us/frame mult.: %s, measured in the same rounds; CPU-us: CPU time of all threads)\n",
                        rows[0].name.c_str());
        }
    } catch (const std::exception& e) {
        std::cerr << "sems_bench_channel: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
