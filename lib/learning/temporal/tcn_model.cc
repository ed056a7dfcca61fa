// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the temporal model of kind "acf_tcn" (see tcn_model.h). */
#include "learning/temporal/tcn_model.h"
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace gr {
namespace sems {
namespace nn {

tcn_model_module::tcn_model_module(int evidence_size, int n_classes, temporal_settings s)
    : track_model_module(evidence_size, n_classes, std::move(s))
{
    if (d_s.kind != "acf_tcn")
        throw std::invalid_argument("tcn_model: settings of kind \"" + d_s.kind + "\", not acf_tcn");
    d_s.validate("tcn_model");
    int in = d_e;
    for (size_t l = 0; l < d_s.dilations.size(); ++l) {
        // No padding here: forward() pads on the left only, so the model stays causal.
        auto o = torch::nn::Conv1dOptions(in, d_s.channels, d_s.kernel).dilation(d_s.dilations[l]);
        d_conv.push_back(register_module("conv" + std::to_string(l), torch::nn::Conv1d(o)));
        in = d_s.channels;
    }
    d_drop = register_module("drop", torch::nn::Dropout(d_s.dropout));
    d_head1 = register_module("head1", torch::nn::Linear(2 * d_s.channels, d_s.head));
    d_head2 = register_module("head2", torch::nn::Linear(d_s.head, d_c));
}

int tcn_model_module::hidden_size() const { return d_s.receptive_field() * d_e + 2 * d_s.channels + 1; }

torch::Tensor tcn_model_module::inputs(const torch::Tensor& evidence) const
{
    return torch::cat({ evidence.slice(-1, 0, d_e - d_c), evidence.slice(-1, d_e - d_c, d_e).exp() }, -1);
}

torch::Tensor tcn_model_module::forward(const torch::Tensor& evidence)
{
    const int64_t t = evidence.size(1);
    auto a = inputs(evidence).transpose(1, 2); // B x E x T
    for (size_t l = 0; l < d_conv.size(); ++l) {
        const int64_t left = int64_t(d_s.kernel - 1) * d_s.dilations[l];
        namespace F = torch::nn::functional;
        a = torch::relu(d_conv[l]->forward(F::pad(a, F::PadFuncOptions({ left, 0 }))));
    }
    a = a.transpose(1, 2); // B x T x channels
    const auto count = torch::arange(1, t + 1, a.options()).view({ 1, t, 1 });
    const auto pooled = torch::cat({ a.cumsum(1) / count, std::get<0>(a.cummax(1)) }, -1);
    return d_head2->forward(torch::relu(d_head1->forward(d_drop->forward(pooled))));
}

struct tcn_stepper::impl {
    using matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    struct layer {
        int dilation = 1;
        std::vector<matrix> taps; // taps[j]: out x in, applied to the input j·dilation frames back
        Eigen::VectorXf bias;
        std::vector<int> offsets; // frames back whose output a decision needs (0 = the newest)
        std::vector<int> column;  // offset -> its column in the layer's outputs, −1 when unused
    };
    int d_e = 0, d_c = 0, d_ch = 0, d_r = 0, d_state = 0;
    std::vector<layer> d_layers;
    matrix d_head1, d_head2;
    Eigen::VectorXf d_head1_b, d_head2_b;

    explicit impl(const tcn_model_module& m);
    void step(float* state, const float* evidence, float* logits) const;
};

tcn_stepper::tcn_stepper(const tcn_model_module& m) : d_impl(std::make_unique<impl>(m)) {}
tcn_stepper::~tcn_stepper() = default;
int tcn_stepper::state_size() const { return d_impl->d_state; }
void tcn_stepper::step(float* state, const float* evidence, float* logits) const
{
    d_impl->step(state, evidence, logits);
}

tcn_stepper::impl::impl(const tcn_model_module& m)
    : d_e(m.evidence_size()),
      d_c(m.n_classes()),
      d_ch(m.settings().channels),
      d_r(m.settings().receptive_field()),
      d_state(m.hidden_size())
{
    auto values = [](const torch::Tensor& t) { return t.detach().to(torch::kFloat).contiguous(); };
    const auto& s = m.settings();
    const int k = s.kernel, n_layers = static_cast<int>(s.dilations.size());
    d_layers.resize(static_cast<size_t>(n_layers));
    // The offsets each layer must give, from the top down: the newest top-layer output, and
    // below each needed output the kernel's taps, dilation frames apart.
    std::vector<int> need{ 0 };
    for (int l = n_layers - 1; l >= 0; --l) {
        auto& y = d_layers[static_cast<size_t>(l)];
        y.dilation = s.dilations[static_cast<size_t>(l)];
        y.offsets = need;
        y.column.assign(static_cast<size_t>(d_r), -1);
        for (size_t i = 0; i < need.size(); ++i)
            y.column[static_cast<size_t>(need[i])] = static_cast<int>(i);
        std::vector<int> below;
        for (int o : need)
            for (int j = 0; j < k; ++j)
                below.push_back(o + j * y.dilation);
        std::sort(below.begin(), below.end());
        below.erase(std::unique(below.begin(), below.end()), below.end());
        need = below;
    }
    for (int l = 0; l < n_layers; ++l) {
        auto& y = d_layers[static_cast<size_t>(l)];
        const auto w = values(m.convolutions()[static_cast<size_t>(l)]->weight); // out x in x k
        const int64_t out = w.size(0), in = w.size(1);
        for (int j = 0; j < k; ++j) {
            // Tap i of a left-padded convolution reads the input (k − 1 − i)·dilation frames back.
            const auto tap = w.select(2, k - 1 - j).contiguous();
            y.taps.push_back(Eigen::Map<const matrix>(tap.data_ptr<float>(), out, in));
        }
        const auto b = values(m.convolutions()[static_cast<size_t>(l)]->bias);
        y.bias = Eigen::Map<const Eigen::VectorXf>(b.data_ptr<float>(), b.numel());
    }
    const auto h1 = values(m.head_hidden()->weight), h1b = values(m.head_hidden()->bias);
    const auto h2 = values(m.head_out()->weight), h2b = values(m.head_out()->bias);
    d_head1 = Eigen::Map<const matrix>(h1.data_ptr<float>(), h1.size(0), h1.size(1));
    d_head1_b = Eigen::Map<const Eigen::VectorXf>(h1b.data_ptr<float>(), h1b.numel());
    d_head2 = Eigen::Map<const matrix>(h2.data_ptr<float>(), h2.size(0), h2.size(1));
    d_head2_b = Eigen::Map<const Eigen::VectorXf>(h2b.data_ptr<float>(), h2b.numel());
}

namespace {
constexpr float max_count = 16777216.0f; // 2^24: the last count a float holds exactly, with its successor
} // namespace

void tcn_stepper::impl::step(float* state, const float* evidence, float* logits) const
{
    using vector = Eigen::VectorXf;
    // The state: the last R frames' inputs (the newest last), the running mean and maximum of
    // the top layer, and the count of frames.
    float* window = state;
    Eigen::Map<vector> mean(state + size_t(d_r) * d_e, d_ch), peak(state + size_t(d_r) * d_e + d_ch, d_ch);
    float& count = state[d_state - 1];
    std::memmove(window, window + d_e, sizeof(float) * size_t(d_r - 1) * d_e);
    float* newest = window + size_t(d_r - 1) * d_e;
    std::copy(evidence, evidence + d_e, newest);
    for (int i = d_e - d_c; i < d_e; ++i)
        newest[i] = std::exp(newest[i]); // as tcn_model_module::inputs()
    // A float counts exactly to 2^24 frames (6 days of 32 ms frames); past that the count stays
    // there and the running mean weighs each new frame by 2^-24 (a moving average that long),
    // where a float sum would stop taking small values in.
    if (count < max_count)
        count += 1.0f;
    const long long t = static_cast<long long>(count); // frames of the track so far (capped)
    // Each layer's needed outputs, bottom up; an offset at or before the track's start is
    // the convolution's zero padding.
    Eigen::MatrixXf below; // the previous layer's outputs, one column per needed offset
    const std::vector<int>* below_column = nullptr;
    for (size_t l = 0; l < d_layers.size(); ++l) {
        const auto& y = d_layers[l];
        Eigen::MatrixXf out = Eigen::MatrixXf::Zero(d_ch, static_cast<int64_t>(y.offsets.size()));
        for (size_t i = 0; i < y.offsets.size(); ++i) {
            const int o = y.offsets[i];
            if (o >= t)
                continue; // before the track: padding
            vector acc = y.bias;
            for (size_t j = 0; j < y.taps.size(); ++j) {
                const int from = o + static_cast<int>(j) * y.dilation;
                if (from >= t)
                    break; // further taps reach further back, into the padding too
                if (l == 0)
                    acc.noalias() += y.taps[j] * Eigen::Map<const vector>(window + size_t(d_r - 1 - from) * d_e, d_e);
                else
                    acc.noalias() += y.taps[j] * below.col((*below_column)[static_cast<size_t>(from)]);
            }
            out.col(static_cast<int64_t>(i)) = acc.cwiseMax(0.0f);
        }
        below = std::move(out);
        below_column = &y.column;
    }
    const vector top = below.col(0);
    mean += (top - mean) / count; // the mean of frames 1..t, as forward()'s cumsum / t
    peak = peak.cwiseMax(top);    // ReLU outputs: a new track's zeros are below any of them
    vector pooled(2 * d_ch);
    pooled << mean, peak;
    const vector hidden = (d_head1 * pooled + d_head1_b).cwiseMax(0.0f);
    Eigen::Map<vector>(logits, d_c) = d_head2 * hidden + d_head2_b;
}

} // namespace nn
} // namespace sems
} // namespace gr
