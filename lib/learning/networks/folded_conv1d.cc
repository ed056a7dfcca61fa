// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: small 1-D convolutions at inference (see folded_conv1d.h). */
#include "learning/networks/folded_conv1d.h"
#include <algorithm>

namespace gr {
namespace sems {
namespace nn {

void folded_conv1d_forward(const folded_conv1d& c,
                           const float* x,
                           int64_t frames,
                           int64_t length,
                           const float* residual,
                           bool relu,
                           float* y)
{
    const int64_t co = c.out_channels, ci = c.in_channels, k = c.kernel, half = c.kernel / 2;
    for (int64_t b = 0; b < frames; ++b) {
        const float* xb = x + b * ci * length;
        for (int64_t o = 0; o < co; ++o) {
            float* yo = y + (b * co + o) * length;
            const float* ro = residual ? residual + (b * co + o) * length : nullptr;
            // The residual first (y may alias it), then the bias and the taps: the inner
            // loops run over t, contiguous in x and y, and vectorise.
            if (ro) {
                for (int64_t t = 0; t < length; ++t)
                    yo[t] = ro[t] + c.bias[o];
            } else {
                std::fill(yo, yo + length, c.bias[o]);
            }
            for (int64_t i = 0; i < ci; ++i) {
                const float* xi = xb + i * length;
                const float* w = c.weight.data() + (o * ci + i) * k;
                for (int64_t j = 0; j < k; ++j) {
                    const int64_t off = (j - half) * c.dilation; // y[t] += w x[t + off]
                    const int64_t t0 = std::max<int64_t>(0, -off), t1 = std::min(length, length - off);
                    const float wj = w[j];
                    for (int64_t t = t0; t < t1; ++t)
                        yo[t] += wj * xi[t + off];
                }
            }
            if (relu)
                for (int64_t t = 0; t < length; ++t)
                    yo[t] = std::max(yo[t], 0.0f);
        }
    }
}

} // namespace nn
} // namespace sems
} // namespace gr
