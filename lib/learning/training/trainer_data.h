// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the trainer's data set (internal): noiseless channels from the channel model,
 * labels, and seeded noise. */
#ifndef INCLUDED_SEMS_LIB_LEARNING_TRAINER_DATA_H
#define INCLUDED_SEMS_LIB_LEARNING_TRAINER_DATA_H

#include <gnuradio/sems/learning/training/trainer.h>
#include <torch/torch.h>
#include <memory>

namespace gr {
namespace sems {
namespace training {

class frame_stream; // frames computed when asked, from their drawn paths (trainer_data.cc)

struct split {
    torch::Tensor h;      // B x 2 x N x M, noiseless; undefined when streamed
    torch::Tensor label;  // B (long): class index into class_names
    torch::Tensor delay;  // B (float): delay index of the target of interest
    std::shared_ptr<const frame_stream> stream; // set when the frames are streamed
    int64_t size() const { return label.size(0); }
    bool streamed() const { return static_cast<bool>(stream); }
    // Frames idx (long) as idx.size(0) x 2 x N x M: held ones selected, streamed ones computed;
    // the same bits either way.
    torch::Tensor frames(const torch::Tensor& idx) const;
    // The first `count` frames' values at the flat grid indices `flat` (long, into N·M):
    // count x 2 x flat.size(0), computed in batches when streamed.
    torch::Tensor pilots(int64_t count, const torch::Tensor& flat) const;
    // What the frames take (or would take) in memory.
    double held_bytes() const;
};

struct data_set {
    split train, val, test;
    std::vector<std::string> class_names;
    double delay_min = 0.0, delay_max = 0.0; // over all frames
};

// The data set of s and sc: noiseless channels of s.frames frames drawn with s.seed, the
// training frames held or streamed as s.training_data says. The last few sets drawn in the
// process are reused (one evaluation trains many networks on them).
data_set make_data(const training_settings& s, const scene& sc);

// Per-frame σ² for SNRs (dB) drawn uniformly in [lo, hi] from `gen` (nullopt: global).
torch::Tensor draw_noise_variance(int64_t count, double lo, double hi, c10::optional<at::Generator> gen);
// h + CN(0, σ²) per frame (σ²: B).
torch::Tensor add_noise(const torch::Tensor& h, const torch::Tensor& var, c10::optional<at::Generator> gen);
// What the receiver sees of frames h (B x 2 x N x M) at per-frame σ² `var` (B): add_noise for
// the ideal radio (s.radio empty), else each frame through the radio (core/radio/front_end_frame.h),
// its oscillators turned at the frame's delay index `delay` (B); seeds from `gen`.
torch::Tensor observe(const torch::Tensor& h,
                      const torch::Tensor& var,
                      const torch::Tensor& delay,
                      const training_settings& s,
                      c10::optional<at::Generator> gen);

} // namespace training
} // namespace sems
} // namespace gr

#endif
