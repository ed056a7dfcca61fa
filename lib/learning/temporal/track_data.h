// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: tracks for training and testing a decision over a track (internal): each track
 * drawn alone from (seed, track index) by the channel model, kept as its pilots only. */
#ifndef INCLUDED_SEMS_LIB_LEARNING_TRACK_DATA_H
#define INCLUDED_SEMS_LIB_LEARNING_TRACK_DATA_H

#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/frame/super_frame_mask.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <torch/torch.h>
#include <cstdint>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace temporal {

struct track_set {
    torch::Tensor obs;    // count x K x N_p x 2 (float): noiseless pilots in mask order, zero past a track's end
    torch::Tensor set;    // count x K (int): the super-frame set each frame was read at (all 0 for F = 1)
    torch::Tensor length; // count (long): frames of each track, 1..K (a track that leaves its range interval is shorter)
    torch::Tensor label;  // count (long): class index into the classifier's class names
    int64_t size() const { return label.size(0); }
};

// Tracks first_track .. first_track + count − 1 of `sc` (which has random.tracks), their first
// K frames, drawn in parallel (each track alone, channel_model::begin_track). `class_names`:
// the classifier's classes, in its order; a track of another class is refused naming it.
// With a super-frame of F sets, frame t of track j is read at set (j + t) mod F: a track
// starts at every phase of the super-frame, as tracks in a stream do (the stream's frame
// index picks the set). F = 1 reads every frame at the one mask.
track_set draw_tracks(const frame_settings& fs,
                      const scene& sc,
                      const super_frame_mask& mask,
                      uint64_t seed,
                      int64_t first_track,
                      int64_t count,
                      int frames,
                      const std::vector<std::string>& class_names);

// One frame's mask: every frame read at it.
inline track_set draw_tracks(const frame_settings& fs,
                             const scene& sc,
                             const pilot_mask& mask,
                             uint64_t seed,
                             int64_t first_track,
                             int64_t count,
                             int frames,
                             const std::vector<std::string>& class_names)
{
    return draw_tracks(fs, sc, super_frame_mask(mask), seed, first_track, count, frames, class_names);
}

// The tracks' whole noiseless grids, frames x 2 x N x M each (count x K x 2 x N x M, float,
// zero past a track's end): what a mask learner picks pilots from. 8·N·M bytes a frame.
track_set draw_track_grids(const frame_settings& fs,
                           const scene& sc,
                           uint64_t seed,
                           int64_t first_track,
                           int64_t count,
                           int frames,
                           const std::vector<std::string>& class_names);

// The tracks' observations at one SNR per track, drawn uniformly in [snr_min, snr_max] dB:
// pilot k of a frame's set gets CN(0, σ²/p_k) (pilot_mask::noise_scale), frames past a
// track's end stay zero.
torch::Tensor observe_tracks(const track_set& t,
                             const super_frame_mask& mask,
                             double snr_min_db,
                             double snr_max_db,
                             at::Generator gen);

// One frame's mask.
inline torch::Tensor
observe_tracks(const track_set& t, const pilot_mask& mask, double snr_min_db, double snr_max_db, at::Generator gen)
{
    return observe_tracks(t, super_frame_mask(mask), snr_min_db, snr_max_db, gen);
}

} // namespace temporal
} // namespace sems
} // namespace gr

#endif
