// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what one frame tells a temporal model (temporal_settings has the equations), one
 * implementation shared by the track trainer and the track classifier, so training and
 * streaming read the same numbers.
 *
 * gru_fusion: the frame decoder's evidence (bundle_decoder::evidence). acf_tcn: the
 * normalised slow-time autocorrelation of the frame's pilots on one subcarrier, then the
 * frame decoder's class log-probabilities (the last C values, as in every kind's evidence,
 * which the fusion of independent frames reads). Torch-free. */
#ifndef INCLUDED_SEMS_LIB_LEARNING_TRACK_EVIDENCE_H
#define INCLUDED_SEMS_LIB_LEARNING_TRACK_EVIDENCE_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/core/frame/pilot_mask.h>
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <gnuradio/sems/learning/temporal/temporal_settings.h>
#include <string>
#include <vector>

namespace gr {
namespace sems {
namespace temporal {

// The normalised slow-time autocorrelation of one mask's pilots. The subcarrier is the
// mask's one with the most pilots (on a tie the lowest index); over its pilots' symbols n,
//   r_k = Σ_{pairs k symbols apart} y(n+k)·y*(n) / Σ |y(n)|²,   k = 1 .. N−1 (N the frame's symbols),
// 0 at a lag no pair spans, and all 0 for a frame whose pilots there are all zero.
class acf_plan
{
public:
    // Refuses a mask without a subcarrier holding two pilots, naming `source`.
    acf_plan(const pilot_mask& mask, const std::string& source);

    int size() const { return 2 * d_lags; } // Re r_1 .. r_{N−1}, then Im r_1 .. r_{N−1}
    int subcarrier() const { return d_subcarrier; }
    // frame: the mask's N_p observations in mask order; out: size() values.
    void compute(const gr_complex* frame, float* out) const;

private:
    int d_lags = 0, d_subcarrier = 0;
    std::vector<int> d_index;  // the subcarrier's pilots in mask order
    std::vector<int> d_symbol; // their symbols
};

// A temporal model's evidence for frames of any tracks.
class track_evidence
{
public:
    // `frames`: the track bundle's frame decoder (kept by reference); `s`: the model's settings.
    // acf_tcn refuses a mask (any set of a super-frame) without a subcarrier holding two
    // pilots, naming the bundle's mask file and the set.
    track_evidence(const bundle_decoder& frames, const nn::temporal_settings& s);

    // The values per frame: bundle_decoder::evidence_size(doppler_profile) for gru_fusion,
    // 2·(N−1) + C for acf_tcn.
    int size() const { return d_size; }
    // obs: batch x N_p observations; sets: each frame's set of a super-frame (may be null
    // when F = 1). Returns batch x size() values. A batch holding a non-finite frame is
    // refused as bundle_decoder::evidence refuses it.
    std::vector<float> operator()(const gr_complex* obs, int batch, const int* sets = nullptr) const;

private:
    const bundle_decoder& d_frames;
    bool d_acf = false, d_profile = false;
    int d_size = 0;
    std::vector<acf_plan> d_plans; // acf_tcn: one per set of the mask
};

} // namespace temporal
} // namespace sems
} // namespace gr

#endif
