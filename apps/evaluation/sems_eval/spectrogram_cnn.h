// SPDX-License-Identifier: GPL-3.0-or-later
/* sems_eval experiment 8: the full-grid reference of the micro-Doppler literature, a 2-D CNN
 * over the slow-time spectrogram of a track's Perfect-CSI grids (noiseless, the whole
 * time-frequency grid of every frame).
 *
 * Per frame, two profiles of its grid H[n, m]: the Doppler power spectrum (a Hann-windowed DFT
 * over the frame's N symbols on every subcarrier, powers summed over subcarriers — the range
 * bins' sum, by Parseval), and the range power profile (an inverse DFT over the M subcarriers
 * of every symbol, powers summed over symbols: the body's extent in range, which the Doppler
 * spectrum alone does not show). Each is normalised to its total (a Rayleigh gain new every
 * frame leaves no trace) and taken in dB, floored at -60 dB and mapped to [0, 1]. Stacked, they
 * make an (N + M) x K image per track, profiles by frames. The CNN decides after t frames from
 * the image's first t columns (the rest zero, its time pooling over those t only), so one
 * network answers every observation time and never sees a frame it has not been given.
 * LibTorch stays in the .cc. */
#ifndef SEMS_EVAL_SPECTROGRAM_CNN_H
#define SEMS_EVAL_SPECTROGRAM_CNN_H

#include <gnuradio/gr_complex.h>
#include <gnuradio/sems/core/frame/frame_settings.h>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <vector>

namespace sems_eval {

// The (N + M) x K image (row-major: N Doppler bins, then M range bins, by frame) of `len` frames
// of one track's noiseless grids (frames x N x M, symbol-major as channel_model fills them);
// columns past len are zero.
std::vector<float> track_spectrogram(const gr::sems::frame_settings& fs, const gr_complex* grids, int frames, int len);

class spectrogram_cnn
{
public:
    // Images of `rows` (N + M) x frames; `classes` outputs.
    spectrogram_cnn(int rows, int frames, int classes, uint64_t seed, int threads);
    ~spectrogram_cnn();

    // Trains on count images (their lengths and labels 0..classes-1): the last tenth validates
    // (best epoch kept), each example cut at a length drawn uniformly in [1, its length] per epoch;
    // AdamW with a cosine learning-rate decay over the epochs.
    void train(const std::vector<float>& images, const std::vector<int>& length, const std::vector<int>& label,
               int epochs, std::ostream& log);
    // Decisions after t frames for count images (tracks shorter than t: -1).
    std::vector<int> predict(const std::vector<float>& images, const std::vector<int>& length, int t) const;

private:
    struct impl;
    std::unique_ptr<impl> d_impl;
};

} // namespace sems_eval

#endif
