// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: learning the pilots of a super-frame (internal; docs/design.md §5, super-frame masks).
 *
 * F pilot sets of N_p each, one per frame of the super-frame, learned jointly with the frame
 * decoder and the fusion over frames. Each set is a semantic encoder of its own (gumbel_topk:
 * exact N_p distinct pilots forward, relaxed gradient); the decoder is the frame bundle's,
 * trained on from its weights. A training track of W frames reads frame t at set
 * (track + t) mod F, and the loss is the cross-entropy of the decision after every frame of
 * the window, Σ_{u ≤ t} log p(c | frame u) (the fusion the temporal model starts from), plus
 * each frame's own cross-entropy (the frame decoder's probabilities stay calibrated: the
 * temporal model reads them). The fused term is what rewards sets that see different things:
 * two frames at one set add less than two at complementary ones.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_SUPER_FRAME_LEARNER_H
#define INCLUDED_SEMS_LIB_LEARNING_SUPER_FRAME_LEARNER_H

#include "learning/networks/task_decoder.h"
#include <gnuradio/sems/core/frame/super_frame_mask.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <gnuradio/sems/learning/bundles/model_bundle.h>
#include <gnuradio/sems/learning/temporal/track_trainer.h>
#include <nlohmann/json.hpp>
#include <functional>
#include <string>

namespace gr {
namespace sems {
namespace temporal {

struct super_frame_result {
    super_frame_mask masks;   // the F learned sets
    nn::task_decoder decoder; // the frame decoder trained with them (eval mode)
    nlohmann::json history;   // one object per epoch
};

// Learns s.super_frames sets of the frame bundle's N_p pilots on tracks of `sc` (training
// tracks 0 .. s.mask_tracks − 1, validation tracks from `first_val_track`), each read over
// a window of min(2F, s.track_frames) frames. `say` prints progress.
super_frame_result learn_super_frame(const model_bundle& frame,
                                     const scene& sc,
                                     const track_training_settings& s,
                                     int64_t first_val_track,
                                     int64_t val_tracks,
                                     const std::function<void(const std::string&)>& say);

} // namespace temporal
} // namespace sems
} // namespace gr

#endif
