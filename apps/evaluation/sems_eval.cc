// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval: the paper's experiments on the same test frames for every method.
 *
 *   sems_eval --size test --out /tmp/eval            (seconds; what CTest runs)
 *   sems_eval --size full --out docs/results         (the documented run, see docs/RESULTS.md)
 *
 * Experiments (one CSV each in --out):
 *   1 exp1_recognition.csv   accuracy / macro-F1 vs SNR: SemS, Perfect CSI (noiseless and at
 *                            the test SNR), feature SVM (uniform / Doppler pilots), MSE-DL
 *   2 exp2_tsne_features.csv the classifier's 16-d features under uniform, Doppler, MSE and SemS pilots
 *   3 exp3_conditions.csv    experiment 1 without micro-Doppler and with strong clutter
 *   4 exp4_delay.csv         delay-index MAE vs SNR, single path and multipath: SemS, OMP,
 *                            periodogram, UP/RP/OP-MUSIC, CRB
 *   5 exp5_pilot_budget.csv  SemS delay MAE vs SNR for each N_p
 *   6 exp6_cost.csv          inference time per frame next to each method's accuracy / MAE
 *   7 exp7_kinematic.csv     experiment 1 on targets of moving scatterers (a kinematic class
 *                            library, any heading), with the staggered band-edge pattern;
 *     exp7_confusion.csv     every method's confusion matrix at --confusion-snr;
 *     exp7_pilot_budget.csv  SemS against the Doppler and staggered patterns at each N_p
 *     exp7_pilot_power.csv   SemS with learned pilot energies (same total) at N_p 32 and 128
 *     exp7_bank.csv, exp7_burst.csv, exp7_range.csv  the bank, burst and range parts (--exp7-parts)
 *   beside experiments 1, 3, 4, 5, 7 and 9's (classes) CSVs: <csv stem>_predictions.npz, every method's output on
 *     every test frame at every SNR and training seed (class ids; delay-index errors), and
 *     exp<N>_truth.npz, the test frames' truth, for the paired statistics of
 *     apps/figures/paired_stats.py (docs/reference/file_formats.md, "Kept predictions")
 *   8 exp8_tracks.csv        decisions over a track (kinematic library, any heading): accuracy /
 *                            macro-F1 against observation time (frames) and SNR for SemS-track,
 *                            the hand patterns under the same temporal decoder, the fusion of
 *                            independent frames, the SVM over the track and the Perfect-CSI
 *                            spectrogram CNN, on the same test tracks;
 *     exp8_predictions.csv   every method's decision on every test track (paired statistics);
 *     exp8_truth.csv         the test tracks' classes and lengths
 *   (experiment 8 runs only when asked: --experiments 8)
 *   9 exp9_angle.csv         an array's angle estimates (8-element ULA): RMSE against SNR next to
 *                            the CRB for one target (beamforming, Capon, MUSIC, and with
 *                            --exp9-position-bundle the learned position decoder on its mask
 *                            and array), and how often
 *                            two coherent targets 1.5 beamwidths apart are both found, with
 *                            exp9_angle_predictions.csv (run only when asked: --experiments 9;
 *                            --exp9-parts angle)
 *     exp9_classes.csv       classification per frame with 1, 4 and 8 elements, each frame's
 *                            pilots beamformed as SemS Classifier Sink does, by classifier
 *                            bundles trained on one antenna (--exp9-classifier-bundles), with
 *                            exp9_classes_predictions.npz and exp9_truth.npz (--exp9-parts classes)
 *     exp9_tracks.csv        a track bundle's decisions over tracks crossing the line of sight
 *                            with the same arrays, with exp9_tracks_predictions.csv and
 *                            exp9_tracks_truth.csv (--exp9-parts tracks)
 *     exp9_mimo.csv          a MIMO array's azimuth by the maximum-likelihood estimator through
 *                            learned MIMO masks and the hand forms (same pilots, time and
 *                            frequency division), against each mask's bound, with
 *                            exp9_mimo_masks.csv and exp9_mimo_predictions.csv (--exp9-parts mimo)
 *     exp9_mimo_budget.csv   those masks' bounds at fewer pilots (--exp9-parts mimo_budget)
 * Model cards: sems_eval --model-card models/classifier [more bundles] measures each bundle's
 *   figures per SNR on a fixed test set (--card-frames frames of its own scene, or --card-tracks
 *   tracks, at --card-snrs) and its speed, and writes model_card.json beside its bundle.json
 *   (sems_eval/model_cards.cc); no experiment runs and --out is not needed.
 * Test frames: one channel_model seed per scene (scene/gain and noise generators are
 * separate), noise drawn once with unit variance and scaled, so every SNR point and
 * every method sees exactly the same frames. Decoders are trained with the project's
 * trainer (trainer.h), once per training seed (--seeds: seed + --first-seed, then + 1, ...; the test
 * frames stay the same), and cached under <out>/bundles/<name>_s<seed> (reused when the
 * settings match). The score rows of experiments 1 to 8 carry their test seed and training seed
 * (or none) where the CSV has those columns (the confusion, range and experiment 9 CSVs keep fewer).
 */
