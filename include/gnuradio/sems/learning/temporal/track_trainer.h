// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Training a decision over a track (docs/design.md §5): the temporal model over a
 *        trained per-frame classifier bundle, on tracks drawn from (seed, track index).
 *
 * \details Torch-free header (the training app and the bindings call it). The frame bundle
 * gives the mask, the frame decoder (kept as it is) and the classes; the scene gives the
 * tracks (random_spec::tracks; by default the frame bundle's own training scene followed
 * over tracks of `track_frames` frames with gains new every frame). Tracks 0 .. 0.8·tracks−1
 * train, the next tenth validates, the last tenth tests, each drawn alone from its index
 * (channel_model::begin_track), so no track depends on the ones before it and the data are
 * the track's pilots only (N_p values per frame, never the whole frames). Each epoch draws
 * new noise (a track keeps one SNR, uniform in [snr_min_db, snr_max_db]) and runs the frame
 * decoder once over every frame; the temporal model trains on the cross-entropy of its
 * decision after every frame (weighted towards a track's end with loss_ramp > 0). The best validation epoch is kept. With super_frames F > 1 the
 * pilots come first: F sets learned with the frame decoder (super_frame_learner), frame t of
 * track j read at set (j + t) mod F. The test tracks are scored at
 * each eval SNR after each number of frames in eval_frames, for the temporal model and for
 * the fusion of independent frames (the product of per-frame posteriors), on the same frames.
 */
#ifndef INCLUDED_SEMS_LEARNING_TRACK_TRAINER_H
#define INCLUDED_SEMS_LEARNING_TRACK_TRAINER_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/temporal/temporal_settings.h>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief Everything train_track() needs. */
struct SEMS_LEARNING_API track_training_settings {
    std::string frame_bundle;        ///< the per-frame classifier bundle (a name or directory)
    std::optional<scene> scene_spec; ///< a scene with random.tracks; empty: the frame bundle's training scene, tracked
    std::string scene_source = "the frame bundle's training scene"; ///< names the scene in errors and bundle.json
    int track_frames = 32;           ///< K: frames of a training track (longer scene tracks are cut to K)
    int tracks = 4000;               ///< tracks drawn, split 8:1:1
    double snr_min_db = -10.0;       ///< training SNR range (one SNR per track): lower end in dB
    double snr_max_db = 30.0;        ///< its upper end
    int epochs = 12;                 ///< epochs of the temporal model
    int batch = 64;                  ///< tracks per step
    double lr = 3e-3;                ///< AdamW's rate for kind gru_fusion
    double acf_tcn_lr = 1e-3;        ///< AdamW's rate for kind acf_tcn (lr is gru_fusion's)
    double weight_decay = 1e-3;      ///< AdamW's decoupled weight decay (0 = none)
    int patience = 4;                ///< early stop after this many epochs without a better validation
    uint64_t seed = 1;               ///< seed of the tracks, the noise and the weights
    int threads = 0;                 ///< <= 0: leave LibTorch's default
    std::vector<double> eval_snr_db{ -10.0, 0.0, 10.0, 20.0, 30.0 }; ///< test SNR points in dB
    std::vector<int> eval_frames{ 1, 2, 4, 8, 16, 32 };             ///< observation times scored, in frames
    nn::temporal_settings temporal;  ///< the temporal model
    /*!
     * \brief How the loss weighs the decision after t frames of a track of K: by (t/K)^loss_ramp
     *        (0: every decision alike, the plain mean; 1: in proportion to the frames seen, so
     *        the decisions a long track makes count more than its first guesses).
     */
    double loss_ramp = 0.0;
    /*!
     * \brief F, the frames of a super-frame mask: 1 keeps the frame bundle's mask and decoder;
     *        F > 1 first learns F sets of the frame bundle's N_p pilots, one per frame of the
     *        super-frame, jointly with the frame decoder (trained on from the frame bundle's
     *        weights) under the fused cross-entropy over frames (docs/design.md §5), then the
     *        temporal model on them. Needs out_dir (the learned sets and decoder are written there).
     */
    int super_frames = 1;
    int mask_epochs = 8;          ///< F > 1: epochs of the super-frame learner
    int mask_tracks = 1600;       ///< F > 1: training tracks it learns on, windows of min(2F, track_frames) frames (8·N·M bytes a frame)
    double mask_lr = 3e-4;        ///< F > 1: Adam's rate for the frame decoder
    double mask_encoder_lr = 0.3; ///< F > 1: Adam's rate for the sets' scores (they must sharpen within a few epochs)
    /*!
     * \brief F > 1: where the sets start: "frame" (every set at the frame bundle's mask, the
     *        repeated mask, kept unless an epoch validates better) or "random" (scores zero:
     *        uniformly random sets, as the frame trainer's encoder starts).
     */
    std::string mask_start = "frame";
    std::string out_dir;             ///< empty: do not write a bundle
    std::string command_line;        ///< recorded in bundle.json
    bool verbose = true;             ///< per-epoch progress on the log

    /*! \brief Checks every setting. \throws std::invalid_argument naming the setting. */
    void validate() const;
    /*! \brief What bundle.json records under track.training. \return the JSON object. */
    nlohmann::json to_json() const;
};

/*! \brief What train_track() returns. */
struct SEMS_LEARNING_API track_training_result {
    model_bundle bundle;    ///< the track bundle (directory set when written)
    nlohmann::json history; ///< one object per epoch
    nlohmann::json metrics; ///< the test scores (bundle.json's track.metrics)
    double seconds = 0.0;   ///< wall time
};

/*!
 * \brief Trains the temporal model, scores the test tracks and (if out_dir is set) writes the
 *        track bundle: the frame bundle's files and a `track` record with temporal.pt.
 * \param settings the settings (validated first). \param log where progress goes (nullptr: silent).
 * \return the bundle, history and test scores.
 * \throws std::invalid_argument naming a bad setting, the scene or the bundle.
 */
SEMS_LEARNING_API track_training_result train_track(const track_training_settings& settings, std::ostream* log);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_TRACK_TRAINER_H */
