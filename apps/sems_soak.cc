// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems soak test: streams many frames through
 *   pilot_mapper (pilot-only frames) -> head -> target_channel -> pilot_extractor x2
 *     -> classifier_sink, delay_estimator_sink
 * prints the resident memory every --report frames and the frame accounting at the
 * end, and fails (exit 1) unless
 *   - resident memory after warm-up (the first report) stays within --max-growth-kib,
 *   - frames in = frames out + counted drops/skips at every stage:
 *       mapper frames = extractor frames_out + dropped_partial + skipped_nonfinite,
 *       sink frames   = extractor frames_out = scored + skipped (every frame has a truth).
 * The mapper sends pilot-only frames (N_p = N*M), so each extractor can take its own
 * bundle's mask out of the same stream.
 *
 *   sems_soak --frames 10000000 --report 1000000      (the soak)
 *   sems_soak --frames 100000 --report 10000          (the CI version, a CTest test)
 */
#include <gnuradio/blocks/head.h>
#include <gnuradio/sems/blocks/pilot_extractor.h>
#include <gnuradio/sems/blocks/pilot_mapper.h>
#include <gnuradio/sems/blocks/target_channel.h>
#include <gnuradio/sems/learning/classifier_sink.h>
#include <gnuradio/sems/learning/delay_estimator_sink.h>
#include <gnuradio/sems/learning/model_bundle.h>
#include <gnuradio/top_block.h>
#include <boost/program_options.hpp>
#include <malloc.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numeric>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace po = boost::program_options;
using namespace gr::sems;

namespace {
// Resident set size in KiB (Linux /proc/self/statm).
long rss_kib()
{
    std::ifstream f("/proc/self/statm");
    long pages_total = 0, pages_resident = 0;
    f >> pages_total >> pages_resident;
    return pages_resident * (::sysconf(_SC_PAGESIZE) / 1024);
}
} // namespace