#include "count_list.h"
#include "frame_options.h"
#include "sems_eval/eval.h"
#include <gnuradio/sems/core/common/limits.h>
#include <algorithm>
#include <boost/program_options.hpp>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace po = boost::program_options;
using namespace sems_eval;

namespace {

std::vector<double> parse_list(const std::string& s)
{
    std::vector<double> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item.empty())
            continue;
        size_t used = 0;
        const double v = std::stod(item, &used);
        if (used != item.size())
            throw std::invalid_argument("not a number: " + item);
        out.push_back(v);
    }
    if (out.empty())
        throw std::invalid_argument("empty list: \"" + s + "\"");
    return out;
}

// A comma-separated subset of `allowed`; an unknown name is an error naming the flag.
std::set<std::string> parse_names(const std::string& list, const std::set<std::string>& allowed, const std::string& flag)
{
    std::set<std::string> out;
    std::stringstream ss(list);
    std::string name;
    while (std::getline(ss, name, ',')) {
        if (!allowed.count(name)) {
            std::string known;
            for (const auto& a : allowed)
                known += (known.empty() ? "" : ", ") + a;
            throw std::invalid_argument(flag + ": \"" + name + "\" is not one of " + known);
        }
        out.insert(name);
    }
    return out;
}

void apply_size(config& c)
{
    if (c.size == "test") {
        // Seconds in CI: tiny sets, tiny training; the numbers mean nothing, the plumbing is checked.
        c.test_frames = 24;
        c.train_frames = 60;
        c.epochs = 1;
        c.decoder_epochs = 1;
        c.classifier_epochs = 1;
        c.batch = 32;
        c.seeds = 1; // the CTest test adds --seeds 2 to check the per-seed plumbing
        c.svm_train_frames = 60;
        c.tsne_frames = 24;
        c.snrs = { -10, 10, 30 };
        c.delay_snrs = { 0, 30 };
        c.np_sweep = { 2, 8 };
        c.exp7_np_sweep = { 8 };
        c.classic_oversample = 4; // experiment 8: eval.h's defaults are its test size
    } else if (c.size == "full") {
        // 3 + 3 epochs: what the documented run used (docs/RESULTS.md: the six experiments in
        // 65-100 minutes on 2 cores, split over processes). The data budget below is
        // the paper's; only the epochs trade accuracy for time.
        constexpr int full_epochs = 3;
        constexpr int full_decoder_epochs = 3;
        // The paper's budget: 30 000 training frames (split 8:1:1 by the trainer), batch 256,
        // 3 000 test frames per point, and 3 training seeds per learned method.
        c.test_frames = 3000;
        c.train_frames = 30000;
        c.epochs = full_epochs;
        c.decoder_epochs = full_decoder_epochs;
        // The classifiers' masks get 6 + 3 (the hand patterns and Perfect CSI 9 on the decoder):
        // with 3 mask epochs the learner had not always settled (docs/results/notes/evaluation_run.md).
        c.classifier_epochs = 6;
        c.batch = 256;
        c.seeds = 3;
        c.svm_train_frames = 3000;
        c.tsne_frames = 600;
        c.snrs = { -10, -5, 0, 5, 10, 15, 20, 25, 30 };
        c.delay_snrs = { -10, -5, 0, 5, 10, 15, 20, 25, 30 };
        c.np_sweep = { 2, 8, 16, 32, 64, 128 };
        c.exp7_np_sweep = { 128, 64, 16, 8 }; // with the main part's 32: 8..128
        c.exp7_power_np = { 32, 128 };
        // Where the network alone on the learned mask is behind the Doppler pattern beyond two
        // standard errors at some SNR (docs/RESULTS.md)
        c.exp7_bank_np = { 16, 64 };
        c.exp7_burst_np = { 8, 16 };
        c.classic_oversample = 16;
        // Experiment 8: 300 test tracks of 64 frames (2 s); each temporal decoder and the
        // spectrogram CNN on 4 000 tracks of their own (with 2 000 the temporal decoders stayed
        // level with the fusion of independent frames), the SVM on 600.
        c.exp8_test_tracks = 300;
        c.exp8_track_frames = 64;
        c.exp8_frames = { 1, 2, 4, 8, 16, 32, 64 };
        c.exp8_train_tracks = 4000;
        c.exp8_track_epochs = 15;
        c.exp8_cnn_epochs = 20;
        c.exp8_svm_tracks = 600;
        c.exp8_np_sweep = { 8, 128 };
        c.exp9_frames = 2000;
        c.exp9_snrs = { -10, -5, 0, 5, 10, 15, 20, 25, 30 };
        c.exp9_track_count = 300; // as experiment 8's test tracks
        c.exp9_track_frames = 32; // the shipped track bundle's training length
        c.exp9_mimo_epochs = 40;
        c.exp9_mimo_steps = 25;
        c.exp9_mimo_draws = 64;
        c.exp9_mimo_budget = { 4, 8, 16 };
        c.exp9_mimo_azimuths = 161;
    } else {
        throw std::invalid_argument("--size must be test or full, got \"" + c.size + "\"");
    }
}

} // namespace

