// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: small 1-D convolutions at inference, BatchNorm folded in, as plain loops
 * (internal, torch-free).
 *
 * A narrow network (the fast delay bundle: 4 channels over an 89-point grid) costs a few
 * thousand multiply-adds per frame and layer, far below the fixed cost of a LibTorch
 * convolution call (MKL-DNN's reorders, a BatchNorm and a ReLU call each): its eight
 * convolutions were most of the decoder's operator time. In inference the BatchNorm that
 * follows a convolution is an affine map per output channel, so it folds into the
 * convolution's weights and bias (w'[o] = s[o] w[o], b' = s (b - mean) + beta,
 * s = gamma / sqrt(var + eps)); what is left is one pass per layer.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_FOLDED_CONV1D_H
#define INCLUDED_SEMS_LIB_LEARNING_FOLDED_CONV1D_H

#include <cstdint>
#include <vector>

namespace gr {
namespace sems {
namespace nn {

//! One convolution (zero padding that keeps the length), its BatchNorm folded in.
struct folded_conv1d {
    int out_channels = 0, in_channels = 0, kernel = 1, dilation = 1;
    std::vector<float> weight; //!< out x in x kernel, row-major
    std::vector<float> bias;   //!< out
};

/*!
 * y[b, o, t] = bias[o] + sum_{i, j} w[o, i, j] x[b, i, t + (j - kernel/2) dilation] (zero
 * outside [0, length)), then + residual[b, o, t] when residual is given, then max(0, .) when
 * relu. x: frames x in x length, y and residual: frames x out x length, all row-major; y
 * must not alias x (it may alias residual).
 */
void folded_conv1d_forward(const folded_conv1d& c,
                           const float* x,
                           int64_t frames,
                           int64_t length,
                           const float* residual,
                           bool relu,
                           float* y);

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_FOLDED_CONV1D_H */
