// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_train: learn a pilot mask and a task decoder, write a model bundle.
 *
 *   sems_train --task classify --out models/classifier --snr-min 0 --snr-max 20 --threads 2
 *   sems_train --task delay --paths 3 --snr-min 10 --snr-max 30 --out models/delay_multipath
 *   sems_train --task classify --mask uniform.json --out uniform_bundle   (decoder only)
 *   sems_train --task classify --pilot-power learned --out powered   (learned placement and energies)
 *   sems_train --task delay --mask m.json --pilot-phases newman --out d   (pilots with Newman phases)
 *   sems_train ... --world-size 2 --rank R --store-file /tmp/rdzv   (one of 2 ranks, one machine)
 *   sems_train --from models/classifier --out retrained   (again, from the bundle's recorded settings)
 *   sems_train --task classify --frame sdr_2g4_20mhz --out sdr_classifier   (another radio's frame)
 *   sems_train --frame-bundle models/classifier_kinematic --track-frames 32 --out track_bundle
 *       (a decision over a track on a trained per-frame classifier: learning/temporal/track_trainer.h)
 *   sems_train --frame-bundle b8 --super-frames 4 --out sf_bundle   (4 pilot sets learned across frames)
 *   sems_train --delay-bundle delay_single --array ula8_3g --out position_ula8
 *       (a position bundle: an angle network over an array's pilots: learning/array/position_trainer.h)
 *
 * See include/gnuradio/sems/learning/training/trainer.h for what the phases do and
 * docs/reference/distributed_training.md for several processes and machines.
 */
#include "command_line.h"
#include "frame_options.h"
#include "model_card_speed.h"
#include <gnuradio/sems/core/radio/front_end.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sems/core/scene/target_class.h>
#include <gnuradio/sems/learning/array/position_trainer.h>
#include <gnuradio/sems/learning/bundles/model_card.h>
#include <gnuradio/sems/learning/temporal/track_trainer.h>
#include <gnuradio/sems/learning/training/trainer.h>
#include <algorithm>
#include <boost/program_options.hpp>
#include <cmath>
#include <iostream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace po = boost::program_options;
using namespace gr::sems;

namespace {
std::vector<std::string> split_list(const std::string& s)
{
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
        if (!item.empty())
            out.push_back(item);
    return out;
}

double parse_snr(const std::string& s)
{
    if (s == "inf" || s == "+inf")
        return std::numeric_limits<double>::infinity();
    size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size())
        throw std::invalid_argument("not a number: " + s);
    return v;
}

// The model card's SNR to cite: 10 dB when measured, else the measured SNR closest to it.
double cite_snr(const std::vector<double>& snrs)
{
    double best = snrs.front();
    for (double v : snrs)
        if (std::abs(v - 10.0) < std::abs(best - 10.0))
            best = v;
    return best;
}

// The card of a bundle just written (model_card.h): `figures` per SNR from its test split,
// the sink's decoder timed beside the anchor on a few frames (sems_eval --model-card measures
// a card on a fixed test set, with more frames).
void write_card(const model_bundle& written, model_card::test_record test)
{
    auto card = model_card::of_bundle(written);
    card.test = std::move(test);
    std::vector<double> snrs;
    for (const auto& f : card.test.by_snr)
        snrs.push_back(f.snr_db);
    if (snrs.empty())
        return; // no test SNR, no figures: no card
    card.cite_snr_db = cite_snr(snrs);
    // A rough figure that costs training little: one sink batch of the paper's frame, twice, and
    // as many resource elements on a larger frame (a preset of 28 times the paper's grid decodes
    // about 100 frames/s); sems_eval --model-card times thousands of frames.
    const int speed_frames = std::clamp(32 * 2048 / written.frame.grid_size(), 1, 32), speed_repeats = 2;
    card.speed = apps::measure_card_speed(written, card.cite_snr_db, speed_frames, speed_repeats, card.test.seed + 1);
    card.save(written.directory);
}

// --delay-bundle and --array: a position bundle on a trained delay bundle. Only the flags that
// mean something for it may be given; the position trainer's own defaults apply to the rest.
int train_positions(const po::variables_map& vm, const std::string& command_line)
{
    static const std::set<std::string> allowed = { "delay-bundle", "array", "scene", "frames", "snr", "snr-min", "snr-max",
                                                    "epochs", "batch", "lr", "patience", "seed", "threads",
                                                    "eval-snr", "angle-grid", "out", "quiet" };
    for (const auto& [name, value] : vm)
        if (!value.defaulted() && !allowed.count(name))
            throw std::invalid_argument("--" + name + " does not apply to --delay-bundle (a position bundle on a "
                                        "trained delay bundle: its mask, frame and delay decoder are the bundle's)");
    position_training_settings p;
    p.delay_bundle = vm["delay-bundle"].as<std::string>();
    if (!vm.count("array"))
        throw std::invalid_argument("--delay-bundle needs --array (a preset's name, e.g. ula8_3g, or an array file)");
    p.array = vm["array"].as<std::string>();
    p.out_dir = vm["out"].as<std::string>();
    auto given = [&](const char* flag) { return vm.count(flag) && !vm[flag].defaulted(); };
    if (given("frames"))
        p.frames = vm["frames"].as<int>();
    if (given("epochs"))
        p.epochs = vm["epochs"].as<int>();
    if (given("batch"))
        p.batch = vm["batch"].as<int>();
    if (given("lr"))
        p.lr = vm["lr"].as<double>();
    if (given("patience"))
        p.patience = vm["patience"].as<int>();
    if (given("seed"))
        p.seed = vm["seed"].as<uint64_t>();
    if (given("threads"))
        p.threads = vm["threads"].as<int>();
    if (given("angle-grid"))
        p.angle.grid = vm["angle-grid"].as<int>();
    if (given("snr")) {
        p.snr_min_db = p.snr_max_db = parse_snr(vm["snr"].as<std::string>());
    } else {
        if (given("snr-min"))
            p.snr_min_db = parse_snr(vm["snr-min"].as<std::string>());
        if (given("snr-max"))
            p.snr_max_db = parse_snr(vm["snr-max"].as<std::string>());
    }
    if (given("eval-snr")) {
        p.eval_snr_db.clear();
        for (const auto& v : split_list(vm["eval-snr"].as<std::string>()))
            p.eval_snr_db.push_back(parse_snr(v));
    }
    if (given("scene")) {
        p.scene_spec = scene::load(vm["scene"].as<std::string>());
        p.scene_source = vm["scene"].as<std::string>();
    }
    p.verbose = !vm.count("quiet");
    p.command_line = command_line;
    const auto r = train_position(p, &std::cout);
    // The card: its test split's figures per SNR.
    model_card::test_record test;
    test.measured_by = "sems_train test split";
    test.command = command_line;
    test.frames = "the trainer's test split (a tenth of --frames), the same noise scaled to each SNR";
    test.scene = p.scene_source;
    test.seed = p.seed;
    const frame_settings& fs = r.bundle.frame;
    for (const auto& m : r.metrics.at("by_snr")) {
        model_card::snr_figures f;
        f.snr_db = m.at("snr_db").get<double>();
        f.frames = m.at("frames").get<int>();
        f.mae_index = m.at("mae_index").get<double>();
        f.mae_m = *f.mae_index * fs.range_per_delay_index_m();
        f.median_abs_error_index = m.at("median_abs_error_index").get<double>();
        f.rmse_azimuth_rad = m.at("rmse_azimuth_rad").get<double>();
        if (m.contains("crb_azimuth_rad"))
            f.crb_azimuth_rad = m.at("crb_azimuth_rad").get<double>();
        test.by_snr.push_back(f);
    }
    write_card(r.bundle, test);
    std::cout << "position bundle written to " << p.out_dir << " (" << r.seconds << " s)" << std::endl;
    return 0;
}

// --frame-bundle: a decision over a track on a trained per-frame classifier. Only the flags
// that mean something for it may be given; the track trainer's own defaults apply to the rest.
int train_tracks(const po::variables_map& vm, const std::string& command_line)
{
    static const std::set<std::string> allowed = { "frame-bundle", "track-model", "track-loss-ramp", "track-frames",
                                                    "tracks", "track-hidden", "track-no-profile", "track-dropout", "track-weight-decay",
                                                    "track-eval-frames", "super-frames", "super-frame-epochs",
                                                    "super-frame-tracks", "super-frame-start", "scene", "snr", "snr-min", "snr-max",
                                                    "epochs", "batch", "lr", "patience", "seed", "threads",
                                                    "eval-snr", "out", "quiet" };
    for (const auto& [name, value] : vm)
        if (!value.defaulted() && !allowed.count(name))
            throw std::invalid_argument("--" + name + " does not apply to --frame-bundle (a decision over a track "
                                        "on a trained per-frame bundle: its mask, frame and classes are the bundle's)");
    track_training_settings t;
    t.frame_bundle = vm["frame-bundle"].as<std::string>();
    t.out_dir = vm["out"].as<std::string>();
    auto given = [&](const char* flag) { return vm.count(flag) && !vm[flag].defaulted(); };
    t.temporal.kind = vm["track-model"].as<std::string>();
    const auto kinds = nn::temporal_settings::kinds();
    if (std::find(kinds.begin(), kinds.end(), t.temporal.kind) == kinds.end()) {
        std::string known;
        for (const auto& k : kinds)
            known += (known.empty() ? "" : " or ") + k;
        throw std::invalid_argument("--track-model: unknown temporal model \"" + t.temporal.kind + "\" (give " +
                                    known + ")");
    }
    if (t.temporal.kind != "gru_fusion")
        for (const char* gru_only : { "track-hidden", "track-no-profile" })
            if (given(gru_only))
                throw std::invalid_argument(std::string("--") + gru_only + " applies to --track-model gru_fusion (the "
                                            "GRU's), not " + t.temporal.kind);
    if (given("track-loss-ramp"))
        t.loss_ramp = vm["track-loss-ramp"].as<double>();
    if (given("track-frames"))
        t.track_frames = vm["track-frames"].as<int>();
    if (given("tracks"))
        t.tracks = vm["tracks"].as<int>();
    if (given("track-hidden"))
        t.temporal.hidden = vm["track-hidden"].as<int>();
    if (vm.count("track-no-profile") && vm["track-no-profile"].as<bool>())
        t.temporal.doppler_profile = false;
    if (given("super-frames"))
        t.super_frames = vm["super-frames"].as<int>();
    if (given("super-frame-epochs"))
        t.mask_epochs = vm["super-frame-epochs"].as<int>();
    if (given("super-frame-tracks"))
        t.mask_tracks = vm["super-frame-tracks"].as<int>();
    if (given("super-frame-start"))
        t.mask_start = vm["super-frame-start"].as<std::string>();
    if (given("track-dropout"))
        t.temporal.dropout = vm["track-dropout"].as<double>();
    if (given("track-weight-decay"))
        t.weight_decay = vm["track-weight-decay"].as<double>();
    if (given("epochs"))
        t.epochs = vm["epochs"].as<int>();
    if (given("batch"))
        t.batch = vm["batch"].as<int>();
    if (given("lr")) // the chosen model's rate
        (t.temporal.kind == "acf_tcn" ? t.acf_tcn_lr : t.lr) = vm["lr"].as<double>();
    if (given("patience"))
        t.patience = vm["patience"].as<int>();
    if (given("seed"))
        t.seed = vm["seed"].as<uint64_t>();
    if (given("threads"))
        t.threads = vm["threads"].as<int>();
    if (given("snr")) {
        if (given("snr-min") || given("snr-max"))
            throw std::invalid_argument("give either --snr or --snr-min/--snr-max");
        t.snr_min_db = t.snr_max_db = parse_snr(vm["snr"].as<std::string>());
    } else if (given("snr-min") || given("snr-max")) {
        if (!given("snr-min") || !given("snr-max"))
            throw std::invalid_argument("--snr-min and --snr-max go together");
        t.snr_min_db = parse_snr(vm["snr-min"].as<std::string>());
        t.snr_max_db = parse_snr(vm["snr-max"].as<std::string>());
    }
    if (given("eval-snr")) {
        t.eval_snr_db.clear();
        for (const auto& v : split_list(vm["eval-snr"].as<std::string>()))
            t.eval_snr_db.push_back(parse_snr(v));
    }
    if (given("track-eval-frames")) {
        t.eval_frames.clear();
        for (const auto& v : split_list(vm["track-eval-frames"].as<std::string>()))
            t.eval_frames.push_back(std::stoi(v));
    } else { // 1, 2, 4, ... up to the track length, and the track length itself
        t.eval_frames.clear();
        for (int f = 1; f < t.track_frames; f *= 2)
            t.eval_frames.push_back(f);
        t.eval_frames.push_back(t.track_frames);
    }
    if (given("scene")) {
        t.scene_spec = scene::load(vm["scene"].as<std::string>());
        t.scene_source = vm["scene"].as<std::string>();
    }
    t.verbose = !vm.count("quiet");
    t.command_line = command_line;
    const auto r = train_track(t, &std::cout);
    // The card: its test tracks' figures after the first frame and after the longest time scored.
    model_card::test_record test;
    test.measured_by = "sems_train test split";
    test.command = command_line;
    test.frames = "the trainer's test tracks (a tenth of --tracks), each scored at every SNR";
    test.scene = t.scene_source;
    test.seed = t.seed;
    test.track_frames = *std::max_element(t.eval_frames.begin(), t.eval_frames.end());
    for (const auto& by : r.metrics.at("by_snr")) {
        model_card::snr_figures f;
        f.snr_db = by.at("snr_db").get<double>();
        for (const auto& row : by.at("by_frames")) {
            const int frames = row.at("frames").get<int>();
            if (frames == 1)
                f.first_frame_accuracy = row.at("accuracy").get<double>();
            if (frames == test.track_frames) {
                f.accuracy = row.at("accuracy").get<double>();
                f.frames = row.at("tracks").get<int>();
            }
        }
        if (f.accuracy && f.frames > 0 && std::isfinite(f.snr_db))
            test.by_snr.push_back(f);
    }
    write_card(r.bundle, test);
    std::cout << "track bundle written to " << t.out_dir << " (" << r.seconds << " s)" << std::endl;
    return 0;
}
// What --delay-bundle and --frame-bundle train with when a flag is not given: their trainer's
// own defaults, not the ones --help shows beside each flag (those are the classifier's).
std::string own_defaults(int frames_or_tracks,
                         const char* what,
                         int epochs,
                         int batch,
                         double lr,
                         int threads,
                         const std::vector<double>& eval_snr_db)
{
    std::ostringstream o;
    o << "; a flag not given keeps that trainer's own default, not the one shown above: " << frames_or_tracks
      << " " << what << ", " << epochs << " epochs, batch " << batch << ", lr " << lr << ", "
      << (threads > 0 ? std::to_string(threads) + " threads" : std::string("LibTorch's threads (every core)"))
      << ", test SNRs";
    for (size_t i = 0; i < eval_snr_db.size(); ++i)
        o << (i ? "," : " ") << eval_snr_db[i];
    o << " dB";
    return o.str();
}
} // namespace

int main(int argc, char** argv)
{
    training_settings s;
    const position_training_settings pd;
    const track_training_settings td;
    const std::string delay_bundle_help =
        "train a position bundle on this trained delay bundle (a directory or name, e.g. delay_single): an angle "
        "network over the pilots of --array, whose beamformed pilots the bundle's delay decoder reads "
        "(learning/array/position_trainer.h); takes --scene, --frames, --epochs, --batch, --lr, --patience, --seed, "
        "--threads, --snr*, --eval-snr, --angle-grid, --out" +
        own_defaults(pd.frames, "frames", pd.epochs, pd.batch, pd.lr, pd.threads, pd.eval_snr_db);
    const std::string frame_bundle_help =
        "train a decision over a track on this trained per-frame classifier bundle (a directory or name): a GRU over "
        "its per-frame evidence, started from the fusion of independent frames, or another --track-model; the track "
        "flags below and --scene, "
        "--snr*, --epochs, --batch, --lr, --patience, --seed, --threads, --eval-snr, --out apply" +
        own_defaults(td.tracks, "tracks", td.epochs, td.batch, td.lr, td.threads, td.eval_snr_db);
    std::string task, scene_file, classes, snr, snr_min, snr_max, eval_snr, heading, from;
    std::string class_library_name, radio_file;
    int paths = 1;
    double clutter_csr = std::numeric_limits<double>::quiet_NaN();
    bool no_md = false;

    po::options_description opts("sems_train: learn pilots and a task decoder, write a model bundle");
    apps::frame_options frame_flags;
    // clang-format off
    opts.add_options()
        ("help,h", "this help")
        ("task", po::value(&task), "classify | delay (required unless --from, --frame-bundle or --delay-bundle, which refuse it)")
        ("from", po::value(&from), "train again from this bundle's recorded settings (a bundle directory or name, e.g. classifier): "
                                   "same settings and seed (a bundle made by this version of sems_train comes out with the same mask and "
                                   "weights, bit for bit; one made by an earlier version need not); only --out, --frames, --epochs, "
                                   "--decoder-epochs, --batch, --eval-frames, --eval-snr, --threads, --data, --quiet, --dry-run and the distributed "
                                   "options may be given with it")
        ("objective", po::value(&s.objective)->default_value(s.objective), "task (SemS) | mse (reconstruction baseline)")
        ("pilots", po::value(&s.n_pilots)->default_value(s.n_pilots), "number of pilots N_p")
        ("mask", po::value(&s.mask_file), "fixed pilot mask file: train the decoder only")
        ("mask-pattern", po::value(&s.mask_pattern), "fixed standard mask (uniform|random|doppler|staggered|burst): train the decoder only")
        ("pilot-power", po::value(&s.pilot_power)->default_value(s.pilot_power), "pilot energies: equal (every pilot the same) | learned (the mask learner also shares the total pilot energy among the pilots; learned masks only)")
        ("pilot-power-floor", po::value(&s.pilot_power_floor)->default_value(s.pilot_power_floor), "--pilot-power learned: the smallest energy of a pilot, relative to equal power, in [0, 1)")
        ("pilot-phases", po::value(&s.pilot_phases), "pilot phases in the bundle's mask: newman (low crest factor: the pilots of one symbol do not peak together in time, so a radio's converter does not clip them) | zero (none); default: as the mask has them (a --mask file's own phases, none otherwise). The decoder sees Y/x_k (x_k the pilot sent, its phase included), so training is the same")
        ("radio", po::value(&radio_file), "radio file (format sems.radio, e.g. examples/radios/sdr_monostatic.json): draw every "
                                          "observation through its front end (leakage and canceller, oscillators, IQ imbalance, DC, "
                                          "converter; no sample clock offset) for training and the test metrics, and record it in the "
                                          "bundle; default: the ideal radio")
        ("scene", po::value(&scene_file), "scene JSON file (else a random scene from the flags below)")
        ("classes", po::value(&classes)->default_value("pedestrian,car,drone"),
         "random scene: comma-separated classes of --class-library (default: the paper's three; with another "
         "library, every class of it)")
        ("class-library", po::value(&class_library_name)->default_value("paper"),
         "random scene: the class library, by name (paper, kinematic, automotive, nr_urban, wifi_indoor) or file (format sems.classes); default: the "
         "library the frame names (the paper's for the paper frame)")
        ("paths", po::value(&paths)->default_value(1), "random scene: paths per target (1 = single path)")
        ("clutter-csr", po::value(&clutter_csr), "random scene: add static clutter at this clutter-to-signal ratio (dB)")
        ("no-micro-doppler", po::bool_switch(&no_md), "random scene: no micro-Doppler")
        ("heading", po::value(&heading)->default_value("approaching"), "random scene: approaching (radial velocity = +speed, the paper) | any (speed·cos θ, θ uniform)")
        ("snr", po::value(&snr), "fixed SNR in dB ('inf' = noiseless)")
        ("snr-min", po::value(&snr_min), "SNR range, low end (dB)")
        ("snr-max", po::value(&snr_max), "SNR range, high end (dB)")
        ("frames", po::value(&s.frames)->default_value(s.frames), "frames, split 8:1:1 train/val/test")
        ("epochs", po::value(&s.epochs)->default_value(s.epochs), "mask-learning epochs (decoder epochs with --mask)")
        ("decoder-epochs", po::value(&s.decoder_epochs)->default_value(s.decoder_epochs), "decoder epochs on the final learned mask")
        ("batch", po::value(&s.batch)->default_value(s.batch), "batch size")
        ("lr", po::value(&s.lr)->default_value(s.lr), "Adam learning rate")
        ("lr-final", po::value(&s.lr_final_scale)->default_value(s.lr_final_scale), "cosine schedule ends at lr * this")
        ("patience", po::value(&s.patience)->default_value(s.patience), "early stop after this many epochs without improvement")
        ("mask-settle-epochs", po::value(&s.mask_settle_epochs)->default_value(s.mask_settle_epochs), "phase 1 ends once the learned mask is unchanged for this many epochs (0 = never); its unused epochs go to the decoder phase")
        ("threads", po::value(&s.threads)->default_value(2), "LibTorch threads")
        ("data", po::value(&s.training_data)->default_value(s.training_data), "the training frames: hold (in memory, 8*N*M bytes a frame) | stream (computed again from their drawn paths for every batch: the same bundle, the emulator's time per epoch) | auto (stream when they would take more than a quarter of the machine's memory)")
        ("seed", po::value(&s.seed)->default_value(s.seed), "seed (data, noise, initial weights)")
        ("eval-snr", po::value(&eval_snr)->default_value("0,10,20,30"), "test SNR points (dB), comma-separated")
        ("eval-frames", po::value(&s.eval_frames)->default_value(s.eval_frames), "test frames per SNR point (0 = all)")
        ("out", po::value(&s.out_dir)->required(), "bundle directory to write")
        // Network sizes (defaults: include/gnuradio/sems/learning/networks/network_settings.h).
        ("width", po::value<int>(), "decoder width (classifier: channels of every convolution; delay: 1-D CNN channels)")
        ("depth", po::value<int>(), "decoder depth (resnet classifier: residual stages; delay: residual blocks; the spectral classifier has none)")
        ("hidden", po::value(&s.classifier.hidden)->default_value(s.classifier.hidden), "classifier MLP width")
        ("projections", po::value(&s.delay.projections)->default_value(s.delay.projections), "delay: complex time projections")
        ("kernel", po::value(&s.delay.kernel)->default_value(s.delay.kernel), "delay: 1-D kernel size (odd)")
        ("window", po::value(&s.delay.window)->default_value(s.delay.window), "delay: local soft-argmax half-window (0 = global)")
        ("dilation-growth", po::value(&s.delay.dilation_growth)->default_value(s.delay.dilation_growth), "delay: residual block i dilates by growth^i (1 = undilated)")
        ("refine-paths", po::value(&s.delay.refine_paths)->default_value(s.delay.refine_paths), "delay: paths of the least-squares refinement after the network (0 = off, -1 = the scene's paths per target)")
        ("delay-spacing", po::value(&s.delay_spacing)->default_value(s.delay_spacing), "delay: dictionary spacing (delay index)")
        ("temp-start", po::value(&s.encoder.temperature_start)->default_value(s.encoder.temperature_start), "Gumbel temperature at the start")
        ("temp-floor", po::value(&s.encoder.temperature_floor)->default_value(s.encoder.temperature_floor), "Gumbel temperature floor")
        ("temp-decay", po::value(&s.encoder.temperature_decay)->default_value(s.encoder.temperature_decay), "temperature factor per epoch")
        ("encoder", po::value(&s.encoder.kind)->default_value(s.encoder.kind), "mask learner: gumbel_topk (structured scores, top-N_p) | gumbel_heads (the paper's N_p heads)")
        ("free-scores", "encoder gumbel_topk: add a free N x M score term to a[n] + b[m]")
        ("soft-epochs", po::value(&s.encoder.soft_epochs)->default_value(s.encoder.soft_epochs), "mask epochs with a soft (relaxed) forward pass first; 0 = hard 0/1 masks from the start")
        ("embedding", po::value(&s.encoder.embedding)->default_value(s.encoder.embedding), "encoder: head embedding size")
        ("encoder-hidden", po::value(&s.encoder.hidden)->default_value(s.encoder.hidden), "encoder: MLP width")
        ("shared-scores", "encoder: add a score matrix shared by all heads")
        ("full-scores", "encoder: free N*M score matrix per head instead of the factorised a[n] + b[m]")
        ("collision-weight", po::value(&s.encoder.collision_weight)->default_value(s.encoder.collision_weight), "gumbel_heads: head collision penalty (0 = off)")
        ("classifier", po::value(&s.classifier.architecture)->default_value(s.classifier.architecture), "classifier decoder: spectral (phase-invariant Doppler profile, any mask) | resnet (the paper's)")
        ("mti", po::value(&s.classifier.mti)->default_value(s.classifier.mti), "spectral classifier: zero-Doppler stage none | mean (subtract each subcarrier's mean: removes static clutter) | both")
        ("doppler-bins", po::value(&s.classifier.doppler_bins)->default_value(s.classifier.doppler_bins), "spectral classifier: slow-time DFT size (>= symbols)")
        ("range-bins", po::value(&s.classifier.range_bins)->default_value(s.classifier.range_bins), "spectral classifier: range gate, L delay bins (coherent across subcarriers; -1 = 2·M); 0 = off (the subcarriers' Doppler profiles pooled in power)")
        ("chirp-bins", po::value(&s.classifier.chirp_bins)->default_value(s.classifier.chirp_bins), "spectral classifier: tone/chirp fit, the number of chirp rates (odd; 0 = off): the share of the slow-time energy one tone or chirp explains, which tells a car (a pure tone) from a pedestrian (a chirp) at equal Doppler; with or without the range gate")
        ("chirp-sweep-bins", po::value(&s.classifier.chirp_sweep_bins)->default_value(s.classifier.chirp_sweep_bins), "spectral classifier: the largest chirp rate of the fit, as its Doppler change over the frame in Doppler bins")
        ("chirp-min-pilots", po::value(&s.classifier.chirp_min_pilots)->default_value(s.classifier.chirp_min_pilots), "spectral classifier: the tone/chirp fit counts only subcarriers with at least this many pilots (1 = every observed one)")
        ("template-frames", po::value(&s.classifier.template_frames)->default_value(s.classifier.template_frames), "spectral classifier: keep this many training frames' noiseless pilots on the final mask as a template bank and add its class scores (each class's likelihood over its templates, the Monte-Carlo Bayes classifier of those frames) to the network's (0 = off, -1 = every training frame; costs 8 N_p T multiply-adds per frame and 8 N_p T bytes in decoder.pt; one process only)")
        ("conv-slope", po::value(&s.classifier.conv_slope)->default_value(s.classifier.conv_slope), "spectral classifier: leaky-ReLU slope of the convolutions (0 = ReLU, as bundles trained before this setting)")
        ("doppler-kernel", po::value(&s.classifier.kernel)->default_value(s.classifier.kernel), "spectral classifier: 1-D kernel over Doppler bins (odd)")
        ("encoder-lr-scale", po::value(&s.encoder.lr_scale)->default_value(s.encoder.lr_scale), "encoder lr = lr * this")
        ("delay-bundle", po::value<std::string>(), delay_bundle_help.c_str())
        ("array", po::value<std::string>(), "--delay-bundle: the array, a preset's name (ula8_3g, ula8_3g5, ura4x2_2g4, ula4_5g) or an array file")
        ("angle-grid", po::value<int>()->default_value(nn::angle_settings{}.grid), "--delay-bundle: azimuths of the angle network's spectrum grid")
        ("frame-bundle", po::value<std::string>(), frame_bundle_help.c_str())
        ("track-frames", po::value<int>()->default_value(track_training_settings{}.track_frames), "--frame-bundle: frames of a training track (K)")
        ("tracks", po::value<int>()->default_value(track_training_settings{}.tracks), "--frame-bundle: tracks drawn, split 8:1:1")
        ("track-model", po::value<std::string>()->default_value(track_training_settings{}.temporal.kind), "--frame-bundle: the temporal model, gru_fusion (a GRU over the frame decoder's evidence, started from the fusion of independent frames) or acf_tcn (causal dilated convolutions over each frame's slow-time autocorrelation of its pilots and class probabilities, the running mean and maximum, and a head; its own --lr default, 1e-3)")
        ("track-loss-ramp", po::value<double>()->default_value(track_training_settings{}.loss_ramp), "--frame-bundle: the loss weighs the decision after t of K frames by (t/K)^this (0: every frame alike)")
        ("track-hidden", po::value<int>()->default_value(track_training_settings{}.temporal.hidden), "--frame-bundle: the GRU's state size (gru_fusion)")
        ("track-no-profile", po::bool_switch(), "--frame-bundle: each frame's evidence without its log Doppler profile (the frame decoder's embedding and class log-probabilities only; gru_fusion)")
        ("super-frames", po::value<int>()->default_value(track_training_settings{}.super_frames), "--frame-bundle: F, the frames of a super-frame mask; F > 1 learns F sets of the bundle's N_p pilots (one per frame, set = frame index mod F) with its frame decoder before the temporal model")
        ("super-frame-epochs", po::value<int>()->default_value(track_training_settings{}.mask_epochs), "--super-frames > 1: epochs of the sets' learner")
        ("super-frame-start", po::value<std::string>()->default_value(track_training_settings{}.mask_start), "--super-frames > 1: where the sets start, frame (the bundle's mask in every set, kept unless an epoch validates better) or random")
        ("super-frame-tracks", po::value<int>()->default_value(track_training_settings{}.mask_tracks), "--super-frames > 1: training tracks it learns on (windows of min(2F, --track-frames) frames held whole: 8·N·M bytes a frame)")
        ("track-dropout", po::value<double>()->default_value(track_training_settings{}.temporal.dropout), "--frame-bundle: the share dropped in training, of each frame's evidence (gru_fusion) or of the pooled features (acf_tcn)")
        ("track-weight-decay", po::value<double>()->default_value(track_training_settings{}.weight_decay), "--frame-bundle: AdamW weight decay")
        ("track-eval-frames", po::value<std::string>(), "--frame-bundle: observation times scored, in frames, comma-separated (default 1, 2, 4, ... and the track length)")
        ("quiet", "no per-epoch progress")
        ("dry-run", "print the resolved settings (JSON: training record, decoder settings, frame) and exit without training")
        // Distributed training (docs/reference/distributed_training.md); the flags override
        // WORLD_SIZE, RANK, MASTER_ADDR, MASTER_PORT and GLOO_SOCKET_IFNAME.
        ("world-size", po::value<int>(), "number of ranks (processes) training together (default: WORLD_SIZE or 1)")
        ("rank", po::value<int>(), "this process's rank in [0, world-size) (default: RANK)")
        ("store-file", po::value<std::string>(), "rendezvous through this file (FileStore; one machine): a fresh path every run")
        ("master-addr", po::value<std::string>(), "rendezvous at rank 0's address (TCPStore; default: MASTER_ADDR)")
        ("master-port", po::value<int>(), "rank 0's TCPStore port (default: MASTER_PORT or 29500)")
        ("gloo-interface", po::value<std::string>(), "network interface for Gloo's connections (default: GLOO_SOCKET_IFNAME)")
        ("dist-timeout", po::value<double>(), "seconds a rank waits for the others (rendezvous, each collective) before failing");
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
        s.verbose = !vm.count("quiet");
        if (vm.count("frame-bundle"))
            return train_tracks(vm, apps::command_of(argc, argv));
        if (vm.count("delay-bundle"))
            return train_positions(vm, apps::command_of(argc, argv));
        frame_file frame; // the frame trained on, printed before training
        if (!from.empty()) {
            // The bundle's own settings; only sizes, output and where it runs may change.
            static const std::set<std::string> allowed = { "from", "out", "frames", "epochs", "decoder-epochs",
                                                            "batch", "eval-frames", "eval-snr", "threads", "data", "quiet", "dry-run",
                                                            "world-size", "rank", "store-file", "master-addr",
                                                            "master-port", "gloo-interface", "dist-timeout" };
            for (const auto& [name, value] : vm)
                if (!value.defaulted() && !allowed.count(name))
                    throw std::invalid_argument("--" + name + " cannot be given with --from (the bundle's recorded "
                                                "settings are used; only sizes, --out, --eval-snr, --threads, --data, --quiet, --dry-run "
                                                "and the distributed flags may change)");
            auto r = training_settings::from_bundle(model_bundle::load(from));
            auto size = [&](const char* flag, int& field, int value) {
                if (!vm[flag].defaulted())
                    field = value;
            };
            size("frames", r.frames, s.frames);
            size("epochs", r.epochs, s.epochs);
            size("decoder-epochs", r.decoder_epochs, s.decoder_epochs);
            size("batch", r.batch, s.batch);
            size("eval-frames", r.eval_frames, s.eval_frames);
            if (!vm["threads"].defaulted())
                r.threads = s.threads;
            r.training_data = s.training_data;
            if (!vm["eval-snr"].defaulted()) {
                r.eval_snr_db.clear();
                for (const auto& v : split_list(eval_snr))
                    r.eval_snr_db.push_back(parse_snr(v));
            }
            r.out_dir = s.out_dir;
            r.verbose = s.verbose;
            s = r;
            frame.name = "of bundle " + from;
            frame.frame = s.frame;
        }
        s.distributed = distributed_settings::from_environment();
        if (vm.count("world-size"))
            s.distributed.world_size = vm["world-size"].as<int>();
        if (vm.count("rank"))
            s.distributed.rank = vm["rank"].as<int>();
        if (vm.count("store-file"))
            s.distributed.store_file = vm["store-file"].as<std::string>();
        if (vm.count("master-addr"))
            s.distributed.master_addr = vm["master-addr"].as<std::string>();
        if (vm.count("master-port"))
            s.distributed.master_port = vm["master-port"].as<int>();
        if (vm.count("gloo-interface"))
            s.distributed.interface = vm["gloo-interface"].as<std::string>();
        if (vm.count("dist-timeout"))
            s.distributed.timeout_s = vm["dist-timeout"].as<double>();
        if (vm.count("shared-scores"))
            s.encoder.shared = true;
        if (vm.count("full-scores"))
            s.encoder.factorized = false;
        if (vm.count("free-scores"))
            s.encoder.free_scores = true;
        if (from.empty()) { // the settings from the flags
            if (task.empty())
                throw std::invalid_argument("--task is required (classify | delay), or --from a bundle");
            frame = frame_flags.resolve(vm);
            s.frame = frame.frame;
            if (vm["class-library"].defaulted() && !frame.classes.empty())
                class_library_name = frame.classes;
            s.task = task_from_name(task);
            if (vm.count("width")) {
                s.classifier.width = vm["width"].as<int>();
                s.delay.width = vm["width"].as<int>();
            }
            if (vm.count("depth")) {
                s.classifier.depth = vm["depth"].as<int>();
                s.delay.depth = vm["depth"].as<int>();
            }
            if (!snr.empty() && (!snr_min.empty() || !snr_max.empty()))
                throw std::invalid_argument("give either --snr or --snr-min/--snr-max");
            if (!snr.empty()) {
                s.snr_min_db = s.snr_max_db = parse_snr(snr);
            } else if (!snr_min.empty() || !snr_max.empty()) {
                if (snr_min.empty() || snr_max.empty())
                    throw std::invalid_argument("--snr-min and --snr-max go together");
                s.snr_min_db = parse_snr(snr_min);
                s.snr_max_db = parse_snr(snr_max);
            }
            s.eval_snr_db.clear();
            for (const auto& v : split_list(eval_snr))
                s.eval_snr_db.push_back(parse_snr(v));

            if (!scene_file.empty() && !vm["heading"].defaulted())
                throw std::invalid_argument("--heading is for random scenes built from the flags; with --scene, "
                                            "set \"heading\" in the scene file");
            if (!scene_file.empty() && !vm["class-library"].defaulted())
                throw std::invalid_argument("--class-library is for random scenes built from the flags; with --scene, "
                                            "set \"classes\" in the scene file");
            if (!radio_file.empty()) {
                s.radio = front_end_settings::load(radio_file);
                s.radio_source = radio_file;
            }
            if (!scene_file.empty()) {
                s.scene_spec = scene::load(scene_file);
                s.scene_source = scene_file;
            } else {
                const auto lib = class_library::find(class_library_name);
                const bool all_classes = vm["classes"].defaulted() && lib->name() != class_library::paper()->name();
                if (all_classes)
                    classes = "all of " + lib->name();
                random_spec r;
                r.classes.clear(); // empty: every class of the library
                if (!all_classes)
                    for (const auto& c : split_list(classes))
                        r.classes.push_back(static_cast<target_class>(lib->id_of(c)));
                r.paths_per_target = paths;
                r.micro_doppler = !no_md;
                r.heading = heading_from_name(heading);
                std::optional<clutter_spec> clutter;
                if (!std::isnan(clutter_csr)) {
                    clutter_spec c;
                    c.csr_db = clutter_csr;
                    clutter = c;
                }
                s.scene_spec = scene::random(r, clutter, fading_kind::rayleigh, lib);
                std::ostringstream src;
                src << "random scene (classes " << classes << ", " << paths << " path(s) per target"
                    << (no_md ? ", no micro-Doppler" : "") << ", heading " << heading
                    << (clutter ? ", clutter CSR " + std::to_string(clutter_csr) + " dB" : "") << ")";
                s.scene_source = src.str();
            }
        }
        s.command_line = apps::command_of(argc, argv);

        if (vm.count("dry-run")) {
            s.validate();
            nlohmann::json j = { { "training", s.to_json() }, { "frame", s.frame.to_json() } };
            j["training"]["scene"] = s.scene_spec ? s.scene_spec->to_json() : nlohmann::json();
            j[s.task == task_kind::classify ? "classifier" : "delay"] =
                s.task == task_kind::classify ? s.classifier.to_json() : s.delay.to_json();
            std::cout << j.dump(2) << std::endl;
            return 0;
        }
        if (s.distributed.rank == 0)
            std::cout << apps::describe(frame) << std::endl;
        const auto res = train(s, &std::cout);
        if (s.distributed.rank == 0) {
            // The card: the test split's figures per SNR (bundle.json's metrics.test_by_snr).
            model_card::test_record test;
            test.measured_by = "sems_train test split";
            test.command = s.command_line;
            test.frames = "the trainer's test split (a tenth of --frames), noise drawn at each SNR";
            test.scene = s.scene_source;
            test.seed = s.seed;
            if (s.radio)
                test.radio = s.radio_source;
            for (const auto& m : res.bundle.metrics.at("test_by_snr")) {
                model_card::snr_figures f;
                f.snr_db = m.at("snr_min_db").get<double>();
                f.frames = m.at("frames").get<int>();
                if (s.task == task_kind::classify) {
                    f.accuracy = m.at("accuracy").get<double>();
                } else {
                    f.mae_index = m.at("mae_index").get<double>();
                    f.mae_m = m.at("mae_m").get<double>();
                    f.median_abs_error_index = m.at("median_abs_error_index").get<double>();
                }
                if (std::isfinite(f.snr_db))
                    test.by_snr.push_back(f);
            }
            write_card(res.bundle, test);
            std::cout << "bundle written to " << s.out_dir << " (" << res.seconds << " s)" << std::endl;
        }
        return 0;
    } catch (const po::error& e) {
        std::cerr << "sems_train: " << e.what() << "\n\n" << opts << std::endl;
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "sems_train: " << e.what() << std::endl;
        return 1;
    }
}