int main(int argc, char** argv)
{
    config c;
    std::string experiments = "1,2,3,4,5,6,7", snrs, delay_snrs, np_sweep, exp7_np_sweep, exp7_parts = "main,budget,power,bank,burst",
                exp8_frames, exp8_np_sweep, exp8_parts = "main,budget", exp9_parts = "angle,classes,tracks,mimo,mimo_budget",
                exp9_classifier_bundles = "classifier_kinematic", exp9_class_elements = "1,4,8",
                delay_scenarios = "single,multipath";
    po::options_description opts("sems_eval: baselines, sweeps and figures data (one CSV per experiment)");
    apps::frame_options frame_flags;
    // clang-format off
    opts.add_options()
        ("help,h", "this help")
        ("size", po::value(&c.size)->default_value(c.size), "test (seconds, CI) | full (the documented run)")
        ("out", po::value(&c.out_dir), "output directory (CSVs, masks, cached bundles); required unless --model-card")
        ("experiments", po::value(&experiments)->default_value(experiments), "comma-separated subset of 1..9 (8 and 9 only when named)")
        ("seed", po::value(&c.seed)->default_value(c.seed), "seed of the test frames and the first training seed")
        ("seeds", po::value<int>(), "override: training seeds per learned method (seed + --first-seed, then + 1, ...; test 1, full 3)")
        ("first-seed", po::value(&c.first_seed)->default_value(c.first_seed),
         "train with seeds seed + first-seed, ... (the test frames stay those of --seed): one seed per process")
        ("threads", po::value(&c.threads)->default_value(c.threads), "LibTorch threads (training and inference)")
        ("test-frames", po::value<int>(), "override: test frames per operating point of experiments 1, 3, 4, 5, 7 and 9's classes part "
         "(test 24, full 3000), the same for every method, seed and SNR; e.g. 30000 for tighter paired tests (each "
         "scene's frames are held in memory: 16 N M bytes each, 1 GB at 30000 of 32 x 64)")
        ("train-frames", po::value<int>(), "override: training frames per network (split 8:1:1)")
        ("epochs", po::value<int>(), "override: mask-learning epochs of the delay networks (all learn their mask; a classifier "
         "on a fixed mask, a hand pattern's or Perfect CSI's, trains --classifier-epochs plus --decoder-epochs)")
        ("decoder-epochs", po::value<int>(), "override: decoder epochs after a learned mask (and added to a fixed mask's epochs)")
        ("classifier-epochs", po::value<int>(), "override: mask-learning epochs of every classification network (experiments 1-3, 7 and 8)")
        ("svm-train-frames", po::value<int>(), "override: feature-SVM training frames")
        ("tsne-frames", po::value<int>(), "override: frames in the t-SNE features")
        ("snrs", po::value(&snrs), "override: recognition SNR points (dB), comma-separated")
        ("delay-snrs", po::value(&delay_snrs), "override: delay SNR points (dB)")
        ("np-sweep", po::value(&np_sweep), "override: pilot budgets of experiment 5")
        ("clutter-csr", po::value(&c.clutter_csr_db)->default_value(c.clutter_csr_db), "clutter-to-signal ratio of the strong-clutter scene (dB)")
        ("class-library", po::value(&c.class_library)->default_value(c.class_library),
         "experiments 1-3: the class library of the recognition scenes, by name (paper, kinematic, automotive, nr_urban, wifi_indoor) or file; "
         "not given: the library --frame names (paper for the paper frame)")
        ("exp7-class-library", po::value(&c.exp7_class_library)->default_value(c.exp7_class_library),
         "experiments 7 and 8: the class library of targets of moving scatterers, by name or file")
        ("exp7-np-sweep", po::value(&exp7_np_sweep), "override: experiment 7's pilot budgets besides 32 (test 8; full 128,64,16,8)")
        ("exp7-parts", po::value(&exp7_parts)->default_value(exp7_parts),
         "experiment 7: comma-separated subset of main (N_p 32, every method), budget (the N_p sweep), power (SemS with "
         "learned pilot energies), bank (SemS and the Doppler pattern's decoder, each with a template bank, at N_p 8 in test, "
         "16 and 64 in full), burst (the decoder on the burst pattern at N_p 8 in test, 8 and 16 in full, beside the budget "
         "part's), to split a run over processes; "
         "range (a shipped classifier against range under a link budget, only when named: --exp7-range-bundle, --exp7-range-scene)")
        ("exp7-range-bundle", po::value(&c.exp7_range_bundle), "experiment 7's range part: the classifier bundle (its frame is used)")
        ("exp7-range-scene", po::value(&c.exp7_range_scene), "experiment 7's range part: a scene with a link budget, of the bundle's class library")
        ("exp7-range-frames", po::value(&c.exp7_range_frames), "experiment 7's range part: frames (default 10 x the test frames)")
        ("exp7-range-snr", po::value(&c.exp7_range_margin_db)->default_value(c.exp7_range_margin_db),
         "experiment 7's range part: the emulator's SNR setting in dB (0: the budget's thermal noise; +10: a floor 10 dB lower)")
        ("exp8-parts", po::value(&exp8_parts)->default_value(exp8_parts),
         "experiment 8: comma-separated subset of main (N_p 32, every method), budget (SemS-track against the track "
         "hand patterns at each --exp8-np-sweep budget), superframe (learned super-frame masks of --exp8-super-frames "
         "sets under the temporal decoder at each --exp8-np-sweep budget; only when named), to split a run over processes")
        ("exp8-super-frames", po::value<int>(), "experiment 8's superframe part: F, the frames of its learned super-frame masks (default 4)")
        ("exp8-super-frame-start", po::value<std::string>(), "experiment 8's superframe part: where the sets start, frame (the SemS frame mask, repeated) or random (default frame)")
        ("exp8-np-sweep", po::value(&exp8_np_sweep), "override: experiment 8's pilot budgets besides 32 (test 8; full 8,128)")
        ("exp8-frames", po::value(&exp8_frames), "override: experiment 8's observation times in frames (test 1,2,4,8; full 1,2,4,...,64); the largest is K")
        ("exp8-test-tracks", po::value<int>(), "override: experiment 8's test tracks (test 12, full 300)")
        ("exp8-train-tracks", po::value<int>(), "override: tracks of each temporal decoder and of the spectrogram CNN (test 40, full 4000)")
        ("exp8-track-epochs", po::value<int>(), "override: epochs of each temporal decoder (test 1, full 15)")
        ("exp8-cnn-epochs", po::value<int>(), "override: epochs of the spectrogram CNN (test 1, full 20)")
        ("exp8-svm-tracks", po::value<int>(), "override: training tracks of the SVM over the track (test 12, full 600)")
        ("confusion-snr", po::value(&c.confusion_snr_db)->default_value(c.confusion_snr_db), "experiment 7: SNR (dB) of the confusion matrices")
        ("multipath-paths", po::value(&c.multipath_paths)->default_value(c.multipath_paths), "paths per target in the multipath scene")
        ("shipped-classifier", po::value(&c.shipped_classifier), "also evaluate this shipped classifier bundle (experiment 1)")
        ("shipped-track", po::value(&c.shipped_track), "experiment 8: also score this shipped track bundle (and its frame decoder's fusion)")
        ("shipped-delay-single", po::value(&c.shipped_delay_single), "also evaluate this shipped single-path delay bundle")
        ("exp9-position-bundle", po::value(&c.exp9_position_bundle), "experiment 9: also score this position bundle "
         "(learned angle), or several of one mask and array comma-separated, one per training seed; every method then "
         "on their mask and array")
        ("exp9-parts", po::value(&exp9_parts)->default_value(exp9_parts),
         "experiment 9: comma-separated subset of angle (azimuth estimates against the CRB), classes (classification "
         "per frame with 1, 4 and 8 elements, beamformed as SemS Classifier Sink does), tracks (a track bundle's "
         "decisions over tracks crossing the line of sight, with the same arrays), mimo (learned MIMO masks against "
         "the hand forms, by the azimuth's bound and its maximum-likelihood estimate) and mimo_budget (their bounds "
         "at fewer pilots: test 4, 8; full 4, 8, 16)")
        ("exp9-mimo-array", po::value(&c.exp9_mimo_array)->default_value(c.exp9_mimo_array),
         "experiment 9's mimo part: the array (a preset's name or an array file with two or more transmit elements)")
        ("exp9-mimo-seeds", po::value(&c.exp9_mimo_seeds)->default_value(c.exp9_mimo_seeds),
         "experiment 9's mimo part: learned masks, seeds --seed, --seed + 1, ...")
        ("exp9-classifier-bundles", po::value(&exp9_classifier_bundles)->default_value(exp9_classifier_bundles),
         "experiment 9's classes part: comma-separated classifier bundles (names or directories) of one class library and "
         "pilot count, one per training seed, trained on one antenna")
        ("exp9-class-elements", po::value(&exp9_class_elements)->default_value(exp9_class_elements),
         "experiment 9's classes and tracks parts: the half-wavelength ULAs' element counts, comma-separated")
        ("exp9-track-bundle", po::value(&c.exp9_track_bundle)->default_value(c.exp9_track_bundle),
         "experiment 9's tracks part: the track bundle (a name or directory)")
        ("exp9-track-count", po::value<int>(), "override: experiment 9's test tracks (test 12, full 300)")
        ("exp9-track-frames", po::value<int>(), "override: experiment 9's planned frames of a test track (test 8, full 32)")
        ("shipped-delay-multipath", po::value(&c.shipped_delay_multi), "also evaluate this shipped multipath delay bundle")
        ("reuse-bundles", po::bool_switch(&c.reuse_bundles), "use every cached bundle in <out>/bundles as is (no check of the training settings; a bundle of another frame is refused)")
        ("only-shipped", po::bool_switch(&c.only_shipped), "evaluate only the shipped bundles (rows to add to a full run)")
        ("no-any-heading", "experiment 1: skip the \"any\" heading scene")
        ("no-hand-patterns", "experiment 1: skip the SemS decoder on the hand patterns (doppler, uniform, random)")
        ("delay-scenarios", po::value(&delay_scenarios)->default_value(delay_scenarios), "experiment 4: comma-separated subset of single,multipath (to split a run over processes)")
        ("model-card", po::value(&c.model_cards)->multitoken(), "measure these bundles (directories or names) on a fixed test set and write "
         "each one's model_card.json beside its bundle.json; only the --card-* options apply")
        ("card-frames", po::value(&c.card_frames)->default_value(c.card_frames), "--model-card: test frames per SNR "
         "(frames 0..n-1 of the bundle's training scene; with --card-seed 1 those scripts/demo.sh streams)")
        ("card-tracks", po::value(&c.card_tracks)->default_value(c.card_tracks), "--model-card: test tracks of a track bundle")
        ("card-track-frames", po::value(&c.card_track_frames)->default_value(c.card_track_frames),
         "--model-card: frames of a test track (0: the track bundle's training length)")
        ("card-snrs", po::value<std::string>()->default_value("0,10,20,30"), "--model-card: SNRs (dB), comma-separated")
        ("card-seed", po::value(&c.card_seed)->default_value(c.card_seed), "--model-card: seed of the test frames "
         "(a delay bundle's: this + 1, as the demo's delay channel; a position bundle's: this + 3); refused when it "
         "is the seed the bundle was trained with, whose first frames it would score")
        ("card-speed-frames", po::value(&c.card_speed_frames)->default_value(c.card_speed_frames),
         "--model-card: frames per timing run of the decoder and of the anchor")
        ("card-summary", po::value(&c.card_summary), "--model-card: the card's one-line summary (default: the card's own, "
         "else one made from the bundle)")
        ("card-cite-snr", po::value(&c.card_cite_snr_db), "--model-card: the SNR whose figure the card cites "
         "(default: the card's own, else 10 dB)");
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
        std::ostringstream cmd;
        for (int i = 0; i < argc; ++i)
            cmd << (i ? " " : "") << argv[i];
        c.command_line = cmd.str();
        if (!c.model_cards.empty()) {
            c.card_snrs = parse_list(vm["card-snrs"].as<std::string>());
            for (double v : c.card_snrs)
                if (!std::isfinite(v))
                    throw std::invalid_argument("--card-snrs: " + num(v) + " is not a finite SNR in dB");
            if (c.card_frames < 2 || c.card_tracks < 2 || c.card_track_frames < 0 || c.card_speed_frames < 1)
                throw std::invalid_argument("--card-frames >= 2, --card-tracks >= 2, --card-track-frames >= 0, "
                                            "--card-speed-frames >= 1");
            run_model_cards(c, std::cout);
            return 0;
        }
        if (c.out_dir.empty())
            throw std::invalid_argument("--out is required (the output directory), unless --model-card");
        apply_size(c);
        const frame_file frame = frame_flags.resolve(vm);
        c.fs = frame.frame;
        if (vm["class-library"].defaulted() && !frame.classes.empty())
            c.class_library = frame.classes;
        c.exp1_any_heading = !vm.count("no-any-heading");
        c.exp1_hand_patterns = !vm.count("no-hand-patterns");
        c.delay_scenarios = parse_names(delay_scenarios, { "single", "multipath" }, "--delay-scenarios");
        c.exp7_parts = parse_names(exp7_parts, { "main", "budget", "power", "bank", "burst", "range" }, "--exp7-parts");
        c.exp8_parts = parse_names(exp8_parts, { "main", "budget", "superframe" }, "--exp8-parts");
        c.exp9_parts = parse_names(exp9_parts, { "angle", "classes", "tracks", "mimo", "mimo_budget" }, "--exp9-parts");
        if (c.exp9_mimo_seeds < 1)
            throw std::invalid_argument("--exp9-mimo-seeds must be >= 1, got " + std::to_string(c.exp9_mimo_seeds));
        if (vm.count("exp9-track-count"))
            c.exp9_track_count = vm["exp9-track-count"].as<int>();
        if (vm.count("exp9-track-frames"))
            c.exp9_track_frames = vm["exp9-track-frames"].as<int>();
        if (c.exp9_track_count < 1 || c.exp9_track_frames < 1 || c.exp9_track_frames > limits::max_track_frames)
            throw std::invalid_argument("--exp9-track-count must be >= 1 and --exp9-track-frames in [1, " +
                                        std::to_string(limits::max_track_frames) + "]");
        c.exp9_class_elements = apps::parse_counts(exp9_class_elements, "--exp9-class-elements", 1, limits::max_array_elements);
        c.exp9_classifier_bundles.clear();
        {
            std::stringstream names(exp9_classifier_bundles);
            std::string name;
            while (std::getline(names, name, ','))
                if (!name.empty())
                    c.exp9_classifier_bundles.push_back(name);
            if (c.exp9_classifier_bundles.empty())
                throw std::invalid_argument("--exp9-classifier-bundles: no bundle given");
        }
        if (vm.count("exp8-super-frame-start")) {
            c.exp8_super_frame_start = vm["exp8-super-frame-start"].as<std::string>();
            if (c.exp8_super_frame_start != "frame" && c.exp8_super_frame_start != "random")
                throw std::invalid_argument("--exp8-super-frame-start must be frame or random, got \"" +
                                            c.exp8_super_frame_start + "\"");
        }
        if (vm.count("exp8-super-frames")) {
            c.exp8_super_frames = vm["exp8-super-frames"].as<int>();
            if (c.exp8_super_frames < 2 || c.exp8_super_frames > limits::max_super_frames)
                throw std::invalid_argument("--exp8-super-frames must be in [2, " + std::to_string(limits::max_super_frames) +
                                            "] (1 is the budget part's repeated mask), got " +
                                            std::to_string(c.exp8_super_frames));
        }
        for (const auto& [flag, field] : { std::pair<const char*, int*>{ "exp8-test-tracks", &c.exp8_test_tracks },
                                           { "exp8-train-tracks", &c.exp8_train_tracks },
                                           { "exp8-track-epochs", &c.exp8_track_epochs },
                                           { "exp8-cnn-epochs", &c.exp8_cnn_epochs },
                                           { "exp8-svm-tracks", &c.exp8_svm_tracks } })
            if (vm.count(flag))
                *field = vm[flag].as<int>();
        if (!exp8_np_sweep.empty()) {
            c.exp8_np_sweep.clear();
            for (double v : parse_list(exp8_np_sweep))
                c.exp8_np_sweep.push_back(static_cast<int>(v));
        }
        if (!exp8_frames.empty()) {
            c.exp8_frames.clear();
            for (double v : parse_list(exp8_frames)) {
                if (v < 1 || v != static_cast<int>(v) || v > limits::max_track_frames)
                    throw std::invalid_argument("--exp8-frames: " + std::to_string(v) + " is not a frame count in [1, " +
                                                std::to_string(limits::max_track_frames) + "]");
                c.exp8_frames.push_back(static_cast<int>(v));
            }
            std::sort(c.exp8_frames.begin(), c.exp8_frames.end());
            c.exp8_frames.erase(std::unique(c.exp8_frames.begin(), c.exp8_frames.end()), c.exp8_frames.end());
        }
        c.exp8_track_frames = c.exp8_frames.back();
        if (c.exp8_test_tracks < 2 || c.exp8_train_tracks < 10 || c.exp8_svm_tracks < 2 || c.exp8_track_epochs < 1 ||
            c.exp8_cnn_epochs < 1)
            throw std::invalid_argument("experiment 8: --exp8-test-tracks >= 2, --exp8-train-tracks >= 10, "
                                        "--exp8-svm-tracks >= 2, --exp8-track-epochs >= 1, --exp8-cnn-epochs >= 1");
        for (int np : c.exp8_np_sweep)
            if (np < 1 || np > c.fs.usable_elements())
                throw std::invalid_argument("--exp8-np-sweep: " + std::to_string(np) + " is outside [1, N*(M - guards) = " +
                                            std::to_string(c.fs.usable_elements()) + "]");
        if (vm.count("test-frames"))
            c.test_frames = vm["test-frames"].as<int>();
        if (vm.count("train-frames"))
            c.train_frames = vm["train-frames"].as<int>();
        if (vm.count("epochs"))
            c.epochs = vm["epochs"].as<int>();
        if (vm.count("decoder-epochs"))
            c.decoder_epochs = vm["decoder-epochs"].as<int>();
        if (vm.count("classifier-epochs"))
            c.classifier_epochs = vm["classifier-epochs"].as<int>();
        if (vm.count("svm-train-frames"))
            c.svm_train_frames = vm["svm-train-frames"].as<int>();
        if (vm.count("tsne-frames"))
            c.tsne_frames = vm["tsne-frames"].as<int>();
        if (vm.count("seeds")) {
            c.seeds = vm["seeds"].as<int>();
            if (c.seeds < 1)
                throw std::invalid_argument("--seeds must be >= 1 (training seeds per learned method), got " +
                                            std::to_string(c.seeds));
        }
        if (c.first_seed < 0)
            throw std::invalid_argument("--first-seed must be >= 0, got " + std::to_string(c.first_seed));
        if (!snrs.empty())
            c.snrs = parse_list(snrs);
        if (!delay_snrs.empty())
            c.delay_snrs = parse_list(delay_snrs);
        if (!exp7_np_sweep.empty()) {
            c.exp7_np_sweep.clear();
            for (double v : parse_list(exp7_np_sweep))
                c.exp7_np_sweep.push_back(static_cast<int>(v));
        }
        if (!np_sweep.empty()) {
            c.np_sweep.clear();
            for (double v : parse_list(np_sweep))
                c.np_sweep.push_back(static_cast<int>(v));
        }
        c.experiments.clear();
        for (double e : parse_list(experiments)) {
            if (e < 1 || e > 9 || e != static_cast<int>(e))
                throw std::invalid_argument("--experiments: " + std::to_string(e) + " is not one of 1..9");
            c.experiments.insert(static_cast<int>(e));
        }
        // Each scene's test frames are held in memory (H and W: 16 bytes per resource element each).
        const double max_test_frames = std::floor(8.0 * (1ull << 30) / (16.0 * c.fs.grid_size()));
        if (c.test_frames < 2 || c.test_frames > max_test_frames)
            throw std::invalid_argument("--test-frames must be in [2, " + num(max_test_frames, 10) +
                                        "] (test frames per operating point; at most 8 GB per scene of this frame), got " +
                                        std::to_string(c.test_frames));
        if (c.train_frames < 10 || c.svm_train_frames < 6 || c.tsne_frames < 2)
            throw std::invalid_argument("frame counts are too small (--train-frames >= 10, --svm-train-frames >= 6, "
                                        "--tsne-frames >= 2)");
        if (c.epochs < 1 || c.classifier_epochs < 1 || c.decoder_epochs < 0 || c.threads < 1)
            throw std::invalid_argument("--epochs >= 1, --classifier-epochs >= 1, --decoder-epochs >= 0, --threads >= 1");
        for (int np : c.np_sweep)
            if (np < 1 || np > c.fs.usable_elements())
                throw std::invalid_argument("--np-sweep: " + std::to_string(np) +
                                            " is outside [1, N*(M - guards) = " +
                                            std::to_string(c.fs.usable_elements()) + "]");
        for (int np : c.exp7_np_sweep)
            if (np < 1 || np > c.fs.usable_elements())
                throw std::invalid_argument("--exp7-np-sweep: " + std::to_string(np) +
                                            " is outside [1, N*(M - guards) = " +
                                            std::to_string(c.fs.usable_elements()) + "]");
        if (c.experiments.count(7) && c.exp7_parts.count("range")) {
            if (c.exp7_range_bundle.empty() || c.exp7_range_scene.empty())
                throw std::invalid_argument("--exp7-parts range needs --exp7-range-bundle (a classifier) and "
                                            "--exp7-range-scene (a scene with a link budget)");
            if (c.exp7_range_frames == 0)
                c.exp7_range_frames = 10 * c.test_frames;
            if (c.exp7_range_frames < 1)
                throw std::invalid_argument("--exp7-range-frames must be >= 1, got " + std::to_string(c.exp7_range_frames));
            if (!std::isfinite(c.exp7_range_margin_db))
                throw std::invalid_argument("--exp7-range-snr must be a finite number of dB");
        }
        // A shipped bundle (and experiment 9's classifiers) is scored on this run's test frames:
        // one of another frame is refused here, before any training, naming the first field that
        // differs and both values.
        std::vector<std::pair<std::string, std::string>> given = {
            { "shipped-classifier", c.shipped_classifier }, { "shipped-delay-single", c.shipped_delay_single },
            { "shipped-delay-multipath", c.shipped_delay_multi }, { "shipped-track", c.shipped_track }
        };
        {
            std::stringstream list(c.exp9_position_bundle); // one or several, comma-separated
            std::string dir;
            while (std::getline(list, dir, ','))
                given.emplace_back("exp9-position-bundle", dir);
        }
        if (c.experiments.count(9) && c.exp9_parts.count("classes"))
            for (const auto& dir : c.exp9_classifier_bundles)
                given.emplace_back("exp9-classifier-bundles", dir);
        if (c.experiments.count(9) && c.exp9_parts.count("tracks"))
            given.emplace_back("exp9-track-bundle", c.exp9_track_bundle);
        for (const auto& [flag, dir] : given)
            if (!dir.empty()) {
                model_bundle b;
                try {
                    b = model_bundle::load(dir);
                } catch (const std::exception& e) {
                    throw std::invalid_argument("--" + flag + ": " + e.what());
                }
                b.frame.require_same(c.fs, "--" + flag + " " + dir, "the bundle's frame",
                                     "the run's frame (--frame and its overrides)");
            }
        std::filesystem::create_directories(c.out_dir);

        std::cout << apps::describe(frame) << std::endl;
        std::cout << "[" << now_utc() << "] sems_eval --size " << c.size << ": " << c.test_frames
                  << " test frames per point, " << c.train_frames << " training frames, " << c.epochs << "+"
                  << c.decoder_epochs << " epochs (classifiers " << c.classifier_epochs << "+" << c.decoder_epochs << "), batch " << c.batch << ", test seed base " << c.seed << ", "
                  << c.seeds << " training seed(s) " << c.seed + uint64_t(c.first_seed) << ".." << c.seed + uint64_t(c.first_seed + c.seeds - 1) << ", out "
                  << c.out_dir << std::endl;
        // Cheapest-to-most-expensive is not the order: the headline experiments come first,
        // and the cost table is rewritten after each, so a stopped run still leaves results.
        config first = c, rest = c;
        first.experiments.clear();
        rest.experiments.clear();
        for (int e : c.experiments)
            (e == 3 || e == 7 ? rest : first).experiments.insert(e);
        run_recognition(first, std::cout);
        if (c.experiments.count(7) && c.exp7_parts.count("range"))
            run_kinematic_range(c, std::cout); // a shipped classifier under a link budget: seconds
        write_cost(c, std::cout);
        run_delay(c, std::cout);
        write_cost(c, std::cout);
        run_pilot_budget(c, std::cout);
        write_cost(c, std::cout);
        run_tsne(c, std::cout);
        write_cost(c, std::cout);
        run_recognition(rest, std::cout);
        write_cost(c, std::cout);
        run_tracks(c, std::cout);
        run_angle(c, std::cout);
        run_array_classes(c, std::cout);
        run_array_tracks(c, std::cout);
        run_array_mimo(c, std::cout);
        run_array_mimo_budget(c, std::cout);
        std::cout << "[" << now_utc() << "] done" << std::endl;
        return 0;
    } catch (const po::error& e) {
        std::cerr << "sems_eval: " << e.what() << "\n\n" << opts << std::endl;
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "sems_eval: " << e.what() << std::endl;
        return 1;
    }
}
