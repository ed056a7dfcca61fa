// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval: shared pieces of the evaluation app (configuration, the common test
 * frames, CSV output, metrics, and training-or-reusing the decoders). */
#ifndef SEMS_EVAL_EVAL_H
#define SEMS_EVAL_EVAL_H

#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sems/learning/training/trainer.h>
#include <nlohmann/json.hpp>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace gr {
namespace sems {
class bundle_decoder; // gnuradio/sems/learning/bundles/bundle_decoder.h
}
} // namespace gr

namespace sems_eval {

using namespace gr::sems;

struct config {
    std::string size = "test";
    std::string out_dir;
    uint64_t seed = 2026;         // test frames: seed + a per-scene constant; training: see training_seeds
    int seeds = 1;                // training seeds per learned method: seed + first_seed, ..., seed + first_seed + seeds - 1
    int first_seed = 0;           // the first of them is seed + first_seed (one seed per process shares a run)
    int threads = 2;
    int test_frames = 60;         // per operating point (the same frames at every SNR)
    int train_frames = 600;       // DL training frames (the trainer splits 8:1:1)
    int epochs = 2;               // mask-learning epochs (a fixed mask trains epochs + decoder_epochs)
    int decoder_epochs = 1;       // decoder epochs after a learned mask
    int classifier_epochs = 2;    // mask-learning epochs of the classification networks (experiments 1-3, 7 and 8)
    int patience = 3;
    int batch = 64;
    int svm_train_frames = 300;
    int tsne_frames = 60;
    double tsne_snr_db = 10.0;
    double train_snr_min_db = -10.0, train_snr_max_db = 30.0;
    double delay_train_snr_min_db = -10.0, delay_train_snr_max_db = 30.0;
    std::vector<double> snrs{ -10, 0, 10, 20, 30 };
    std::vector<double> delay_snrs{ -10, 0, 10, 20, 30 };
    std::vector<int> np_sweep{ 2, 8, 32 };
    int multipath_paths = 3;
    double clutter_csr_db = 10.0;
    std::string class_library = "paper"; // experiments 1-3: the recognition scenes' class library (name or file)
    std::string exp7_class_library = "kinematic"; // experiments 7 and 8: targets of moving scatterers (name or file)
    std::vector<int> exp7_np_sweep{ 8 };          // experiment 7's pilot budgets besides its 32
    std::vector<int> exp7_power_np{ 32 };        // experiment 7: N_p of SemS with learned pilot energies
    std::vector<int> exp7_bank_np{ 8 };          // experiment 7: N_p of the bank part (SemS and the Doppler
                                                 // pattern, each with a template bank)
    std::vector<int> exp7_burst_np{ 8 };         // experiment 7: N_p of the burst pattern (below N: else the Doppler one)
    std::set<std::string> exp7_parts{ "main", "budget", "power", "bank", "burst" }; // one per process lets cores share a run
                                                 // ("range" only when named)
    std::string exp7_range_bundle, exp7_range_scene; // experiment 7, range part: a classifier and a link-budget scene
    int exp7_range_frames = 0;                    // experiment 7, range part: frames (0: 10 x test_frames)
    double exp7_range_margin_db = 0.0;            // experiment 7, range part: the emulator's SNR setting (0: the budget's noise)
    double confusion_snr_db = 10.0;               // experiment 7's confusion matrices
    int exp8_test_tracks = 12;                    // experiment 8: test tracks (every method, every SNR)
    int exp8_track_frames = 8;                    // experiment 8: K, frames of a track (test and training)
    std::vector<int> exp8_frames{ 1, 2, 4, 8 };   // experiment 8: observation times scored, in frames (<= K)
    int exp8_train_tracks = 40;                   // experiment 8: tracks of each temporal decoder (split 8:1:1)
                                                  // and of the spectrogram CNN (9:1)
    int exp8_track_epochs = 1;                    // experiment 8: epochs of each temporal decoder
    int exp8_cnn_epochs = 1;                      // experiment 8: epochs of the spectrogram CNN
    int exp8_svm_tracks = 12;                     // experiment 8: training tracks of the SVM over the track
    std::vector<int> exp8_np_sweep{ 8 };          // experiment 8's pilot budgets besides 32 (budget part)
    std::set<std::string> exp8_parts{ "main", "budget" }; // "superframe" only when named
    int exp8_super_frames = 4;                    // experiment 8, superframe part: F of the learned super-frame masks
    std::string exp8_super_frame_start = "frame"; // experiment 8, superframe part: where its sets start (frame | random)
    int exp9_elements = 8;                        // experiment 9 (angle): the ULA's elements
    int exp9_np = 32;                             // experiment 9: pilots per element
    int exp9_frames = 40;                         // experiment 9: test frames per SNR (one and two targets)
    std::vector<double> exp9_snrs{ -10, 0, 10, 20, 30 }; // experiment 9's SNR points
    std::string exp9_position_bundle; // experiment 9: a position bundle scored on the same frames (its mask and array)
    std::set<std::string> exp9_parts{ "angle", "classes", "tracks" }; // experiment 9's parts (one per process lets cores share a run)
    std::vector<std::string> exp9_classifier_bundles{ "classifier_kinematic" }; // experiment 9, classes: one per training seed
    std::vector<int> exp9_class_elements{ 1, 4, 8 };          // experiment 9, classes and tracks: the ULAs' element counts
    std::string exp9_track_bundle = "classifier_kinematic_track"; // experiment 9, tracks: the track bundle
    int exp9_track_count = 12;                                // experiment 9, tracks: test tracks
    int exp9_track_frames = 8;                                // experiment 9, tracks: planned frames of a track
    std::string exp9_mimo_array = "mimo2x4_3g";               // experiment 9, mimo: the MIMO array
    int exp9_mimo_seeds = 3;                                  // experiment 9, mimo: learned masks (seeds)
    int exp9_mimo_epochs = 2;                                 // experiment 9, mimo: the learner's epochs (full 40)
    int exp9_mimo_steps = 2;                                  // experiment 9, mimo: its steps per epoch (full 25)
    int exp9_mimo_draws = 8;                                  // experiment 9, mimo: its azimuths per step (full 64)
    int exp9_mimo_azimuths = 41;                              // experiment 9, mimo: the bound's azimuth grid (full 161)
    std::vector<int> exp9_mimo_budget{ 4, 8 };                // experiment 9, mimo_budget: pilot counts (full 4, 8, 16)
    int classic_oversample = 16;
    std::set<int> experiments{ 1, 2, 3, 4, 5, 6 };
    std::string shipped_classifier, shipped_delay_single, shipped_delay_multi;
    std::string shipped_track; // experiment 8: a shipped track bundle scored beside the methods trained here
    bool reuse_bundles = false; // load any cached bundle without comparing settings (timing re-runs)
    bool only_shipped = false; // evaluate only the shipped bundles (rows to add to a full run)
    bool exp1_any_heading = true;   // experiment 1 also on the "any" heading scene
    bool exp1_hand_patterns = true; // experiment 1: the SemS decoder also on Doppler/uniform/random pilots
    std::set<std::string> delay_scenarios{ "single", "multipath" }; // experiment 4's scenes (one per process
                                                                    // lets two cores share a full run)
    frame_settings fs;
    std::string command_line;
    // --model-card: measure and write these bundles' model cards (model_cards.cc), nothing else.
    std::vector<std::string> model_cards;
    int card_frames = 2000;            // test frames per SNR (the demo's)
    int card_tracks = 1000;            // test tracks of a track bundle
    int card_track_frames = 0;         // frames of a test track (0: the track bundle's training length)
    std::vector<double> card_snrs{ 0, 10, 20, 30 }; // the demo's SNRs
    uint64_t card_seed = 1;            // the demo's: classifiers seed 1, delay bundles seed + 1
    int card_speed_frames = 2048;      // frames per timing run of the speed record
    int card_speed_repeats = 5;        // timing runs (the fastest counts)
    std::string card_summary;          // replaces the card's summary when given
    double card_cite_snr_db = std::numeric_limits<double>::quiet_NaN(); // replaces the SNR to cite when given
};

// Wall-clock stamps for progress lines.
std::string now_utc();
double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b);

