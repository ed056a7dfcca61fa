// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Training a position bundle (docs/reference/arrays.md, "The learned position decoder"):
 *        the angle network over an array's pilots, on a trained delay bundle.
 *
 * \details Torch-free header (the training app and the bindings call it). The delay bundle
 * gives the frame, the mask and the delay decoder (kept as it is: it reads the pilots beamformed
 * towards the angle). The array (a preset's name or a file) receives the scene; frames are drawn
 * from (seed, frame index) by the channel model with that array, split 8:1:1, and kept as their
 * pilots only (N_r·N_p values per frame). Each epoch draws new noise (one SNR per frame, uniform
 * in [snr_min_db, snr_max_db]); the angle network trains on the cross-entropy of the grid point
 * nearest the truth plus the error of its soft-argmax in grid steps (Adam, cosine schedule); the
 * best validation epoch is kept. The bundle is then written (out_dir, or a scratch folder) and
 * loaded back, and its test frames are scored at each eval SNR by position_estimator itself:
 * the azimuth RMSE with and without the polish, beamforming's on the same frames, the
 * root-mean-square Cramér–Rao bound (written only when every test frame's target is one path),
 * and the delay's mean absolute error from the beamformed pilots and from one element's.
 */
#ifndef INCLUDED_SEMS_LEARNING_POSITION_TRAINER_H
#define INCLUDED_SEMS_LEARNING_POSITION_TRAINER_H

#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief Everything train_position() needs. */
struct SEMS_LEARNING_API position_training_settings {
    std::string delay_bundle = "delay_single"; ///< the delay bundle (a name or directory): frame, mask, delay decoder
    std::string array = "ula8_3g";              ///< the array: a preset's name or an array file (one transmit element)
    std::optional<scene> scene_spec;            ///< the scene the array receives; empty: default_scene()
    std::string scene_source = "the default position scene"; ///< names the scene in errors and bundle.json
    int frames = 20000;        ///< frames drawn, split 8:1:1
    int epochs = 15;           ///< epochs
    int batch = 256;           ///< frames per step
    double lr = 3e-3;          ///< Adam's learning rate (cosine schedule towards lr/50)
    int patience = 4;          ///< early stop after this many epochs without a better validation
    double snr_min_db = -10.0; ///< training SNR range (one SNR per frame): lower end in dB
    double snr_max_db = 30.0;  ///< its upper end
    double ce_weight = 1.0;    ///< weight of the grid cross-entropy beside the soft-argmax error
    uint64_t seed = 1;         ///< seed of the frames, the noise and the weights
    int threads = 0;           ///< <= 0: leave LibTorch's default
    std::vector<double> eval_snr_db{ -10.0, -5.0, 0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0 }; ///< test SNR points in dB
    nn::angle_settings angle;  ///< the angle network
    std::string out_dir;       ///< where the bundle goes (empty: a scratch folder, removed)
    std::string command_line;  ///< recorded in bundle.json
    bool verbose = true;       ///< per-epoch progress on the log

    /*!
     * \brief The default scene: one target of the paper's classes per frame, one unfaded path
     *        (the deterministic amplitude the angle bound assumes), its azimuth uniform on
     *        [−0.8, 0.8] rad.
     * \return the scene (without an array: the trainer adds it).
     */
    static scene default_scene();
    /*! \brief Checks every setting. \throws std::invalid_argument naming the setting. */
    void validate() const;
    /*! \brief What bundle.json records under `position.training`. \return the JSON object. */
    nlohmann::json to_json() const;
};

/*! \brief What train_position() returns. */
struct SEMS_LEARNING_API position_training_result {
    model_bundle bundle;     ///< the position bundle (directory set when written to out_dir)
    nlohmann::json history;  ///< one object per epoch
    nlohmann::json metrics;  ///< the test figures per SNR (bundle.json's `position.metrics`)
    double seconds = 0.0;    ///< wall time
};

/*!
 * \brief Trains the angle network, scores the bundle on the test split and writes it.
 * \param settings the settings (validated first).
 * \param log where progress goes (nullptr: silent).
 * \return the bundle, history and test figures.
 * \throws std::invalid_argument naming a bad setting or file.
 */
SEMS_LEARNING_API position_training_result train_position(const position_training_settings& settings,
                                                          std::ostream* log);

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_POSITION_TRAINER_H */
