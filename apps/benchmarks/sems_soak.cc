// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems soak test: streams many frames through
 *   ones -> pilot_mapper (the delay mask) -> gate -> target_channel -> pilot_extractor x2
 *     -> classifier_sink, delay_estimator_sink
 * prints the heap in use and the resident memory every --report frames and the frame
 * accounting at the end, and fails (exit 1) unless
 *   - the heap in use after warm-up (the first report) grows by at most --max-growth-kib
 *     (a leak grows it; glibc's mallinfo2 over all arenas, ASan's allocator under ASan),
 *   - resident memory, read after malloc_trim, grows by at most --max-rss-growth-kib,
 *   - frames in = frames out + counted drops/skips at every stage:
 *       requested frames = the gate's = extractor frames_out + dropped_partial + skipped_nonfinite
 *       (the mapper, fed endlessly, may run ahead of the gate: its count is printed only),
 *       sink frames   = extractor frames_out = scored + skipped (every frame has a truth).
 * The mapper places the delay bundle's pilots with their values (its mask's Newman phases)
 * and 1 on every other resource element, which are the classifier's unit pilots: each
 * extractor takes its own bundle's mask out of the same stream, and each sink sees the
 * pilots it was trained on (on the one element the two masks may share, the classifier
 * sees a delay pilot's phase). Both sinks' scores are therefore the bundles' own accuracy.
 *
 * Resident memory is read at a quiet point of the one continuous stream: at each report
 * the gate (a head whose budget the main thread raises) holds the next frames back until
 * every frame let through has left both extractors and the sinks' counters have stopped
 * moving. The gate stops at a whole number of batches (a report at 10^6 frames reads at
 * 999 936 with batch 256), so the sinks hold no partial batch either. Read at any other
 * moment, the figure would include the batches in flight (the decoders' working tensors,
 * ~10 MiB) or pending frames, not what stays.
 *
 *   sems_soak --frames 10000000 --report 1000000      (the long soak, docs/reference/hardening.md)
 *   sems_soak --frames 60000 --report 6000            (the CTest test sems_soak_short, apps/CMakeLists.txt)
 */
#include <gnuradio/sems/blocks/pilot_extractor.h>
#include <gnuradio/sems/blocks/pilot_mapper.h>
#include <gnuradio/sems/blocks/target_channel.h>
#include <gnuradio/sems/learning/sinks/classifier_sink.h>
#include <gnuradio/sems/learning/sinks/delay_estimator_sink.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/blocks/vector_source.h>
#include <gnuradio/io_signature.h>
#include <gnuradio/sync_block.h>
#include <gnuradio/top_block.h>
#include <boost/program_options.hpp>
#include <malloc.h>
#if defined(__SANITIZE_ADDRESS__)
#define SEMS_SOAK_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SEMS_SOAK_ASAN 1
#endif
#endif
#ifndef SEMS_SOAK_ASAN
#define SEMS_SOAK_ASAN 0
#endif
#if SEMS_SOAK_ASAN
// The sanitizer runtime's count of bytes allocated and not freed (GCC's libasan and clang's
// both export it; GCC does not install compiler-rt's sanitizer/allocator_interface.h).
extern "C" size_t __sanitizer_get_current_allocated_bytes(void);
#endif
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
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

// Bytes the program holds from the allocator, in KiB: what a leak grows. Resident memory
// also holds what the allocator keeps for reuse after a free (glibc's per-thread arenas
// grow and shrink with the order in which the block threads free their batches), which
// moved a quiet-point reading by up to 5.6 MiB between runs without anything held.
long heap_in_use_kib()
{
#if SEMS_SOAK_ASAN
    return static_cast<long>(__sanitizer_get_current_allocated_bytes() / 1024);
#else
    const struct mallinfo2 mi = ::mallinfo2(); // all arenas: heap chunks in use + mmapped chunks
    return static_cast<long>((mi.uordblks + mi.hblkhd) / 1024);
#endif
}

// A head with a budget: passes items while fewer than budget() went through, then waits
// (work() returns 0 after a short sleep); ends the stream after `total` items once end()
// was called (so that the last report is read before the blocks wind down).
class gate : public gr::sync_block
{
public:
    gate(size_t itemsize, uint64_t total)
        : gr::sync_block("soak_gate",
                         gr::io_signature::make(1, 1, itemsize),
                         gr::io_signature::make(1, 1, itemsize)),
          d_itemsize(itemsize),
          d_total(total)
    {
    }
    void set_budget(uint64_t items) { d_budget = std::min(items, d_total); }
    uint64_t passed() const { return d_passed; }
    void end() { d_end = true; }

    int work(int noutput_items, gr_vector_const_void_star& in, gr_vector_void_star& out) override
    {
        if (d_passed >= d_total && d_end)
            return WORK_DONE;
        const uint64_t n = std::min<uint64_t>(noutput_items, d_budget - d_passed);
        if (n == 0) {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            return 0;
        }
        std::memcpy(out[0], in[0], n * d_itemsize);
        d_passed += n;
        return static_cast<int>(n);
    }

private:
    const size_t d_itemsize;
    const uint64_t d_total;
    std::atomic<uint64_t> d_budget{ 0 }, d_passed{ 0 };
    std::atomic<bool> d_end{ false };
};
} // namespace

