// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: every stream-tag key, PMT-dict key and message port name, spelled once.
 *
 * Blocks, bindings and apps take their keys from here (Python gets them as
 * gnuradio.sems.keys), so no string is spelled twice.
 */
#ifndef INCLUDED_SEMS_TAGS_H
#define INCLUDED_SEMS_TAGS_H

namespace gr {
namespace sems {
namespace keys {

// Stream tags (DESIGN §3).
constexpr const char* frame_tag = "sems_frame"; // uint64 frame index, first symbol of a frame
constexpr const char* truth_tag = "sems_truth"; // PMT dict of the frame's ground truth

// Truth and result dictionary keys.
constexpr const char* frame = "frame";
constexpr const char* class_id = "class";
constexpr const char* class_name = "class_name";
constexpr const char* delay_s = "delay_s";
constexpr const char* delay_index = "delay_index";
constexpr const char* range_m = "range_m";
constexpr const char* velocity_mps = "velocity_mps";
constexpr const char* snr_db = "snr_db";
constexpr const char* n_paths = "n_paths";
constexpr const char* label = "label";
constexpr const char* probs = "probs";
constexpr const char* truth = "truth";
constexpr const char* correct = "correct";
constexpr const char* abs_error_index = "abs_error_index";

// Running-metric dictionary keys.
constexpr const char* frames = "frames";
constexpr const char* frames_scored = "frames_scored";
constexpr const char* frames_skipped = "frames_skipped";
constexpr const char* frames_faulted = "frames_faulted"; // skipped because decoding failed
constexpr const char* accuracy = "accuracy";
constexpr const char* mae_index = "mae_index";
constexpr const char* mae_m = "mae_m";
constexpr const char* confusion = "confusion"; // rows: truth class, columns: predicted class

// Message ports.
constexpr const char* result_port = "result";
constexpr const char* metrics_port = "metrics";

} // namespace keys
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_TAGS_H */