int main(int argc, char** argv)
{
    uint64_t n_frames = 100000, report = 10000;
    std::string models = "models";
    double snr_db = 10.0;
    long max_growth_kib = 1024;
    int batch = 256;
    bool glibc_dynamic_mmap = false;
    po::options_description opts("sems_soak options");
    opts.add_options()("help", "this text")(
        "frames", po::value(&n_frames)->default_value(n_frames), "frames to stream")(
        "report", po::value(&report)->default_value(report), "print resident memory every this many frames")(
        "models", po::value(&models)->default_value(models), "folder holding classifier/ and delay_single/")(
        "snr", po::value(&snr_db)->default_value(snr_db), "SNR per resource element (dB)")(
        "batch", po::value(&batch)->default_value(batch), "sink batch size")(
        "glibc-dynamic-mmap", po::bool_switch(&glibc_dynamic_mmap),
        "keep glibc's dynamic mmap threshold (by default it is fixed at 128 KiB so that freed batch "
        "tensors go back to the system and resident memory measures leaks, not heap reuse)")(
        "max-growth-kib", po::value(&max_growth_kib)->default_value(max_growth_kib),
        "allowed resident-memory growth after warm-up (KiB)");
    po::variables_map vm;
    try {
        po::store(po::parse_command_line(argc, argv, opts), vm);
        po::notify(vm);
    } catch (const std::exception& e) {
        std::cerr << "sems_soak: " << e.what() << "\n" << opts;
        return 2;
    }
    if (vm.count("help")) {
        std::cout << opts;
        return 0;
    }
    if (n_frames < 1 || report < 1) {
        std::cerr << "sems_soak: --frames and --report must be >= 1\n";
        return 2;
    }

    // glibc raises its mmap threshold after a large block is freed, so later batch tensors
    // come from the heap and resident memory jitters by tens of MiB without any leak.
    if (!glibc_dynamic_mmap)
        ::mallopt(M_MMAP_THRESHOLD, 128 * 1024);
    const auto cls = model_bundle::load(models + "/classifier");
    const auto dly = model_bundle::load(models + "/delay_single");
    const frame_settings fs = cls.frame;
    std::vector<int> all(static_cast<size_t>(fs.grid_size()));
    std::iota(all.begin(), all.end(), 0);

    auto mapper = pilot_mapper::make("", all, fs.n_symbols, fs.n_subcarriers);
    auto head = gr::blocks::head::make(sizeof(gr_complex) * fs.n_subcarriers, n_frames * fs.n_symbols);
    auto channel = target_channel::make("", {}, 1, 1, true, "approaching", 0, 0.0, snr_db, 1234, fs.n_symbols, fs.n_subcarriers,
                                        fs.bandwidth_hz, fs.carrier_hz, fs.symbol_interval_s);
    auto ex_c = pilot_extractor::make(models + "/classifier/mask.json", {}, fs.n_symbols, fs.n_subcarriers);
    auto ex_d = pilot_extractor::make(models + "/delay_single/mask.json", {}, fs.n_symbols, fs.n_subcarriers);
    auto sink_c = classifier_sink::make(cls.directory, cls.mask.size(), batch, 1, 0, fs.n_symbols, fs.n_subcarriers);
    auto sink_d =
        delay_estimator_sink::make(dly.directory, dly.mask.size(), batch, 1, 0, fs.n_symbols, fs.n_subcarriers);

    auto tb = gr::make_top_block("sems_soak");
    tb->connect(mapper, 0, head, 0);
    tb->connect(head, 0, channel, 0);
    tb->connect(channel, 0, ex_c, 0);
    tb->connect(channel, 0, ex_d, 0);
    tb->connect(ex_c, 0, sink_c, 0);
    tb->connect(ex_d, 0, sink_d, 0);

    std::printf("# sems_soak: %llu frames of %d x %d, SNR %.1f dB, batch %d\n",
                static_cast<unsigned long long>(n_frames), fs.n_symbols, fs.n_subcarriers, snr_db, batch);
    std::printf("%12s %10s %10s\n", "frames", "rss_kib", "seconds");
    const auto t0 = std::chrono::steady_clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    std::vector<long> rss;
    tb->start();
    std::atomic<bool> done{ false };
    std::thread waiter([&] {
        tb->wait();
        done = true;
    });
    uint64_t next = report;
    while (true) {
        const uint64_t now = std::min(sink_c->frames(), sink_d->frames());
        if (now >= next || (done && next <= n_frames)) {
            if (now >= next) {
                rss.push_back(rss_kib());
                std::printf("%12llu %10ld %10.1f\n", static_cast<unsigned long long>(next), rss.back(), seconds());
                std::fflush(stdout);
                next += report;
                continue;
            }
        }
        if (done)
            break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    waiter.join();

    struct row {
        const char* what;
        uint64_t a, b;
    };
    const uint64_t in = mapper->frames();
    const std::vector<row> checks = {
        { "head frames = requested", n_frames, in >= n_frames ? n_frames : in },
        { "classifier path: frames in = out + dropped + skipped", n_frames,
          ex_c->frames_out() + ex_c->frames_dropped_partial() + ex_c->frames_skipped_nonfinite() },
        { "delay path: frames in = out + dropped + skipped", n_frames,
          ex_d->frames_out() + ex_d->frames_dropped_partial() + ex_d->frames_skipped_nonfinite() },
        { "classifier_sink frames = extractor frames_out", ex_c->frames_out(), sink_c->frames() },
        { "delay_estimator_sink frames = extractor frames_out", ex_d->frames_out(), sink_d->frames() },
        { "classifier_sink frames = scored + skipped", sink_c->frames(),
          sink_c->frames_scored() + sink_c->frames_skipped() },
        { "delay_estimator_sink frames = scored + skipped", sink_d->frames(),
          sink_d->frames_scored() + sink_d->frames_skipped() },
    };
    bool ok = true;
    std::printf("# accounting after %.1f s (mapper made %llu frames; head passed %llu)\n", seconds(),
                static_cast<unsigned long long>(in), static_cast<unsigned long long>(n_frames));
    for (const auto& c : checks) {
        std::printf("#   %-55s %llu = %llu  %s\n", c.what, static_cast<unsigned long long>(c.a),
                    static_cast<unsigned long long>(c.b), c.a == c.b ? "ok" : "MISMATCH");
        ok = ok && c.a == c.b;
    }
    std::printf("#   classifier: scored %llu skipped %llu (faulted %llu) accuracy %.4f\n",
                static_cast<unsigned long long>(sink_c->frames_scored()),
                static_cast<unsigned long long>(sink_c->frames_skipped()),
                static_cast<unsigned long long>(sink_c->frames_faulted()), sink_c->accuracy());
    std::printf("#   delay: scored %llu skipped %llu (faulted %llu) mae_index %.4f\n",
                static_cast<unsigned long long>(sink_d->frames_scored()),
                static_cast<unsigned long long>(sink_d->frames_skipped()),
                static_cast<unsigned long long>(sink_d->frames_faulted()), sink_d->mae_index());
    if (rss.size() >= 2) {
        const auto [lo, hi] = std::minmax_element(rss.begin() + 1, rss.end());
        const long growth = *hi - rss.front();
        std::printf("# resident memory: %ld KiB after warm-up (first report), then %ld..%ld KiB: growth %ld KiB "
                    "(limit %ld)\n",
                    rss.front(), *lo, *hi, growth, max_growth_kib);
        ok = ok && growth <= max_growth_kib;
    } else {
        std::printf("# resident memory: fewer than two reports, growth not measured\n");
    }
    std::printf("# %s\n", ok ? "PASS" : "FAIL");
    return ok ? 0 : 1;
}
