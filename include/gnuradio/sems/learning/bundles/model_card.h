// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief A model bundle's card (model_card.json beside bundle.json): what the bundle is for,
 *        its measured figures per SNR, how they were measured, its speed and how to retrain it.
 */
#ifndef INCLUDED_SEMS_LEARNING_MODEL_CARD_H
#define INCLUDED_SEMS_LEARNING_MODEL_CARD_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <nlohmann/json.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*!
 * \brief A model bundle's card: the file `model_card.json` in the bundle directory, holding the
 *        fields below (`format` "sems.model_card", `version` 1), grouped as
 *        docs/reference/file_formats.md gives them: `pilots` {n_pilots, mask, mask_origin,
 *        phases (pilot_phases)}, `frame` (a preset's name, or the settings), `retrain`
 *        {command, recorded}, `test`, `speed`.
 * \details sems_train writes it at the end of training (its test split's figures) and
 * `sems_eval --model-card DIR` measures and rewrites it on a fixed test set; scripts/models_catalogue.py
 * builds models/README.md from the shipped bundles' cards. The card refers to bundle.json for
 * what bundle.json records (the training command, the scene, the decoder) instead of copying it.
 * Reading validates every field and names the file and the field of a bad one.
 */
struct SEMS_LEARNING_API model_card {
    static constexpr const char* format_name = "sems.model_card"; ///< the file's `format`
    static constexpr int format_version = 1;                       ///< the file's `version`
    static constexpr const char* card_file = "model_card.json";    ///< its name in the bundle directory

    /*! \brief The figures at one SNR. */
    struct snr_figures {
        double snr_db = 0.0;                          ///< SNR per resource element (dB)
        int frames = 0;                               ///< frames scored (tracks, for a track bundle)
        std::optional<double> accuracy;               ///< classify: share correct (a track bundle: after the whole track)
        std::optional<double> first_frame_accuracy;   ///< a track bundle: share correct after its first frame
        std::optional<double> mae_index;              ///< delay: mean |error| in delay index
        std::optional<double> mae_m;                  ///< delay: the same in metres of range
        std::optional<double> median_abs_error_index; ///< delay: median |error| in delay index
        std::optional<double> rmse_azimuth_rad;       ///< a position bundle: root-mean-square azimuth error
        std::optional<double> crb_azimuth_rad;        ///< a position bundle: the azimuth's Cramér–Rao bound (RMS over the frames)
    };

    /*! \brief How the figures were measured. */
    struct test_record {
        std::string measured_by; ///< "sems_eval --model-card" or "sems_train test split"
        std::string command;     ///< the exact command that measured them
        std::string frames;      ///< how the test frames were drawn, in words
        std::string scene;       ///< the test scene, in words
        uint64_t seed = 0;       ///< the seed the test frames were drawn with
        std::string radio;       ///< the radio file the frames crossed (empty: none)
        int track_frames = 0;    ///< a track bundle: the frames of a test track (0: per-frame figures)
        std::vector<snr_figures> by_snr; ///< one entry per SNR, in the order measured
    };

    /*! \brief The decoder's speed beside an anchor timed in the same run (apps/model_card_speed.h). */
    struct speed_record {
        int threads = 1;          ///< LibTorch threads (the measurement uses one)
        int batch = 32;           ///< frames per inference call (the measurement uses sink_defaults::batch_size)
        double snr_db = 10.0;     ///< SNR of the frames decoded (the delay refinements' cost depends on it)
        int frames = 0;           ///< frames per timing run
        int repeats = 0;          ///< timing runs of each (the fastest counts)
        double decoder_fps = 0.0; ///< frames per CPU-second of the sink's decoder (a track bundle: evidence and one step per frame)
        std::string anchor;       ///< what the anchor is, in words
        double anchor_fps = 0.0;  ///< frames per CPU-second of the anchor in the same run
        /*! \brief The decoder's rate over the anchor's. \return decoder_fps / anchor_fps. */
        double ratio() const { return decoder_fps / anchor_fps; }
    };

    std::string bundle;        ///< the bundle's folder name
    std::string summary;       ///< one line: what the bundle is for
    double cite_snr_db = 10.0; ///< the figure to cite: test.by_snr at this SNR
    task_kind task = task_kind::classify; ///< the bundle's task
    std::string frame_preset;  ///< the frame preset's name (empty when the frame is no preset: see `frame`)
    frame_settings frame;      ///< the frame
    std::string class_library; ///< classify: the class library's name
    std::vector<std::string> classes; ///< classify: the class names, in output order
    int n_pilots = 0;          ///< N_p
    std::string mask;          ///< where the mask came from: "learned", a mask file or "pattern NAME"
    std::string mask_origin;   ///< mask.json's origin kind ("learned", "random subcarriers, one symbol", ...)
    std::string pilot_phases;  ///< "newman", "explicit" (the mask's own phases), or empty for none
    test_record test;          ///< the figures and how they were measured
    speed_record speed;        ///< the decoder's speed
    std::string retrain_command;  ///< the command that trains the bundle again (may be empty: see retrain_recorded)
    std::string retrain_recorded; ///< the key of bundle.json that records the command that trained it

    /*!
     * \brief What the card says about a bundle from its files alone: folder, task, frame,
     *        classes, pilots and the retrain commands (no figures, no speed).
     * \param b the bundle (directory set). \return the card.
     */
    static model_card of_bundle(const model_bundle& b);
    /*!
     * \brief A one-line summary made from the bundle's record (what sems_train writes).
     * \param b the bundle. \return e.g. "classify pedestrian, car, drone (class library paper) from 32 pilots".
     */
    static std::string default_summary(const model_bundle& b);
    /*!
     * \brief The figures to cite.
     * \return test.by_snr's entry at cite_snr_db.
     * \throws std::invalid_argument when there is none.
     */
    const snr_figures& cited() const;
    /*! \brief model_card.json's content. \return the JSON object. */
    nlohmann::json to_json() const;
    /*!
     * \brief Reads a card's JSON.
     * \param j the JSON. \param source names the file in errors.
     * \return the card.
     * \throws std::invalid_argument naming `source`, the field and the problem.
     */
    static model_card from_json(const nlohmann::json& j, const std::string& source);
    /*!
     * \brief Reads dir/model_card.json (or the file itself).
     * \param path a bundle directory or a card file. \return the card.
     * \throws std::invalid_argument naming the file and the problem.
     */
    static model_card load(const std::string& path);
    /*!
     * \brief Writes dir/model_card.json.
     * \param dir the bundle directory. \throws std::invalid_argument naming the file.
     */
    void save(const std::string& dir) const;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_MODEL_CARD_H */
