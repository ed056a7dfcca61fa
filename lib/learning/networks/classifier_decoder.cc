// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the ResNet classifier decoder (see classifier_decoder.h). */
#include "learning/networks/classifier_decoder.h"
#include <stdexcept>

namespace gr {
namespace sems {
namespace nn {

namespace {
// 3 x 1 convolution along slow time.
torch::nn::Conv2dOptions conv3(int in, int out, int stride)
{
    return torch::nn::Conv2dOptions(in, out, { 3, 1 }).stride({ stride, 1 }).padding({ 1, 0 }).bias(false);
}
} // namespace

residual_block2d_module::residual_block2d_module(int in, int out, int stride)
{
    conv1 = register_module("conv1", torch::nn::Conv2d(conv3(in, out, stride)));
    bn1 = register_module("bn1", torch::nn::BatchNorm2d(out));
    conv2 = register_module("conv2", torch::nn::Conv2d(conv3(out, out, 1)));
    bn2 = register_module("bn2", torch::nn::BatchNorm2d(out));
    if (in != out || stride != 1) {
        shortcut = register_module(
            "shortcut", torch::nn::Conv2d(torch::nn::Conv2dOptions(in, out, 1).stride({ stride, 1 }).bias(false)));
        bn_sc = register_module("bn_sc", torch::nn::BatchNorm2d(out));
    }
}

torch::Tensor residual_block2d_module::forward(const torch::Tensor& x)
{
    auto y = torch::relu(bn1->forward(conv1->forward(x)));
    y = bn2->forward(conv2->forward(y));
    auto s = shortcut ? bn_sc->forward(shortcut->forward(x)) : x;
    return torch::relu(y + s);
}

classifier_decoder_module::classifier_decoder_module(int n, int m, int np, classifier_settings s)
    : d_n(n), d_m(m), d_np(np), d_s(s)
{
    d_s.architecture = "resnet"; // what describe() records

    s.validate("classifier decoder");
    d_stem = register_module(
        "stem", torch::nn::Conv2d(torch::nn::Conv2dOptions(2, s.width, { 3, m }).padding({ 1, 0 }).bias(false)));
    d_stem_bn = register_module("stem_bn", torch::nn::BatchNorm2d(s.width));
    d_stages = register_module("stages", torch::nn::Sequential());
    for (int i = 0; i < s.depth; ++i)
        d_stages->push_back(residual_block2d(s.width, s.width, 1));
    const int flat = s.width * n;
    d_fc1 = register_module("fc1", torch::nn::Linear(flat, s.hidden));
    d_fc2 = register_module("fc2", torch::nn::Linear(s.hidden, s.features));
    d_out = register_module("out", torch::nn::Linear(s.features, s.n_classes));
}

decoder_output classifier_decoder_module::forward(const torch::Tensor& grid)
{
    auto x = normalise_frames(grid, d_np);
    x = torch::relu(d_stem_bn->forward(d_stem->forward(x)));
    if (!d_stages->is_empty())
        x = d_stages->forward(x);
    // Leaky in the MLP head: a unit pushed negative by an early bad mask can come back.
    x = torch::leaky_relu(d_fc1->forward(x.flatten(1)), 0.1);
    decoder_output out;
    out.features = d_fc2->forward(x);
    out.logits = d_out->forward(torch::leaky_relu(out.features, 0.1));
    return out;
}

nlohmann::json classifier_decoder_module::describe() const
{
    return { { "kind", kind() }, { "settings", d_s.to_json() } };
}

} // namespace nn
} // namespace sems
} // namespace gr
