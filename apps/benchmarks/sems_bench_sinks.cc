// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_bench_sinks: frames per second of the sinks' inference, at several batch sizes.
 *
 * For each bundle and batch size it measures
 *   decoder  bundle_decoder::classify / estimate_delay called directly, batch by batch;
 *   sink     the block in a flowgraph (vector_source -> sink), whole-run wall time,
 *            so stream bookkeeping, tags and one result message per frame are included.
 * The frames are complex Gaussian pilot observations with a fixed seed: the decoders'
 * cost does not depend on the values.
 * Each rate is given twice: per wall-clock second, and per second of the process's CPU
 * time (std::clock), which stays meaningful when other jobs share the cores.
 *
 * With both bundles it then runs the two decoders at once, each in its own thread with
 * its own intra-op thread count (--together-threads), as two sinks in one flowgraph do.
 *
 * With a track bundle (--track) it measures what deciding over a track costs, in the same
 * run: its frame decoder alone (bundle_decoder::classify, batch by batch) against the track
 * classifier (the frame decoder's evidence, batch by batch, then one step per frame on one
 * track's state), and the sink in track mode in a flowgraph; the ratio is the anchor's.
 *
 * With an array (--array, and --classifier) it measures what reading an array costs the
 * classifier sink, in the same run: the sink on one antenna's N_p pilots (the anchor) against
 * the sink on the array's N_r·N_p, which beamforms each frame towards the peak of its
 * spectrum before the same decoder (array_beamformer), and that combination alone.
 *
 *   sems_bench_sinks --classifier models/classifier --delay models/delay_single
 *   sems_bench_sinks --track models/classifier_kinematic_track --batches 1,256
 *   sems_bench_sinks --classifier models/classifier_kinematic --array ula8_3g --batches 1,32
 */
#include <gnuradio/blocks/vector_source.h>
#include <gnuradio/sems/baselines/array_beamformer.h>
#include <gnuradio/sems/core/array/array_setting.h>
#include <gnuradio/sems/core/array/steering.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/sinks/classifier_sink.h>
#include <gnuradio/sems/learning/sinks/delay_estimator_sink.h>
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/top_block.h>
#include <boost/program_options.hpp>
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "count_list.h"

namespace po = boost::program_options;
using namespace gr::sems;

namespace {

using clock_type = std::chrono::steady_clock;

// Wall and CPU seconds since construction.
struct stopwatch {
    clock_type::time_point wall0 = clock_type::now();
    std::clock_t cpu0 = std::clock();
    double wall() const { return std::chrono::duration<double>(clock_type::now() - wall0).count(); }
    double cpu() const { return double(std::clock() - cpu0) / CLOCKS_PER_SEC; }
};

struct rate {
    double wall_fps, cpu_fps;
};

rate rate_of(size_t frames, const stopwatch& w)
{
    const double cpu = w.cpu(), wall = w.wall();
    return { frames / wall, cpu > 0 ? frames / cpu : 0.0 };
}

std::vector<gr_complex> gaussian_frames(size_t frames, int n_pilots, unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, std::sqrt(0.5f));
    std::vector<gr_complex> x(frames * n_pilots);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    return x;
}

// Frames to time for one batch size: at least `min_frames`, a whole number of batches.
size_t frames_for(int batch, size_t min_frames)
{
    const size_t b = static_cast<size_t>(batch);
    return std::max<size_t>(b, (min_frames + b - 1) / b * b);
}

rate decoder_fps(const bundle_decoder& dec, const std::vector<gr_complex>& obs, size_t frames, int batch)
{
    const int np = dec.n_pilots();
    auto run_batch = [&](size_t first) {
        if (dec.bundle().task == task_kind::classify)
            (void)dec.classify(obs.data() + first * np, batch);
        else
            (void)dec.estimate_delay(obs.data() + first * np, batch);
    };
    run_batch(0); // warm-up: first-call allocations
    const stopwatch w;
    for (size_t f = 0; f < frames; f += batch)
        run_batch(f);
    return rate_of(frames, w);
}

// The sink in a flowgraph; a classifier sink with n_elements > 1 reads that many elements of
// `array` (obs then holds n_elements·N_p values per frame).
rate sink_fps(const model_bundle& b,
              const std::vector<gr_complex>& obs,
              size_t frames,
              int batch,
              int threads,
              int n_elements = 1,
              const std::string& array = "")
{
    const int np = b.mask.size();
    const int item = n_elements * np; // one frame's observations, element-major
    gr::block_sptr sink;
    if (b.task == task_kind::classify) // metrics only at the end (0), the bundle's N and M, make()'s defaults
                                       // for the frame name, idle time and super-frames, then the array
        sink = classifier_sink::make(b.directory, np, batch, threads, 0, b.frame.n_symbols, b.frame.n_subcarriers,
                                     "", 0.0, 1, n_elements, array);
    else
        sink = delay_estimator_sink::make(
            b.directory, np, batch, threads, 0, b.frame.n_symbols, b.frame.n_subcarriers);
    const std::vector<gr_complex> data(obs.begin(), obs.begin() + frames * item);
    auto src = gr::blocks::vector_source<gr_complex>::make(data, false, item);
    auto tb = gr::make_top_block("sems_bench_sinks");
    tb->connect(src, 0, sink, 0);
    const stopwatch w;
    tb->run();
    return rate_of(frames, w);
}

// The track classifier on one track of `frames` frames: evidence batch by batch, then a step
// per frame.
rate track_fps(const track_classifier& tc, const std::vector<gr_complex>& obs, size_t frames, int batch)
{
    const int np = tc.n_pilots(), e = tc.evidence_size();
    std::vector<float> probs(static_cast<size_t>(tc.n_classes()));
    auto st = tc.begin();
    auto run_batch = [&](size_t first) {
        const auto ev = tc.evidence(obs.data() + first * np, batch);
        for (int i = 0; i < batch; ++i)
            tc.step(st, ev.data() + static_cast<size_t>(i) * e, probs.data());
    };
    run_batch(0); // warm-up
    const stopwatch w;
    for (size_t f = 0; f < frames; f += batch)
        run_batch(f);
    return rate_of(frames, w);
}

// The array's combination alone, frame by frame: K·N_p pilots in, N_p out.
rate combine_fps(const array_beamformer& c, const std::vector<gr_complex>& obs, size_t frames, int np)
{
    std::vector<gr_complex> z(static_cast<size_t>(np));
    const size_t per_frame = static_cast<size_t>(c.n_elements()) * np;
    (void)c.combine(obs.data(), np, z.data()); // warm-up
    const stopwatch w;
    for (size_t f = 0; f < frames; ++f)
        (void)c.combine(obs.data() + f * per_frame, np, z.data());
    return rate_of(frames, w);
}

// Wall-clock frames/s of one decoder in a thread of its own (CPU time is per process, so
// only wall time separates two decoders that run at once).
double decoder_wall_fps(const bundle_decoder& dec, const std::vector<gr_complex>& obs, size_t frames, int batch)
{
    return decoder_fps(dec, obs, frames, batch).wall_fps;
}

// Two decoders at once, each in its own thread with its own intra-op thread count, as two
// sinks in one flowgraph run: frames/s of each alone, then of each while the other runs.
void two_at_once(const model_bundle& a,
                 const model_bundle& b,
                 int threads_a,
                 int threads_b,
                 int batch,
                 size_t min_frames)
{
    const bundle_decoder da(a, threads_a), db(b, threads_b);
    const size_t frames = frames_for(batch, min_frames);
    const auto oa = gaussian_frames(frames, a.mask.size(), 2), ob = gaussian_frames(frames, b.mask.size(), 3);
    double alone_a = 0, alone_b = 0, with_a = 0, with_b = 0;
    std::thread([&] { alone_a = decoder_wall_fps(da, oa, frames, batch); }).join();
    std::thread([&] { alone_b = decoder_wall_fps(db, ob, frames, batch); }).join();
    std::thread ta([&] { with_a = decoder_wall_fps(da, oa, frames, batch); });
    std::thread tb([&] { with_b = decoder_wall_fps(db, ob, frames, batch); });
    ta.join();
    tb.join();
    std::printf("\ntwo decoders at once (own threads), batch %d, wall frames/s:\n", batch);
    std::printf("%-28s %8s %12s %12s\n", "bundle", "threads", "alone", "together");
    std::printf("%-28s %8d %12.0f %12.0f\n", a.directory.c_str(), threads_a, alone_a, with_a);
    std::printf("%-28s %8d %12.0f %12.0f\n", b.directory.c_str(), threads_b, alone_b, with_b);
}

} // namespace