// The test frames of one scene: noiseless H and unit-variance noise W, drawn once, so
// Y = H + σ·W gives exactly the same frames (and noise shape) at every SNR.
struct test_set {
    frame_settings fs;
    int count = 0;
    std::vector<gr_complex> h; // count x N x M
    std::vector<gr_complex> w; // count x N x M, CN(0, 1)
    std::vector<frame_truth> truth;

    // count x N_p observations at the mask positions (mask order) at snr_db (+inf: noiseless).
    std::vector<gr_complex> observe(const pilot_mask& mask, double snr_db) const;
};
test_set make_test_set(const frame_settings& fs, const scene& sc, int count, uint64_t seed);

// Frames for training the feature SVM: per-frame SNR uniform in [lo, hi] dB.
struct train_set {
    std::vector<gr_complex> y; // count x N x M, noisy
    std::vector<gr_complex> h; // count x N x M, noiseless
    std::vector<frame_truth> truth;
};
train_set make_train_set(const frame_settings& fs, const scene& sc, int count, uint64_t seed, double lo, double hi);
// count x N_p pilots of the mask from noisy grids. Pilot k's noise is scaled by
// mask.noise_scale(k): a mask whose pilots differ in energy needs the noiseless grids `clean`.
std::vector<gr_complex> gather(const std::vector<gr_complex>& grids, int count, const frame_settings& fs,
                               const pilot_mask& mask, const std::vector<gr_complex>* clean = nullptr);

