// SPDX-License-Identifier: GPL-3.0-or-later
/*!
 * \file
 * \brief Every stream-tag key, PMT-dict key and message port name, spelled once.
 *
 * \details Blocks, bindings and apps take their keys from here (Python gets them as
 * gnuradio.sems.keys), so no string is spelled twice.
 */
#ifndef INCLUDED_SEMS_CORE_TAGS_H
#define INCLUDED_SEMS_CORE_TAGS_H

namespace gr {
namespace sems {
/*! \brief Stream-tag keys, PMT-dict keys and message port names (docs/design.md §3). */
namespace keys {

// Stream tags (docs/design.md §3).
constexpr const char* frame_tag = "sems_frame"; ///< uint64 frame index, first symbol of a frame
constexpr const char* truth_tag = "sems_truth"; ///< PMT dict of the frame's ground truth

// Truth and result dictionary keys.
constexpr const char* frame = "frame";               ///< frame index (uint64)
constexpr const char* class_id = "class";            ///< target class id of the target of interest
constexpr const char* class_name = "class_name";     ///< target class name
constexpr const char* delay_s = "delay_s";           ///< round-trip delay in s
constexpr const char* delay_index = "delay_index";   ///< delay in delay-index units (τ·B)
constexpr const char* range_m = "range_m";           ///< range in m
constexpr const char* velocity_mps = "velocity_mps"; ///< radial velocity in m/s
constexpr const char* snr_db = "snr_db";             ///< SNR per resource element in dB
/*! \brief With a link budget: the radar equation's SNR of the target of interest alone, without
 *         the emulator's setting (frame_truth::link_snr_db; in a drawn frame's truth dict only). */
constexpr const char* link_snr_db = "link_snr_db";
/*! \brief With an array: the target of interest's azimuth and elevation in rad (frame_truth::azimuth_rad,
 *         elevation_rad; absent without an array). */
constexpr const char* azimuth_rad = "azimuth_rad";
constexpr const char* elevation_rad = "elevation_rad"; ///< see azimuth_rad
constexpr const char* n_paths = "n_paths";           ///< number of channel paths of the frame
constexpr const char* micro_motion = "micro_motion"; ///< the target of interest's micro-motion model ("none", "sinusoid", "rotor", "walker", "wheels", "scatterers")
/*! \brief The drawn parameters of the target of interest's scatterer body: a dict holding
 *         micro_motion_to_json's object plus "speed_mps" and "heading_rad" (arrays as PMT vectors);
 *         PMT_NIL (None in Python) without a body. */
constexpr const char* micro_motion_params = "micro_motion_params";
constexpr const char* class_library = "class_library"; ///< the scene's class library name (class_library::name)
constexpr const char* track_id = "track_id";             ///< the frame's track (uint64; frame_truth::track_id)
constexpr const char* frame_in_track = "frame_in_track"; ///< frames of its track before it (uint64; 0: the track's first)
constexpr const char* track_frames = "track_frames"; ///< a track decision's evidence time: the frames of its track it rests on (uint64)
constexpr const char* tracks_started = "tracks_started"; ///< metrics, track mode: tracks begun (first frame, new track_id, gap or idle)
constexpr const char* track_gaps = "track_gaps";         ///< metrics, track mode: tracks begun again because frames were missing or out of order
constexpr const char* track_idle_resets = "track_idle_resets"; ///< metrics, track mode: tracks begun again after the idle time
constexpr const char* label = "label";               ///< predicted class id
constexpr const char* probs = "probs";               ///< class probabilities (f32vector)
constexpr const char* truth = "truth";               ///< the frame's truth dict, when tagged
constexpr const char* correct = "correct";           ///< prediction matches the truth (bool)
constexpr const char* abs_error_index = "abs_error_index"; ///< |estimated - true| delay index
constexpr const char* abs_error_azimuth_rad = "abs_error_azimuth_rad"; ///< |estimated - true| azimuth (position sink)

// Running-metric dictionary keys.
constexpr const char* frames = "frames";                 ///< frames handled
constexpr const char* frames_scored = "frames_scored";   ///< frames with a truth to compare
constexpr const char* frames_skipped = "frames_skipped"; ///< non-finite or faulted frames, never answered
constexpr const char* frames_faulted = "frames_faulted"; ///< skipped because decoding, scoring or the bookkeeping failed
constexpr const char* accuracy = "accuracy";             ///< fraction of scored frames classified correctly
constexpr const char* mae_index = "mae_index";           ///< mean absolute delay error in delay indices
constexpr const char* mae_m = "mae_m";                   ///< mean absolute range error in m
constexpr const char* rmse_azimuth_rad = "rmse_azimuth_rad"; ///< root-mean-square azimuth error in rad (position sink)
constexpr const char* frames_scored_azimuth = "frames_scored_azimuth"; ///< frames whose truth had an azimuth (position sink)
constexpr const char* confusion = "confusion"; ///< rows: truth class, columns: predicted class

// frame_sync's lock message (on sync_port): one, when it finds the first frame (it never unlocks).
constexpr const char* sync_offset = "offset";     ///< the first frame's start, samples from the stream's start
constexpr const char* sync_metric = "metric";     ///< the timing metric at that start
constexpr const char* sync_failures = "failures"; ///< windows searched without a frame so far

// Message ports.
constexpr const char* result_port = "result";   ///< per-frame result dicts
constexpr const char* metrics_port = "metrics"; ///< running-metric dicts
constexpr const char* sync_port = "sync";       ///< frame_sync's lock messages

} // namespace keys
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_CORE_TAGS_H */
