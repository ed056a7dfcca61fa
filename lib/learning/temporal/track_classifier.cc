// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: decisions over a track from a track bundle (see track_classifier.h). */
#include <gnuradio/sems/learning/temporal/track_classifier.h>
#include "core/common/json_object.h"
#include "learning/networks/task_decoder.h"
#include "learning/temporal/tcn_model.h"
#include "learning/temporal/temporal_model.h"
#include "learning/temporal/track_evidence.h"
#include <gnuradio/sems/learning/bundles/bundle_decoder.h>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gr {
namespace sems {

struct track_classifier::impl {
    std::unique_ptr<bundle_decoder> frames;
    std::unique_ptr<temporal::track_evidence> evidence; // what a frame tells the model (on `frames`)
    std::shared_ptr<nn::track_model_module> model;
    std::unique_ptr<nn::tcn_stepper> tcn; // acf_tcn: its streamed step; gru_fusion: the arrays below
    // gru_fusion: the model's weights as Eigen arrays: one streamed step is a few matrix-vector products
    // (3H x E, 3H x H, C x H), far below what building LibTorch tensors for it would cost
    // per frame, and vectorised.
    using matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    using vector = Eigen::VectorXf;
    int e = 0, c = 0, h = 0;
    vector norm_w, norm_b;   // LayerNorm γ, β (E)
    matrix w_ih, w_hh;       // GRU: 3H x E, 3H x H (gates r, z, n)
    vector b_ih, b_hh;       // 3H each
    matrix head_w;           // C x H
    vector head_b;           // C
    float fusion_weight = 1.0f; // λ
    int fusion_frames = 0;      // temporal_settings::fusion_frames
    float norm_eps = 1e-5f;