// A drawn frame's noiseless pilots at every stream of the model's array (one without an array):
// K·N_p values, element-major as the pilot extractor gives them, at the grid positions `flat`
// (pilot_mask::flat_indices()). `h` is a scratch grid of N·M values.
std::vector<gr_complex> array_pilots(const channel_model& cm, const frame_realization& r, uint64_t first_symbol,
                                     const std::vector<int>& flat, std::vector<gr_complex>& h);

// Scenes of the experiments.
// default | any | no_md | clutter (c.class_library) | kinematic (c.exp7_class_library, any heading)
scene recognition_scene(const std::string& scenario, const config& c);
scene delay_scene(int paths);
// Experiment 9's classes and tracks scenes: the bundle's classes of its library (the paper's
// without one; every class of it, as drawn without a list, when the bundle has them all; a track
// bundle's, those its track record was trained on when fewer: a pair's track decoder), any
// heading, one path, Rayleigh, azimuth uniform on [−0.8, 0.8] rad; on tracks when `tracks` is
// given.
scene array_test_scene(const model_bundle& bundle, std::optional<track_draw_spec> tracks = std::nullopt);
// The class names of a scene's library, by class id.
std::vector<std::string> class_names(const scene& sc);

// Accuracy and macro-F1 (unweighted mean of per-class F1 over the classes present).
struct class_score {
    double accuracy = 0.0, macro_f1 = 0.0;
};
class_score score(const std::vector<int>& predicted, const std::vector<int>& truth, int n_classes);

// One CSV per experiment; values are written as given.
class csv_file
{
public:
    csv_file(const std::string& path, const std::vector<std::string>& header);
    void row(const std::vector<std::string>& values);
    const std::string& path() const { return d_path; }

private:
    std::string d_path;
    size_t d_cols;
    std::ofstream d_out;
};
std::string num(double v, int precision = 6);

