// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Joint training of the pilot mask and a task decoder (docs/design.md §5).
 *
 * \details Torch-free header: the training app, the evaluation and the Python bindings call
 * train() with a settings struct. Data come from gr::sems::channel_model::generate
 * (the emulator's own model): noiseless H per frame, split 8:1:1 into train /
 * validation / test; noise CN(0, channel_model::noise_variance(snr)) is drawn fresh
 * per training batch (per-frame SNR uniform in [snr_min, snr_max] dB) and once, from
 * its own seeded generator, for the validation and test frames.
 *
 * Phases:
 *  1. learned mask (no mask_file): the semantic encoder and the objective's decoder
 *     (objective "task": the task decoder; "mse": the channel-reconstruction decoder)
 *     train together; one Gumbel straight-through mask per batch; temperature
 *     annealed per epoch down to its floor; validation on the final (greedy,
 *     distinct) mask. It ends after `epochs`, or once the mask has stayed the same for
 *     `mask_settle_epochs` epochs (or an early stop): the epochs left go to phase 2.
 *  2. decoder on the fixed final mask (or on mask_file): the task decoder is trained
 *     (objective "task": fine-tuned; "mse": trained from scratch, the paper's
 *     reconstruction-DL baseline) with a cosine learning-rate schedule; the best
 *     validation epoch is kept; early stop after `patience` epochs without improvement.
 * Then the test frames are scored at the training SNR range and at each eval_snr_db.
 *
 * The same settings and seed give the same mask, weights and metrics (seeded data,
 * torch::manual_seed, fixed thread count).
 */
#ifndef INCLUDED_SEMS_LEARNING_TRAINER_H
#define INCLUDED_SEMS_LEARNING_TRAINER_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/radio/front_end.h>
#include <gnuradio/sems/learning/distributed/distributed_settings.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief Everything train() needs; the defaults are the paper's settings. */
struct SEMS_LEARNING_API training_settings {
    task_kind task = task_kind::classify; ///< the decoder's task
    std::string objective = "task"; ///< "task" (SemS) or "mse" (reconstruction baseline)
    int n_pilots = 32;               ///< N_p
    std::string mask_file;          ///< empty: learn the mask; else train the decoder on it
    std::string mask_pattern;       ///< or a standard pattern (uniform|random|doppler|staggered|burst; random seeded by seed)
    /*!
     * \brief The pilots' energies: "equal" (every pilot the same) or "learned".
     * \details "learned" (a learned mask only): the semantic encoder also learns one power
     * logit per resource element; the selected pilots' energies are
     * p = f + (1 - f)·N_p·softmax(their logits), f = pilot_power_floor, so the total pilot
     * energy stays that of equal power and no pilot falls below f. Pilot k's training and
     * test noise is σ/sqrt(p_k); the bundle's mask carries the energies (mean 1). A mask
     * file with its own `power` list is trained on with those energies whatever this says.
     */
    std::string pilot_power = "equal";
    double pilot_power_floor = 0.1; ///< "learned": the smallest energy of a pilot, f in [0, 1)
    /*!
     * \brief The pilots' phases in the bundle's mask: empty (as the mask has them: a mask
     *        file's own phases, none for a learned or pattern mask), "zero" (none) or "newman"
     *        (pilot_mask::newman_phases() on each symbol's pilots).
     * \details A phase changes what is sent, not what a decoder sees: the observation
     * Y/(sqrt(p_k)·s_p·exp(jφ_k)) is H plus noise of the same law, so the training is the
     * same whatever the phases. Newman phases keep a symbol of many pilots from peaking at
     * sqrt(K) times its rms in the time domain, where a radio's converter would clip it.
     */
    std::string pilot_phases;
    frame_settings frame;            ///< the frame
    std::optional<scene> scene_spec; ///< empty: random scene, all classes, single path
    std::string scene_source = "default random scene"; ///< names the scene in errors and bundle.json

    /*!
     * \brief The radio front end the observations cross (core/radio/front_end_frame.h): empty = the
     *        ideal radio, H + noise. A radio draws every frame's observation through its
     *        leakage, oscillators, IQ imbalance, DC and converter (and the canceller), at each
     *        batch's SNR, for training, validation and the test metrics alike.
     */
    std::optional<front_end_settings> radio;
    std::string radio_source = "ideal radio"; ///< names the radio in the log and bundle.json
    double snr_min_db = 10.0;        ///< training SNR range: lower end in dB
    double snr_max_db = 10.0;        ///< training SNR range: upper end in dB
    int frames = 30000;              ///< split 8:1:1
    int epochs = 20;                 ///< phase 1 (learned mask) or the decoder epochs (fixed mask)
    int decoder_epochs = 10;         ///< phase 2 after a learned mask
    int batch = 256;                 ///< global batch: each of the world's ranks trains on batch / world_size
    double lr = 0.01;                ///< Adam
    double lr_final_scale = 0.02;    ///< cosine schedule of phase 2 ends at lr * this
    int patience = 4;                ///< early stop (phase 2, and phase 1 once at the temperature floor)
    /*!
     * \brief Phase 1 ends once the learned mask has stayed the same for this many epochs
     * (0 = never). The mask epochs it leaves, and those an early stop leaves, go to phase 2:
     * the budget epochs + decoder_epochs holds, and a mask found early gets a decoder trained
     * on it for longer (a hand pattern gets every epoch on its mask).
     */
    int mask_settle_epochs = 2;
    int threads = 0;                 ///< <= 0: leave LibTorch's default
    /*!
     * \brief Where the training frames live: "hold" (in memory, 8·N·M bytes a frame),
     *        "stream" (each batch's frames computed again from their drawn paths) or "auto".
     * \details Streamed frames are the held ones bit for bit (the channel model's factors are
     * a function of a frame's drawn paths), so the bundle is the same either way; streaming
     * costs the emulator's time on every training frame of every epoch and holds only the
     * paths. "auto" streams when the training frames would take more than a quarter of the
     * machine's physical memory: the validation and test frames (a fifth of `frames`) are
     * held either way, and a large frame's batches take gigabytes of their own.
     */
    std::string training_data = "auto";
    uint64_t seed = 1;               ///< seed of data, noise, mask draws and torch::manual_seed
    std::vector<double> eval_snr_db{ 0.0, 10.0, 20.0, 30.0 }; ///< test SNR points in dB
    int eval_frames = 0;             ///< test frames scored per SNR point; 0 = the whole test split

    /*! \brief Delay dictionary: grid spacing in delay indices (the grid range comes from the data). */
    double delay_spacing = 0.125;
    double delay_margin = 2.0;       ///< delay dictionary: margin around the training frames' delays (delay indices)
    double delay_ce_weight = 1.0;    ///< cross-entropy on the dictionary scores (finds the peak)
    double delay_ce_weight_final = 0.05; ///< phase 2 ends on (almost) pure L1

    nn::encoder_settings encoder;               ///< the semantic encoder (learned mask)
    nn::classifier_settings classifier;         ///< the classifier decoder
    nn::delay_settings delay;                   ///< the delay decoder
    nn::reconstruction_settings reconstruction; ///< the reconstruction decoder (objective "mse")

    /*!
     * \brief One rank of a distributed run (docs/reference/distributed_training.md); default: alone.
     * \details Each rank draws its own share of `frames` (seeded by rank), its own noise and
     * Gumbel samples; gradients and validation/test sums are all-reduced; rank 0 writes.
     */
    distributed_settings distributed;

    std::string out_dir;             ///< empty: do not write a bundle
    std::string command_line;        ///< recorded in bundle.json
    bool verbose = true;             ///< per-epoch progress on the log

    /*! \brief Checks every setting. \throws std::invalid_argument naming the setting. */
    void validate() const;
    /*! \brief What bundle.json records under "training". \return the JSON object. */
    nlohmann::json to_json() const;
    /*!
     * \brief The settings a bundle was trained with, from its bundle.json, to train it again.
     * \details The training record gives the objective, sizes, SNR range, schedule, seed,
     * scene and encoder; the decoder's settings come from bundle.json's `decoder.settings`
     * (keys a bundle predates take the values it was trained with, as when it is loaded);
     * the frame from `frame`. A record without `mask_settle_epochs` predates that rule (0).
     * A bundle trained on a given mask is retrained on its own mask file. Same settings and
     * seed give the same mask and weights (the class documentation above). out_dir,
     * command_line and the distributed settings are left for the caller.
     * \param b the loaded bundle.
     * \return the settings, validated.
     * \throws std::invalid_argument naming bundle.json and the missing or bad key.
     */
    static training_settings from_bundle(const model_bundle& b);
};

/*! \brief What train() returns: the bundle, the history and the scored test frames. */
struct SEMS_LEARNING_API training_result {
    model_bundle bundle;             ///< directory set when written
    nlohmann::json history;          ///< one object per epoch
    double seconds = 0.0;            ///< wall time of the training

    /*!
     * \brief The number of test frames at the training SNR range, as the app scored them.
     * \details test_obs and the test_* answers let a loaded bundle be checked against the
     * trainer's own answers.
     */
    int n_test = 0;
    std::vector<gr_complex> test_obs;    ///< observations, n_test x N_p, mask order
    std::vector<float> test_probs;       ///< classify: n_test x C
    std::vector<int> test_labels;        ///< classify: label index into class_names
    std::vector<double> test_delay_index; ///< delay: estimates
    std::vector<double> test_truth_index; ///< delay: truth
};

/*!
 * \brief Trains, scores on the test split and (if out_dir is set) writes the bundle.
 * \param settings the settings (validated first).
 * \param log where progress goes (nullptr: silent).
 * \return the bundle, history and test answers.
 * \throws std::invalid_argument naming a bad setting or file.
 */
SEMS_LEARNING_API training_result train(const training_settings& settings, std::ostream* log);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_TRAINER_H */
