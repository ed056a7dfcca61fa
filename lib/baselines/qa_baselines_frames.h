// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what the baselines' tests share (internal to the tests). */
#ifndef INCLUDED_SEMS_LIB_BASELINES_QA_BASELINES_FRAMES_H
#define INCLUDED_SEMS_LIB_BASELINES_QA_BASELINES_FRAMES_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/core/channel/channel_model.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/core/scene/scene.h>
#include <vector>

namespace gr {
namespace sems {
namespace qa {

// Noiseless pilot observations of frame 3 of a scene (rows at symbol 3·N: Doppler phases
// far from zero), in mask order, from the one channel model.
inline std::vector<gr_complex> noiseless_observations(const frame_settings& fs, const scene& sc, const pilot_mask& mask)
{
    channel_model cm(fs, sc, 5);
    std::vector<gr_complex> h(fs.grid_size());
    cm.generate(1, h.data(), 3);
    std::vector<gr_complex> obs;
    for (int i : mask.flat_indices())
        obs.push_back(h[i]);
    return obs;
}

} // namespace qa
} // namespace sems
} // namespace gr

// The tests' frame: the paper's (frame_settings' defaults), defined once for the runner's files
// (a unity build compiles them together).
namespace {
const gr::sems::frame_settings fs{};
} // namespace

#endif /* INCLUDED_SEMS_LIB_BASELINES_QA_BASELINES_FRAMES_H */