// Cost rows gathered from every experiment (experiment 6).
struct cost_row {
    std::string experiment, scenario, method;
    std::string mask; // a method's pilots (some methods run on several)
    uint64_t test_seed;
    std::string train_seed; // the training seed, or "none" (see train_seed_label)
    int n_pilots;
    double snr_db;
    std::string metric;
    double value;
    double us_per_frame;
    int n_frames;
    double train_seconds;
};
std::vector<cost_row>& cost_rows();

// A decoder bundle: trained here (cached under <out>/bundles/<name> and reused when the
// settings match), or a shipped bundle given on the command line.
struct decoder_source {
    model_bundle bundle;
    double train_seconds = 0.0;
    std::string origin; // "trained", "cached", or the shipped path
};
decoder_source train_or_load(const config& c, const std::string& name, training_settings s, std::ostream& log);
// The trainer's settings for one learned method trained with train_seed (one of training_seeds(c)).
training_settings base_training(const config& c, task_kind task, const scene& sc, const std::string& scene_source,
                                uint64_t train_seed);
// The SemS decoder on a fixed hand pattern (doppler, uniform, random) at the learned mask's
// budget (its mask and decoder epochs together), from the SemS settings. Experiments 1 and
// 2 share these bundles (one cache name, one set of settings).
training_settings hand_pattern_training(training_settings sems, const std::string& pattern);

// Every learned method is trained once per seed c.seed + c.first_seed, ..., c.seed + c.first_seed + c.seeds - 1 on the same
// test frames (drawn from c.seed + a constant), so the spread over seeds is the training's alone.
std::vector<uint64_t> training_seeds(const config& c);
// The cache name of a bundle trained with train_seed: <name>_s<seed> (one bundle per seed).
std::string seeded_name(const std::string& name, uint64_t train_seed);
// The CSVs' train_seed value: the seed, or "none" for a method without training.
std::string train_seed_label(std::optional<uint64_t> train_seed);
// <dir>/eval_key.json as written beside a cached bundle (the settings it was trained with and
// its training time), or an empty object when it is missing or unreadable.
nlohmann::json read_eval_key(const std::string& dir);
// Runs a classifier on count x N_p observations in batches of 256 (after a warm-up, so
// us_per_frame is the steady cost); returns the class ids (ids: the scene's id of each output).
std::vector<int> classify_all(const bundle_decoder& dec, const std::vector<gr_complex>& obs, int count,
                              const std::vector<int>& ids, double& us_per_frame);
// Class ids (in the scene's library) of a classifier bundle's outputs; a bundle trained on
// another class library is refused with the reason (model_bundle::check_library).
std::vector<int> output_classes(const model_bundle& b, const scene& sc);
// Writes a mask file under <out>/masks and returns its path.
std::string write_mask(const config& c, const pilot_mask& mask, const std::string& name);
pilot_mask full_grid_mask(const frame_settings& fs);

// Experiments.
void run_recognition(const config& c, std::ostream& log);   // 1, 3 and 7
void run_tsne(const config& c, std::ostream& log);          // 2
void run_delay(const config& c, std::ostream& log);         // 4
void run_pilot_budget(const config& c, std::ostream& log);  // 5
void write_cost(const config& c, std::ostream& log);        // 6
void run_tracks(const config& c, std::ostream& log);        // 8
void run_angle(const config& c, std::ostream& log);         // 9 (angle part)
void run_array_classes(const config& c, std::ostream& log); // 9 (classes part)
void run_array_tracks(const config& c, std::ostream& log);  // 9 (tracks part)
void run_array_mimo(const config& c, std::ostream& log);    // 9 (mimo part)
void run_array_mimo_budget(const config& c, std::ostream& log); // 9 (mimo_budget part)
void run_kinematic_range(const config& c, std::ostream& log); // 7, range part
void run_model_cards(const config& c, std::ostream& log);     // --model-card

} // namespace sems_eval

#endif