int main(int argc, char** argv)
{
    uint64_t n_frames = 100000, report = 10000;
    std::string models = "models", classifier_dir, delay_dir;
    double snr_db = 10.0;
    long max_growth_kib = 1024, max_rss_growth_kib = 65536;
    int batch = 256;
    po::options_description opts("sems_soak options");
    opts.add_options()("help", "this text")(
        "frames", po::value(&n_frames)->default_value(n_frames), "frames to stream")(
        "report", po::value(&report)->default_value(report), "print heap in use and resident memory every this many frames")(
        "models", po::value(&models)->default_value(models), "folder holding classifier/ and delay_single/")(
        "classifier", po::value(&classifier_dir), "classifier bundle (default: <models>/classifier)")(
        "delay", po::value(&delay_dir), "delay bundle (default: <models>/delay_single)")(
        "snr", po::value(&snr_db)->default_value(snr_db), "SNR per resource element (dB)")(
        "batch", po::value(&batch)->default_value(batch), "sink batch size")(
        "max-growth-kib", po::value(&max_growth_kib)->default_value(max_growth_kib),
        "allowed growth of the heap in use after warm-up (KiB): the leak criterion")(
        "max-rss-growth-kib", po::value(&max_rss_growth_kib)->default_value(max_rss_growth_kib),
        "allowed growth of resident memory after warm-up (KiB), read after malloc_trim: a guard "
        "for memory that does not come from malloc");
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

    // The sinks' decoders set glibc's thresholds for tensor work (lib/learning/memory/malloc_tuning.h):
    // the heap keeps the peak working set, so resident memory is flat from the first report.
    const auto cls = model_bundle::load(classifier_dir.empty() ? models + "/classifier" : classifier_dir);
    const auto dly = model_bundle::load(delay_dir.empty() ? models + "/delay_single" : delay_dir);
    if (dly.frame.n_symbols != cls.frame.n_symbols || dly.frame.n_subcarriers != cls.frame.n_subcarriers) {
        std::cerr << "sems_soak: the bundles' frames differ: " << cls.directory << " is " << cls.frame.n_symbols
                  << " x " << cls.frame.n_subcarriers << ", " << dly.directory << " is " << dly.frame.n_symbols << " x "
                  << dly.frame.n_subcarriers << "\n";
        return 2;
    }
    const frame_settings fs = cls.frame;
    // Data symbols 1 around the delay bundle's pilots (see the file comment).
    auto ones = gr::blocks::vector_source_c::make(std::vector<gr_complex>{ gr_complex(1.0f, 0.0f) }, true);
    auto mapper = pilot_mapper::make(dly.directory + "/" + dly.mask_name, {}, fs.n_symbols, fs.n_subcarriers);
    auto gate_ = gnuradio::make_block_sptr<gate>(sizeof(gr_complex) * fs.n_subcarriers, n_frames * fs.n_symbols);
    auto channel = target_channel::make("", {}, 1, 1, true, "approaching", 0, 0.0, snr_db, 1234, fs.n_symbols, fs.n_subcarriers,
                                        fs.bandwidth_hz, fs.carrier_hz, fs.symbol_interval_s);
    auto ex_c = pilot_extractor::make(cls.directory + "/" + cls.mask_name, {}, fs.n_symbols, fs.n_subcarriers);
    auto ex_d = pilot_extractor::make(dly.directory + "/" + dly.mask_name, {}, fs.n_symbols, fs.n_subcarriers);
    auto sink_c = classifier_sink::make(cls.directory, cls.mask.size(), batch, 1, 0, fs.n_symbols, fs.n_subcarriers);
    auto sink_d =
        delay_estimator_sink::make(dly.directory, dly.mask.size(), batch, 1, 0, fs.n_symbols, fs.n_subcarriers);

    auto tb = gr::make_top_block("sems_soak");
    tb->connect(ones, 0, mapper, 0);
    tb->connect(mapper, 0, gate_, 0);
    tb->connect(gate_, 0, channel, 0);
    tb->connect(channel, 0, ex_c, 0);
    tb->connect(channel, 0, ex_d, 0);
    tb->connect(ex_c, 0, sink_c, 0);
    tb->connect(ex_d, 0, sink_d, 0);

    std::printf("# sems_soak: %llu frames of %d x %d, SNR %.1f dB, batch %d, bundles %s and %s\n",
                static_cast<unsigned long long>(n_frames), fs.n_symbols, fs.n_subcarriers, snr_db, batch,
                cls.directory.c_str(), dly.directory.c_str());
    std::printf("%12s %10s %10s %10s\n", "frames", "rss_kib", "heap_kib", "seconds");
    const auto t0 = std::chrono::steady_clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    std::vector<long> rss, heap;
    // Frames of a path that have left its extractor (out, dropped or skipped).
    auto through = [](const pilot_extractor::sptr& ex) {
        return ex->frames_out() + ex->frames_dropped_partial() + ex->frames_skipped_nonfinite();
    };
    tb->start();
    bool stalled = false;
    for (uint64_t next = std::min(report, n_frames); next <= n_frames; next += report) {
        // Read where both sinks hold no partial batch: the pending frames (each with its truth
        // tag, ~1-2 KiB) would otherwise add (at mod batch) frames' worth to the reading, a
        // swing of up to ~1 MiB from one report to the next that is not memory kept.
        const uint64_t at = next >= uint64_t(batch) ? next / uint64_t(batch) * uint64_t(batch) : next;
        gate_->set_budget(at * fs.n_symbols);
        // Quiet: every frame let through has left both extractors, the sinks' counters have
        // not moved for 200 ms and each sink holds less than a batch (so it is not decoding
        // one; frames skipped behind a partial batch can hold more: then 3 s without a move).
        // A stream that makes no progress for 10 minutes fails.
        uint64_t last_c = ~0ull, last_d = ~0ull;
        int still = 0;
        auto progress = std::chrono::steady_clock::now();
        auto idle = [&] {
            return (ex_c->frames_out() - sink_c->frames() < uint64_t(batch) &&
                    ex_d->frames_out() - sink_d->frames() < uint64_t(batch)) ||
                   still >= 150;
        };
        while (still < 10 || !idle()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            const uint64_t fc = sink_c->frames(), fd = sink_d->frames();
            const bool drained = through(ex_c) >= at && through(ex_d) >= at;
            still = drained && fc == last_c && fd == last_d ? still + 1 : 0;
            if (fc != last_c || fd != last_d)
                progress = std::chrono::steady_clock::now();
            last_c = fc;
            last_d = fd;
            if (std::chrono::steady_clock::now() - progress > std::chrono::minutes(10)) {
                stalled = true;
                break;
            }
        }
        if (stalled) {
            std::printf("# the stream stalled before frame %llu\n", static_cast<unsigned long long>(at));
            tb->stop();
            break;
        }
        heap.push_back(heap_in_use_kib());
        ::malloc_trim(0); // give back what the arenas keep for reuse: resident memory is then what is held
        rss.push_back(rss_kib());
        std::printf("%12llu %10ld %10ld %10.1f\n", static_cast<unsigned long long>(at), rss.back(), heap.back(),
                    seconds());
        std::fflush(stdout);
        if (next == n_frames)
            break;
        if (n_frames - next < report) // the last report at the end of the stream
            next = n_frames - report;
    }
    gate_->set_budget(n_frames * fs.n_symbols);
    gate_->end();
    tb->wait();

    struct row {
        const char* what;
        uint64_t a, b;
    };
    const uint64_t in = mapper->frames();
    const std::vector<row> checks = {
        { "gate frames = requested", n_frames, gate_->passed() / fs.n_symbols },
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
    bool ok = !stalled;
    std::printf("# accounting after %.1f s (mapper made %llu frames; the gate passed %llu)\n", seconds(),
                static_cast<unsigned long long>(in), static_cast<unsigned long long>(gate_->passed() / fs.n_symbols));
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
        auto growth_of = [&](const char* what, const std::vector<long>& v, long limit) {
            const auto [lo, hi] = std::minmax_element(v.begin() + 1, v.end());
            const long growth = *hi - v.front();
            std::printf("# %s: %ld KiB after warm-up (first report), then %ld..%ld KiB: growth %ld KiB (limit %ld) %s\n",
                        what, v.front(), *lo, *hi, growth, limit, growth <= limit ? "ok" : "EXCEEDED");
            return growth <= limit;
        };
        const bool heap_ok = growth_of("heap in use", heap, max_growth_kib);
        const bool rss_ok = growth_of("resident memory", rss, max_rss_growth_kib);
        ok = ok && heap_ok && rss_ok;
    } else {
        std::printf("# memory: fewer than two reports, growth not measured\n");
    }
    std::printf("# %s\n", ok ? "PASS" : "FAIL");
    return ok ? 0 : 1;
}
