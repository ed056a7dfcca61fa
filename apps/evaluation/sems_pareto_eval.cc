// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_pareto_eval: one point of the speed/accuracy front per method.
 *
 * For each method it measures, on the same fresh test frames (a scene's frames drawn with a
 * seed no training run uses, noise from channel_model::add_noise, as qa_learning_shipped does):
 *   classify  accuracy at each --snr;
 *   delay     MAE, median |error| and the fraction of frames off by > 0.5 delay index;
 * and its speed on one thread: frames/s at each --batches size, per wall second and per
 * second of process CPU time (std::clock, steadier when other jobs share the cores), best of
 * --repeat runs, and the latency of one batch (batch / frames-per-second).
 *
 * Methods:
 *   --bundle DIR         a model bundle through bundle_decoder (one intra-op thread);
 *   --bundle DIR --no-refine   the same delay bundle with refine_paths = 0 (network only);
 *   --baselines          classify: the feature SVM (Doppler-spectrum moments, libsvm RBF) on
 *                        --mask, trained on --svm-frames frames of the scene over
 *                        --train-snr; delay: periodogram, OMP, OMP + LS refinement and the
 *                        LS estimator (one path) on --mask, searching the delay decoder's
 *                        default dictionary range. They are per-frame methods: the same
 *                        frames/s at every batch size.
 * One CSV row per method and SNR is appended to --csv (header written when the file is new).
 *
 *   sems_pareto_eval --task classify --scene-from models/classifier --mask models/classifier/mask.json \
 *       --bundle models/classifier --baselines --csv docs/pareto/classify.csv
 */
#include <gnuradio/sems/baselines/doppler_features.h>
#include <gnuradio/sems/baselines/feature_svm.h>
#include <gnuradio/sems/baselines/ls_delay_estimator.h>
#include <gnuradio/sems/baselines/omp_delay_estimator.h>
#include <gnuradio/sems/baselines/periodogram_delay_estimator.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <boost/program_options.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace po = boost::program_options;
using namespace gr::sems;

namespace {

constexpr uint64_t fresh_seed = 0x5e5f00d; // qa_learning_shipped's test seed: no training run uses it

using clock_type = std::chrono::steady_clock;

struct speed {
    int batch;
    double wall_fps, cpu_fps;
};

// A method: per-batch inference (frames in, class ids or delay indices out).
struct method {
    std::string name, kind, settings;
    std::function<std::vector<double>(const gr_complex*, int)> run; // frames -> outputs
    bool batched = true;
};

std::vector<double> parse_list(const std::string& s, const std::string& option)
{
    std::vector<double> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
        out.push_back(std::stod(item));
    if (out.empty())
        throw std::invalid_argument(option + ": no value given");
    return out;
}

// Pilot observations (frames x N_p, mask order) at snr_db (NaN: uniform in [lo, hi] per frame).
std::vector<gr_complex> observe(const frame_settings& fs,
                                const scene& sc,
                                const pilot_mask& mask,
                                uint64_t seed,
                                int frames,
                                double snr_lo,
                                double snr_hi,
                                std::vector<frame_truth>& truths)
{
    channel_model model(fs, sc, seed);
    const int g = fs.grid_size();
    std::vector<gr_complex> h(static_cast<size_t>(frames) * g);
    truths = model.generate(frames, h.data());
    // Pilots that differ in energy: pilot k's noise is scaled by mask.noise_scale(k).
    const std::vector<gr_complex> clean = mask.equal_power() ? std::vector<gr_complex>{} : h;
    if (snr_lo == snr_hi) {
        model.add_noise(h.data(), h.size(), snr_lo);
    } else {
        std::mt19937_64 rng(seed ^ 0x5a5a);
        std::uniform_real_distribution<double> u(snr_lo, snr_hi);
        for (int f = 0; f < frames; ++f)
            model.add_noise(h.data() + static_cast<size_t>(f) * g, g, u(rng));
    }
    const auto idx = mask.flat_indices();
    std::vector<gr_complex> obs;
    obs.reserve(static_cast<size_t>(frames) * idx.size());
    for (int f = 0; f < frames; ++f)
        for (size_t k = 0; k < idx.size(); ++k) {
            const size_t at = static_cast<size_t>(f) * g + idx[k];
            obs.push_back(clean.empty()
                              ? h[at]
                              : clean[at] + (h[at] - clean[at]) * static_cast<float>(mask.noise_scale(int(k))));
        }
    return obs;
}

std::vector<gr_complex> gaussian_frames(size_t frames, int np)
{
    std::mt19937 rng(1);
    std::normal_distribution<float> g(0.0f, std::sqrt(0.5f));
    std::vector<gr_complex> x(frames * np);
    for (auto& v : x)
        v = gr_complex(g(rng), g(rng));
    return x;
}

// Frames/s of `m` at `batch`: at least min_frames, best of `repeat` runs, after one warm-up batch.
speed time_method(const method& m, int np, int batch, size_t min_frames, int repeat)
{
    const size_t b = static_cast<size_t>(batch);
    const size_t frames = std::max(b, (min_frames + b - 1) / b * b);
    const auto obs = gaussian_frames(frames, np);
    (void)m.run(obs.data(), batch);
    speed best{ batch, 0.0, 0.0 };
    for (int r = 0; r < repeat; ++r) {
        const auto w0 = clock_type::now();
        const std::clock_t c0 = std::clock();
        for (size_t f = 0; f < frames; f += b)
            (void)m.run(obs.data() + f * np, batch);
        const double wall = std::chrono::duration<double>(clock_type::now() - w0).count();
        const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
        best.wall_fps = std::max(best.wall_fps, frames / wall);
        best.cpu_fps = std::max(best.cpu_fps, cpu > 0 ? frames / cpu : 0.0);
    }
    return best;
}

} // namespace

