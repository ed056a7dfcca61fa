// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief A trained model bundle (docs/design.md §4).
 */
#ifndef INCLUDED_SEMS_LEARNING_MODEL_BUNDLE_H
#define INCLUDED_SEMS_LEARNING_MODEL_BUNDLE_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/core/scene/class_library.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/frame/super_frame_mask.h>
#include <nlohmann/json.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gr {
namespace sems {

/*! \brief The task a bundle's decoder answers: the target's class, or its delay. */
enum class task_kind { classify, delay };
/*! \brief The task's name. \param t the task. \return "classify" or "delay". */
SEMS_LEARNING_API std::string task_name(task_kind t);
/*!
 * \brief The task of a name.
 * \param name "classify" or "delay".
 * \return the task.
 * \throws std::invalid_argument on another name.
 */
SEMS_LEARNING_API task_kind task_from_name(const std::string& name);

/*!
 * \brief A trained model bundle (docs/design.md §4): a directory with mask.json, the network
 *        weights and bundle.json.
 * \details bundle.json records the task, the class names, the decoder architecture and
 * settings, the frame settings, how the bundle was trained and its measured metrics.
 * Loading validates everything and names the file and the problem.
 */
struct SEMS_LEARNING_API model_bundle {
    static constexpr const char* format_name = "sems.model_bundle"; ///< bundle.json's `format`
    static constexpr int format_version = 1;                        ///< bundle.json's `version`
    static constexpr const char* bundle_file = "bundle.json";       ///< the bundle's description
    static constexpr const char* mask_file = "mask.json";           ///< the default pilot mask file name
    static constexpr const char* weights_file = "decoder.pt";       ///< the default decoder weights file name

    std::string directory;                ///< where it was loaded from or saved to
    task_kind task = task_kind::classify; ///< the decoder's task
    std::vector<std::string> class_names; ///< classify only
    /*!
     * \brief Classify only: the class library it was trained on (bundle.json's
     *        `class_library`, the library's full JSON; absent: the paper's table).
     */
    std::shared_ptr<const class_library> library;
    frame_settings frame;                 ///< the frame it was trained on
    pilot_mask mask{ 1, 1, { { 0, 0 } } }; ///< the pilot mask (of frame 0 when the mask spans a super-frame)
    /*!
     * \brief A mask spanning a super-frame of F > 1 frames (mask.json a super-frame file): set
     *        f mod F serves a stream's frame f, and `mask` is its set 0. Empty for one frame's mask.
     */
    std::optional<super_frame_mask> super_frame;
    /*! \brief F. \return the frames the bundle's mask spans (1 without a super-frame). */
    int super_frames() const { return super_frame ? super_frame->n_frames() : 1; }
    /*! \brief The pilots of set f. \param f in [0, super_frames()). \return its mask. */
    const pilot_mask& mask_of_set(int f) const { return super_frame ? super_frame->set(f) : mask; }
    nlohmann::json decoder;  ///< {"kind": ..., settings}
    nlohmann::json training; ///< objective, SNR range, frames, epochs, seed, command
    nlohmann::json metrics;  ///< measured test metrics
    /*!
     * \brief A track bundle's decision over a track (bundle.json's `track`; null for a
     *        per-frame bundle): the temporal model, its weights file and how it was trained,
     *        read and checked by track_classifier (learning/temporal/track_classifier.h).
     */
    nlohmann::json track;
    /*!
     * \brief A position bundle's angle decoder over an array (bundle.json's `position`; null for
     *        a one-antenna bundle): the array, the angle network's settings, its weights file and
     *        how it was trained, read and checked by position_estimator
     *        (learning/array/position_estimator.h). The bundle itself is a delay bundle: its
     *        decoder estimates the delay from the array's pilots beamformed towards the angle.
     */
    nlohmann::json position;
    /*!
     * \brief The pilot mask's file name, as bundle.json records it (`mask_file`; relative to
     *        directory, no folders). load() reads this file, save() writes it.
     */
    std::string mask_name = mask_file;
    /*!
     * \brief The decoder weights' file name, as bundle.json records it (`weights_file`;
     *        relative to directory, no folders). bundle_decoder reads this file.
     */
    std::string weights_name = weights_file;
    /*! \brief Where the weights are. \return directory/weights_name. */
    std::string weights_path() const;

    /*!
     * \brief The folders a bundle name is looked up in, in order (after the name as given).
     * \details
     *  1. each entry of the environment variable SEMS_MODELS_PATH (colon-separated);
     *  2. the source tree's models/ folder: $SEMS_SOURCE_DIR/models when that variable is
     *     set, and the source tree this library was built from when it runs from its build
     *     tree (not once installed);
     *  3. the installed data folder, `<prefix>/share/gr-sems/models`, found next to the
     *     installed library (so a copy installed to another prefix finds its own models),
     *     then the configured install prefix's.
     * Folders that do not exist are listed too (find() names every place it looked).
     * \return the folders, without duplicates.
     */
    static std::vector<std::string> search_path();
    /*!
     * \brief Resolves a bundle name or path to a bundle directory.
     * \details `name` is used as given when it is a directory (an absolute path, or relative
     * to the working directory; load() then needs its bundle.json); otherwise it is looked up in
     * each folder of search_path() in order, so a bare name such as `classifier` finds the
     * shipped bundle from any working directory. A bare name that is a folder of the working
     * directory without a bundle.json, while the search path holds a bundle of that name, is
     * refused, naming both.
     * \param name a bundle directory or a bundle name (e.g. "classifier", "delay_single").
     * \return the directory that holds name's bundle.json.
     * \throws std::invalid_argument when none holds it, listing every place searched; or
     *         when a folder of the working directory hides a bundle of the search path.
     */
    static std::string find(const std::string& name);
    /*!
     * \brief Reads and validates dir/bundle.json and the mask file it names (weights are
     *        read by bundle_decoder).
     * \param dir the bundle directory, or a bundle name resolved by find().
     * \return the bundle (directory is the resolved directory).
     * \throws std::invalid_argument naming the file and the problem, or every place
     *         searched when no bundle of that name was found.
     */
    static model_bundle load(const std::string& dir);
    /*!
     * \brief Writes bundle.json and mask.json (weights are written by the trainer).
     * \param dir the bundle directory (created if missing).
     * \throws std::invalid_argument naming the file if it cannot be written.
     */
    void save(const std::string& dir) const;
    /*! \brief bundle.json's content. \return the JSON object. */
    nlohmann::json to_json() const;

    /*!
     * \brief Refuses a bundle whose frame settings, pilot count or task do not match what a
     *        block expects.
     * \param fs the block's frame. \param n_pilots the block's N_p.
     * \param expected the task the block needs. \param who names the block in errors.
     * \throws std::invalid_argument naming `who` and the mismatch.
     */
    void check_compatible(const frame_settings& fs, int n_pilots, task_kind expected, const std::string& who) const;
    /*!
     * \brief Refuses to classify frames of another class library than the bundle's.
     * \param input the library of the frames (their scene's, or the truth tag's `class_library`).
     * \param who names the block or tool in errors.
     * \throws std::runtime_error naming `who`, both libraries and their difference
     *         (class_library::difference).
     */
    void check_library(const class_library& input, const std::string& who) const;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_MODEL_BUNDLE_H */