int main(int argc, char** argv)
{
    std::string classifier_dir, delay_dir, track_dir, array_name, batches_text;
    size_t min_frames = 0;
    int threads = 1;
    std::string together_text;
    po::options_description opts("sems_bench_sinks: frames per second of the sinks at several batch sizes");
    opts.add_options()("help,h", "this help")(
        "classifier", po::value(&classifier_dir), "classifier bundle directory (e.g. models/classifier)")(
        "delay", po::value(&delay_dir), "delay bundle directory (e.g. models/delay_single)")(
        "track", po::value(&track_dir), "track bundle directory: the cost of deciding over a track against its frame decoder")(
        "array", po::value(&array_name),
        "with --classifier: an array (a preset's name, e.g. ula8_3g, or an array file): the sink reading its "
        "elements against the sink on one antenna")(
        "batches", po::value(&batches_text)->default_value("1,32,256"), "comma-separated batch sizes")(
        "frames", po::value(&min_frames)->default_value(1024), "frames timed per measurement (at least)")(
        "threads", po::value(&threads)->default_value(1), "LibTorch intra-op threads")(
        "together-threads", po::value(&together_text)->default_value("1,1"),
        "with both bundles: intra-op threads of the classifier and the delay decoder when run at once");
    try {
        po::variables_map vm;
        po::store(po::parse_command_line(argc, argv, opts), vm);
        if (vm.count("help")) {
            std::cout << opts << std::endl;
            return 0;
        }
        po::notify(vm);
        if (classifier_dir.empty() && delay_dir.empty() && track_dir.empty())
            throw std::invalid_argument("give --classifier, --delay and/or --track bundle directories");
        if (!array_name.empty() && classifier_dir.empty())
            throw std::invalid_argument("--array " + array_name + " needs --classifier (the sink that reads an array)");
        if (min_frames < 1)
            throw std::invalid_argument("--frames must be >= 1");
        if (threads < 1)
            throw std::invalid_argument("--threads must be >= 1");
        const std::vector<int> batches = apps::parse_counts(batches_text, "--batches");

        std::printf("%-28s %6s %7s %12s %12s %12s %12s\n", "bundle", "batch", "frames", "decoder fps",
                    "sink fps", "decoder/cpu", "sink/cpu");
        for (const std::string& dir : { classifier_dir, delay_dir }) {
            if (dir.empty())
                continue;
            const model_bundle b = model_bundle::load(dir);
            const bundle_decoder dec(b, threads);
            const int np = b.mask.size();
            const size_t max_frames = frames_for(*std::max_element(batches.begin(), batches.end()), min_frames);
            const std::vector<gr_complex> obs = gaussian_frames(max_frames, np, 1);
            for (int batch : batches) {
                const size_t frames = frames_for(batch, min_frames);
                const rate d = decoder_fps(dec, obs, frames, batch);
                const rate s = sink_fps(b, obs, frames, batch, threads);
                std::printf("%-28s %6d %7zu %12.0f %12.0f %12.0f %12.0f\n", dir.c_str(), batch, frames, d.wall_fps,
                            s.wall_fps, d.cpu_fps, s.cpu_fps);
                std::fflush(stdout);
            }
        }
        if (!track_dir.empty()) {
            const model_bundle b = model_bundle::load(track_dir);
            const bundle_decoder dec(b, threads); // its frame decoder, per frame
            const track_classifier tc(b, threads);
            const int np = b.mask.size();
            const size_t max_frames = frames_for(*std::max_element(batches.begin(), batches.end()), min_frames);
            const std::vector<gr_complex> obs = gaussian_frames(max_frames, np, 4);
            std::printf("\ndeciding over a track, %s (frames/s; cost = the track classifier's CPU time per frame over the frame decoder's):\n",
                        track_dir.c_str());
            std::printf("%6s %7s %12s %12s %12s %12s %12s %8s\n", "batch", "frames", "decoder fps", "track fps",
                        "sink fps", "decoder/cpu", "track/cpu", "cost");
            for (int batch : batches) {
                const size_t frames = frames_for(batch, min_frames);
                const rate d = decoder_fps(dec, obs, frames, batch);
                const rate t = track_fps(tc, obs, frames, batch);
                const rate s = sink_fps(b, obs, frames, batch, threads);
                std::printf("%6d %7zu %12.0f %12.0f %12.0f %12.0f %12.0f %8.2f\n", batch, frames, d.wall_fps,
                            t.wall_fps, s.wall_fps, d.cpu_fps, t.cpu_fps, t.cpu_fps > 0 ? d.cpu_fps / t.cpu_fps : 0.0);
                std::fflush(stdout);
            }
        }
        if (!array_name.empty()) {
            const model_bundle b = model_bundle::load(classifier_dir);
            const array_geometry a = array_from_setting(array_name, "--array");
            const int k = a.n_receive(), np = b.mask.size();
            const array_beamformer combiner(a, pilot_wavelength_m(b.frame, b.mask));
            const size_t max_frames = frames_for(*std::max_element(batches.begin(), batches.end()), min_frames);
            const std::vector<gr_complex> one = gaussian_frames(max_frames, np, 5);
            const std::vector<gr_complex> many = gaussian_frames(max_frames, k * np, 6);
            std::printf("\nreading an array, %s with %s (%d elements; frames/s; cost = the array sink's CPU time per "
                        "frame over the one-antenna sink's):\n",
                        classifier_dir.c_str(), array_name.c_str(), k);
            std::printf("%6s %7s %12s %12s %12s %12s %12s %8s\n", "batch", "frames", "sink fps", "array fps",
                        "combine fps", "sink/cpu", "array/cpu", "cost");
            for (int batch : batches) {
                const size_t frames = frames_for(batch, min_frames);
                const rate s1 = sink_fps(b, one, frames, batch, threads);
                const rate sk = sink_fps(b, many, frames, batch, threads, k, array_name);
                const rate c = combine_fps(combiner, many, frames, np);
                std::printf("%6d %7zu %12.0f %12.0f %12.0f %12.0f %12.0f %8.2f\n", batch, frames, s1.wall_fps,
                            sk.wall_fps, c.wall_fps, s1.cpu_fps, sk.cpu_fps,
                            sk.cpu_fps > 0 ? s1.cpu_fps / sk.cpu_fps : 0.0);
                std::fflush(stdout);
            }
        }
        if (!classifier_dir.empty() && !delay_dir.empty()) {
            const std::vector<int> tt = apps::parse_counts(together_text, "--together-threads");
            if (tt.size() != 2)
                throw std::invalid_argument("--together-threads: give two counts, e.g. 1,1");
            two_at_once(model_bundle::load(classifier_dir), model_bundle::load(delay_dir), tt[0], tt[1],
                        batches.back(), min_frames);
        }
    } catch (const std::exception& e) {
        std::cerr << "sems_bench_sinks: " << e.what() << std::endl;
        return 1;
    }
    return 0;
}