int main(int argc, char** argv)
{
    std::string task_text, scene_from, mask_path, csv_path, snr_text, batches_text, train_snr_text, label;
    std::vector<std::string> bundles;
    int frames = 3000, repeat = 3, svm_frames = 8000;
    size_t speed_frames = 1024;
    uint64_t train_seed = 1;
    bool baselines = false, no_refine = false;
    po::options_description opts("sems_pareto_eval: accuracy/MAE and frames/s of decoders and baselines");
    opts.add_options()("help,h", "this help")("task", po::value(&task_text), "classify | delay")(
        "scene-from", po::value(&scene_from), "bundle whose training scene and frame settings the test frames use")(
        "mask", po::value(&mask_path), "pilot mask of the baselines (the networks use their bundle's)")(
        "bundle", po::value(&bundles)->composing(), "bundle directory (repeatable)")(
        "no-refine", po::bool_switch(&no_refine), "delay bundles: also score them with refine_paths = 0")(
        "label", po::value(&label), "name of the (single) --bundle in the CSV (default: its directory)")(
        "baselines", po::bool_switch(&baselines), "also the classical methods on --mask (needed): classify, the feature "
                                                  "SVM; delay, periodogram, OMP, OMP + LS refinement and LS (one path)")(
        "snr", po::value(&snr_text)->default_value("0,10,30"), "test SNRs (dB)")(
        "frames", po::value(&frames)->default_value(3000), "test frames per SNR")(
        "batches", po::value(&batches_text)->default_value("1,32,256"), "batch sizes timed")(
        "speed-frames", po::value(&speed_frames)->default_value(1024), "frames per timing run (at least)")(
        "repeat", po::value(&repeat)->default_value(3), "timing runs per batch (best kept)")(
        "svm-frames", po::value(&svm_frames)->default_value(8000), "feature SVM: training frames")(
        "train-snr", po::value(&train_snr_text)->default_value("0,20"), "feature SVM: training SNR range lo,hi (dB)")(
        "train-seed", po::value(&train_seed)->default_value(1), "feature SVM: training frames' seed")(
        "csv", po::value(&csv_path), "CSV file to append the rows to");
    try {
        po::variables_map vm;
        po::store(po::parse_command_line(argc, argv, opts), vm);
        if (vm.count("help")) {
            std::cout << opts << std::endl;
            return 0;
        }
        po::notify(vm);
        if (task_text != "classify" && task_text != "delay")
            throw std::invalid_argument("--task must be classify or delay, got \"" + task_text + "\"");
        if (scene_from.empty())
            throw std::invalid_argument("--scene-from: give the bundle whose scene the test frames use");
        if (baselines && mask_path.empty())
            throw std::invalid_argument("--baselines needs --mask");
        if (frames < 1 || repeat < 1 || svm_frames < 10 || speed_frames < 1)
            throw std::invalid_argument("--frames, --repeat, --speed-frames must be >= 1, --svm-frames >= 10");
        if (!label.empty() && bundles.size() != 1)
            throw std::invalid_argument("--label names a single --bundle");
        const bool classify = task_text == "classify";
        const auto snrs = parse_list(snr_text, "--snr");
        std::vector<int> batches;
        for (double b : parse_list(batches_text, "--batches")) {
            if (b < 1 || b != std::floor(b))
                throw std::invalid_argument("--batches: whole numbers >= 1");
            batches.push_back(static_cast<int>(b));
        }
        const auto tsnr = parse_list(train_snr_text, "--train-snr");
        if (tsnr.size() != 2 || tsnr[0] > tsnr[1])
            throw std::invalid_argument("--train-snr: give lo,hi with lo <= hi");

        const model_bundle ref = model_bundle::load(scene_from);
        const frame_settings fs = ref.frame;
        const scene sc = scene::from_json(ref.training.at("scene"), scene_from + "/bundle.json: training.scene");

        // The methods, each with the mask it observes.
        std::vector<std::pair<method, pilot_mask>> methods;
        std::vector<std::shared_ptr<void>> keep; // owners of the methods' state
        for (const std::string& dir : bundles) {
            model_bundle b = model_bundle::load(dir);
            if ((b.task == task_kind::classify) != classify)
                throw std::invalid_argument("--bundle " + dir + ": not a " + task_text + " bundle");
            std::vector<bool> refine_variants{ false };
            if (!classify && no_refine && b.decoder.at("settings").value("refine_paths", 0) > 0)
                refine_variants.push_back(true);
            for (bool off : refine_variants) {
                model_bundle bb = b;
                if (off)
                    bb.decoder["settings"]["refine_paths"] = 0;
                auto dec = std::make_shared<bundle_decoder>(bb, 1);
                keep.push_back(dec);
                method m;
                m.name = (label.empty() ? dir : label) + (off ? " (refine off)" : "");
                m.kind = bb.decoder.at("kind").get<std::string>();
                m.settings = bb.decoder.at("settings").dump();
                const int c = static_cast<int>(b.class_names.size());
                m.run = [dec, classify, c](const gr_complex* o, int n) {
                    std::vector<double> out(n);
                    if (classify) {
                        const auto p = dec->classify(o, n);
                        for (int f = 0; f < n; ++f)
                            out[f] = std::max_element(p.begin() + f * c, p.begin() + (f + 1) * c) - (p.begin() + f * c);
                    } else {
                        const auto d = dec->estimate_delay_index(o, n);
                        std::copy(d.begin(), d.end(), out.begin());
                    }
                    return out;
                };
                methods.push_back({ m, bb.mask });
            }
        }
        if (baselines) {
            const pilot_mask mask = pilot_mask::load(mask_path);
            auto per_frame = [](auto est, int np) {
                return [est, np](const gr_complex* o, int n) {
                    std::vector<double> out(n);
                    for (int f = 0; f < n; ++f)
                        out[f] = est(o + static_cast<size_t>(f) * np);
                    return out;
                };
            };
            const int np = mask.size();
            if (classify) {
                std::vector<frame_truth> tt;
                const auto tr = observe(fs, sc, mask, train_seed + 202, svm_frames, tsnr[0], tsnr[1], tt);
                auto fx = std::make_shared<doppler_features>(fs, mask);
                std::vector<std::vector<double>> x;
                std::vector<int> y;
                for (int f = 0; f < svm_frames; ++f) {
                    x.push_back(fx->extract(tr.data() + static_cast<size_t>(f) * np));
                    y.push_back(tt[f].class_id);
                }
                auto svm = std::make_shared<feature_svm>(x, y);
                // The SVM predicts class ids; map them to the bundle's class order.
                std::vector<int> to_bundle(64, -1);
                for (size_t k = 0; k < ref.class_names.size(); ++k)
                    for (int f = 0; f < svm_frames; ++f)
                        if (tt[f].class_name == ref.class_names[k])
                            to_bundle.at(tt[f].class_id) = static_cast<int>(k);
                method m{ "feature SVM", "svm",
                          "{\"features\":6,\"train_frames\":" + std::to_string(svm_frames) +
                              ",\"support_vectors\":" + std::to_string(svm->n_support_vectors()) + "}",
                          per_frame([fx, svm, to_bundle](const gr_complex* o) {
                              return double(to_bundle.at(svm->predict(fx->extract(o))));
                          }, np),
                          false };
                methods.push_back({ m, mask });
            } else {
                delay_search win;
                const nn::delay_settings d{};
                win.oversample = 8;
                win.min_index = d.tau_min_index;
                win.max_index = d.tau_max_index;
                periodogram_delay_estimator::settings ps;
                ps.search = win;
                auto pg = std::make_shared<periodogram_delay_estimator>(fs, mask, ps);
                methods.push_back({ { "periodogram", "periodogram", "{\"oversample\":8}",
                                      per_frame([pg](const gr_complex* o) { return pg->estimate_index(o); }, np), false },
                                    mask });
                omp_delay_estimator::settings os;
                os.search = win;
                os.n_atoms = 1;
                auto omp = std::make_shared<omp_delay_estimator>(fs, mask, os);
                methods.push_back({ { "OMP", "omp", "{\"atoms\":1}",
                                      per_frame([omp](const gr_complex* o) { return omp->estimate_index(o); }, np), false },
                                    mask });
                os.refine = true;
                auto ompr = std::make_shared<omp_delay_estimator>(fs, mask, os);
                methods.push_back({ { "OMP + LS refinement", "omp", "{\"atoms\":1,\"refine\":true}",
                                      per_frame([ompr](const gr_complex* o) { return ompr->estimate_index(o); }, np),
                                      false },
                                    mask });
                ls_delay_estimator::settings ls;
                ls.search = win;
                ls.n_paths = 1;
                auto lse = std::make_shared<ls_delay_estimator>(fs, mask, ls);
                methods.push_back({ { "LS (1 path)", "ls", "{\"paths\":1}",
                                      per_frame([lse](const gr_complex* o) { return lse->estimate_index(o); }, np), false },
                                    mask });
            }
        }
        if (methods.empty())
            throw std::invalid_argument("nothing to evaluate: give --bundle and/or --baselines");

        std::ofstream csv;
        if (!csv_path.empty()) {
            const bool fresh = !std::ifstream(csv_path).good();
            csv.open(csv_path, std::ios::app);
            if (!csv)
                throw std::runtime_error("--csv " + csv_path + ": cannot open for appending");
            if (fresh) {
                csv << "task,method,kind,snr_db,frames,accuracy,mae_index,median_abs_error_index,frac_over_half_index";
                for (int b : batches)
                    csv << ",fps_wall_b" << b << ",fps_cpu_b" << b << ",latency_ms_b" << b;
                csv << ",settings\n";
            }
        }
        for (const auto& [m, mask] : methods) {
            std::vector<speed> sp;
            for (int b : batches)
                sp.push_back(time_method(m, mask.size(), m.batched ? b : 1, speed_frames, repeat));
            for (double snr : snrs) {
                std::vector<frame_truth> truths;
                const auto obs = observe(fs, sc, mask, fresh_seed, frames, snr, snr, truths);
                std::vector<double> out;
                const int chunk = 256;
                for (int f = 0; f < frames; f += chunk) {
                    const int n = std::min(chunk, frames - f);
                    const auto o = m.run(obs.data() + static_cast<size_t>(f) * mask.size(), n);
                    out.insert(out.end(), o.begin(), o.end());
                }
                double acc = NAN, mae = NAN, median = NAN, gross = NAN;
                if (classify) {
                    int correct = 0;
                    for (int f = 0; f < frames; ++f)
                        correct += ref.class_names.at(static_cast<size_t>(out[f])) == truths[f].class_name;
                    acc = double(correct) / frames;
                } else {
                    std::vector<double> err(frames);
                    double sum = 0.0, over = 0.0;
                    for (int f = 0; f < frames; ++f) {
                        err[f] = std::abs(out[f] - truths[f].delay_index);
                        sum += err[f];
                        over += err[f] > 0.5;
                    }
                    std::nth_element(err.begin(), err.begin() + frames / 2, err.end());
                    mae = sum / frames;
                    median = err[frames / 2];
                    gross = over / frames;
                }
                std::printf("%-40s %5.0f dB  %s", m.name.c_str(), snr,
                            classify ? ("acc " + std::to_string(acc)).c_str()
                                     : ("MAE " + std::to_string(mae) + " median " + std::to_string(median)).c_str());
                for (const auto& s : sp)
                    std::printf("  b%d %.0f/%.0f fps", s.batch, s.wall_fps, s.cpu_fps);
                std::printf("\n");
                std::fflush(stdout);
                if (csv.is_open()) {
                    csv << task_text << ",\"" << m.name << "\"," << m.kind << "," << snr << "," << frames << ","
                        << acc << "," << mae << "," << median << "," << gross;
                    for (size_t i = 0; i < sp.size(); ++i)
                        csv << "," << sp[i].wall_fps << "," << sp[i].cpu_fps << ","
                            << 1e3 * batches[i] / std::max(sp[i].wall_fps, 1e-9);
                    std::string st = m.settings;
                    std::replace(st.begin(), st.end(), '"', '\'');
                    csv << ",\"" << st << "\"\n";
                    csv.flush();
                }
            }
        }
    } catch (const std::exception& e) {
        std::cerr << "sems_pareto_eval: " << e.what() << std::endl;
        return 1;
    }
    return 0;
}
