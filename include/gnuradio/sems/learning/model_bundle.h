// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: a trained model bundle (DESIGN §4): a directory with mask.json, the
 * network weights and bundle.json (task, class names, decoder architecture and
 * settings, frame settings, how it was trained, measured metrics).
 *
 * Loading validates everything and names the file and the problem.
 */
#ifndef INCLUDED_SEMS_LEARNING_MODEL_BUNDLE_H
#define INCLUDED_SEMS_LEARNING_MODEL_BUNDLE_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/core/frame_settings.h>
#include <gnuradio/sems/core/pilot_mask.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace gr {
namespace sems {

enum class task_kind { classify, delay };
SEMS_LEARNING_API std::string task_name(task_kind t);
SEMS_LEARNING_API task_kind task_from_name(const std::string& name); // throws std::invalid_argument

struct SEMS_LEARNING_API model_bundle {
    static constexpr const char* format_name = "sems.model_bundle";
    static constexpr int format_version = 1;
    static constexpr const char* bundle_file = "bundle.json";
    static constexpr const char* mask_file = "mask.json";
    static constexpr const char* weights_file = "decoder.pt";

    std::string directory;
    task_kind task = task_kind::classify;
    std::vector<std::string> class_names; // classify only
    frame_settings frame;
    pilot_mask mask{ 1, 1, { { 0, 0 } } };
    nlohmann::json decoder;  // {"kind": ..., settings}
    nlohmann::json training; // objective, SNR range, frames, epochs, seed, command
    nlohmann::json metrics;  // measured test metrics

    // Reads and validates <dir>/bundle.json and <dir>/mask.json (weights are read by
    // bundle_decoder). Throws std::invalid_argument naming the file and the problem.
    static model_bundle load(const std::string& dir);
    // Writes bundle.json and mask.json (weights are written by the trainer).
    void save(const std::string& dir) const;
    nlohmann::json to_json() const;

    // Refuses (std::invalid_argument naming `who`) a bundle whose frame settings,
    // pilot count or task do not match what a block expects.
    void check_compatible(const frame_settings& fs, int n_pilots, task_kind expected, const std::string& who) const;
};

} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LEARNING_MODEL_BUNDLE_H */