    static matrix values(const torch::Tensor& t, int64_t rows, int64_t cols)
    {
        auto v = t.detach().to(torch::kFloat).contiguous();
        return Eigen::Map<const matrix>(v.data_ptr<float>(), rows, cols);
    }
    static vector values(const torch::Tensor& t)
    {
        auto v = t.detach().to(torch::kFloat).contiguous();
        return Eigen::Map<const vector>(v.data_ptr<float>(), v.numel());
    }
    void copy_weights()
    {
        auto p = model->named_parameters();
        norm_w = values(p["norm.weight"]);
        norm_b = values(p["norm.bias"]);
        w_ih = values(p["cell.weight_ih"], 3 * h, e);
        w_hh = values(p["cell.weight_hh"], 3 * h, h);
        b_ih = values(p["cell.bias_ih"]);
        b_hh = values(p["cell.bias_hh"]);
        head_w = values(p["head.weight"], c, h);
        head_b = values(p["head.bias"]);
        fusion_weight = values(p["fusion_weight"])(0);
    }
    // torch::nn::GRUCell and LayerNorm, one frame: h <- GRU(LN(x), h); fused += x's log-probabilities.
    void step(const float* x, float* hidden, float* fused, float* logits) const
    {
        const Eigen::Map<const vector> in(x, e);
        Eigen::Map<vector> hv(hidden, h), fv(fused, c);
        const float mean = in.mean();
        const float var = (in.array() - mean).square().mean();
        const vector y = ((in.array() - mean) / std::sqrt(var + norm_eps)) * norm_w.array() + norm_b.array();
        const vector gi = w_ih * y + b_ih;
        const vector gh = w_hh * hv + b_hh;
        const auto sigmoid = [](const auto& a) { return (1.0f + (-a).exp()).inverse(); };
        const Eigen::ArrayXf r = sigmoid(gi.head(h).array() + gh.head(h).array());
        const Eigen::ArrayXf z = sigmoid(gi.segment(h, h).array() + gh.segment(h, h).array());
        const Eigen::ArrayXf n = (gi.tail(h).array() + r * gh.tail(h).array()).tanh();
        hv = ((1.0f - z) * n + z * hv.array()).matrix();
        fv += in.tail(c);
        Eigen::Map<vector>(logits, c) = head_w * hv + head_b + fusion_weight * fv;
    }
};

// Named, not anonymous: the unity build puts this file beside others with helpers of their own.
namespace track_classifier_detail {
void softmax(const float* z, int c, float* p)
{
    const float top = *std::max_element(z, z + c);
    double sum = 0.0;
    for (int k = 0; k < c; ++k)
        sum += std::exp(double(z[k] - top));
    for (int k = 0; k < c; ++k)
        p[k] = static_cast<float>(std::exp(double(z[k] - top)) / sum);
}

const model_bundle& track_bundle(const model_bundle& bundle)
{
    if (!track_classifier::is_track_bundle(bundle))
        throw std::invalid_argument(bundle.directory + "/" + model_bundle::bundle_file +
                                    ": no \"track\" record: a per-frame bundle, not a track bundle (train one with "
                                    "sems_train --frame-bundle)");
    return bundle;
}
} // namespace track_classifier_detail
using namespace track_classifier_detail;

track_classifier::track_classifier(const model_bundle& bundle, int threads)
    : track_classifier(std::make_unique<bundle_decoder>(track_bundle(bundle), threads))
{
}

track_classifier::track_classifier(std::unique_ptr<bundle_decoder> frames) : d_impl(std::make_unique<impl>())
{
    const model_bundle& bundle = track_bundle(frames->bundle());
    const std::string path = bundle.directory + "/" + model_bundle::bundle_file;
    d_impl->frames = std::move(frames);
    json_read::object_reader r(bundle.track, path, "track");
    const auto& temporal = r.require("temporal");
    json_read::object_reader rt(temporal, path, "track.temporal");
    const auto kind = rt.string("kind");
    nn::temporal_settings::from_json({ { "kind", kind } }, path + ": track.temporal"); // an unknown kind, by name
    const auto* settings = rt.find("settings");
    rt.finish();
    auto s = nn::temporal_settings::from_json(settings ? *settings : nlohmann::json::object(),
                                              path + ": track.temporal.settings");
    if (kind != s.kind)
        json_read::fail(path, "track.temporal.kind", "\"" + kind + "\" but its settings say \"" + s.kind + "\"");
    const std::string weights = r.string_or("weights_file", weights_file);
    if (weights.empty() || weights.find('/') != std::string::npos)
        json_read::fail(path, "track.weights_file", "must be a file name inside the bundle, got \"" + weights + "\"");
    r.allow("frames");   // the track length it was trained on (a record)
    r.allow("training"); // how (a record)
    r.allow("metrics");  // what it measured (a record)
    r.finish();
    const int c = static_cast<int>(bundle.class_names.size());
    d_impl->evidence = std::make_unique<temporal::track_evidence>(*d_impl->frames, s);
    d_impl->model = nn::make_temporal_model(d_impl->evidence->size(), c, s);
    nn::load_module(d_impl->model, bundle.directory + "/" + weights);
    d_impl->model->eval();
    d_impl->e = d_impl->model->evidence_size();
    d_impl->c = c;
    d_impl->h = d_impl->model->hidden_size();
    if (const auto tcn = std::dynamic_pointer_cast<nn::tcn_model_module>(d_impl->model))
        d_impl->tcn = std::make_unique<nn::tcn_stepper>(*tcn);
    else
        d_impl->copy_weights();
    d_impl->fusion_frames = s.fusion_frames;
}

track_classifier::~track_classifier() = default;

const model_bundle& track_classifier::bundle() const { return d_impl->frames->bundle(); }
int track_classifier::n_pilots() const { return d_impl->frames->n_pilots(); }
int track_classifier::n_classes() const { return d_impl->model->n_classes(); }
int track_classifier::evidence_size() const { return d_impl->model->evidence_size(); }
const nn::temporal_settings& track_classifier::settings() const { return d_impl->model->settings(); }

track_classifier::state track_classifier::begin() const
{
    state s;
    s.hidden.assign(static_cast<size_t>(d_impl->model->hidden_size()), 0.0f); // zeros: a new track, either kind
    s.fused.assign(static_cast<size_t>(n_classes()), 0.0f);
    return s;
}

std::vector<float> track_classifier::evidence(const gr_complex* obs, int batch, const int* sets) const
{
    return (*d_impl->evidence)(obs, batch, sets);
}

int track_classifier::super_frames() const { return d_impl->frames->super_frames(); }

void track_classifier::step(state& s, const float* evidence, float* probs, float* fusion_probs) const
{
    const auto& m = *d_impl;
    if (s.hidden.size() != static_cast<size_t>(m.h) || s.fused.size() != static_cast<size_t>(m.c))
        throw std::invalid_argument("track_classifier::step: a state of another model (begin() makes one)");
    thread_local std::vector<float> logits;
    logits.resize(static_cast<size_t>(m.c));
    if (m.tcn) {
        m.tcn->step(s.hidden.data(), evidence, logits.data());
        Eigen::Map<impl::vector>(s.fused.data(), m.c) += Eigen::Map<const impl::vector>(evidence + m.e - m.c, m.c);
    } else {
        m.step(evidence, s.hidden.data(), s.fused.data(), logits.data());
    }
    ++s.frames;
    // The first fusion_frames frames of a track: the fusion decides (temporal_settings).
    if (s.frames <= static_cast<uint64_t>(m.fusion_frames))
        softmax(s.fused.data(), m.c, probs);
    else
        softmax(logits.data(), m.c, probs);
    if (fusion_probs)
        softmax(s.fused.data(), m.c, fusion_probs);
}

} // namespace sems
} // namespace gr
