// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the causal temporal model over a track (see temporal_model.h). */
#include "learning/temporal/temporal_model.h"
#include "core/common/json_object.h"
#include <gnuradio/sems/core/common/limits.h>
#include <stdexcept>

namespace gr {
namespace sems {
namespace nn {

nlohmann::json temporal_settings::to_json() const
{
    return { { "kind", kind },
             { "hidden", hidden },
             { "doppler_profile", doppler_profile },
             { "dropout", dropout },
             { "fusion_frames", fusion_frames } };
}

temporal_settings temporal_settings::from_json(const nlohmann::json& j, const std::string& source)
{
    if (!j.is_object())
        json_read::fail(source, "settings", "expected a JSON object");
    json_read::object_reader r(j, source);
    temporal_settings s;
    s.kind = r.string_or("kind", s.kind);
    if (s.kind != "gru_fusion")
        json_read::fail(source, "kind", "unknown temporal model \"" + s.kind + "\" (known: gru_fusion)");
    s.hidden = r.int_or("hidden", s.hidden, 1, limits::max_network_size);
    s.doppler_profile = r.boolean_or("doppler_profile", s.doppler_profile);
    s.dropout = r.number_or("dropout", s.dropout);
    if (!(s.dropout >= 0.0 && s.dropout < 1.0))
        json_read::fail(source, "dropout", "must be in [0, 1), got " + std::to_string(s.dropout));
    s.fusion_frames = r.int_or("fusion_frames", s.fusion_frames, 0, limits::max_track_frames);
    r.finish();
    return s;
}

temporal_model_module::temporal_model_module(int evidence_size, int n_classes, temporal_settings s)
    : d_e(evidence_size), d_c(n_classes), d_s(std::move(s))
{
    if (d_c < 2 || d_e < d_c)
        throw std::invalid_argument("temporal model: evidence of " + std::to_string(d_e) + " values for " +
                                    std::to_string(d_c) + " classes (it ends with the C log-probabilities)");
    d_norm = register_module("norm", torch::nn::LayerNorm(torch::nn::LayerNormOptions({ d_e })));
    d_drop = register_module("drop", torch::nn::Dropout(d_s.dropout));
    d_cell = register_module("cell", torch::nn::GRUCell(torch::nn::GRUCellOptions(d_e, d_s.hidden)));
    d_head = register_module("head", torch::nn::Linear(d_s.hidden, d_c));
    // Start as the fusion of independent frames: no learned term, λ = 1.
    torch::NoGradGuard no_grad;
    d_head->weight.zero_();
    d_head->bias.zero_();
    d_fusion_weight = register_parameter("fusion_weight", torch::ones({ 1 }));
}

torch::Tensor temporal_model_module::step(const torch::Tensor& evidence, torch::Tensor& hidden, torch::Tensor& fused)
{
    hidden = d_cell->forward(d_drop->forward(d_norm->forward(evidence)), hidden); // dropout: training only
    fused = fused + evidence.slice(1, d_e - d_c, d_e);
    return d_head->forward(hidden) + d_fusion_weight * fused;
}

torch::Tensor temporal_model_module::forward(const torch::Tensor& evidence)
{
    const int64_t b = evidence.size(0), t = evidence.size(1);
    auto hidden = torch::zeros({ b, d_s.hidden }, evidence.options());
    auto fused = torch::zeros({ b, d_c }, evidence.options());
    std::vector<torch::Tensor> out;
    out.reserve(static_cast<size_t>(t));
    for (int64_t i = 0; i < t; ++i)
        out.push_back(step(evidence.select(1, i), hidden, fused));
    return torch::stack(out, 1);
}

torch::Tensor temporal_model_module::decide(const torch::Tensor& logits, const torch::Tensor& evidence) const
{
    auto gru = logits.argmax(-1);
    if (d_s.fusion_frames <= 0)
        return gru;
    auto fused = evidence.slice(2, d_e - d_c, d_e).cumsum(1).argmax(-1);
    auto early = torch::arange(logits.size(1), torch::kLong).view({ 1, -1 }) < d_s.fusion_frames;
    return torch::where(early, fused, gru);
}

nlohmann::json temporal_model_module::describe() const
{
    return { { "kind", d_s.kind }, { "settings", d_s.to_json() } };
}

} // namespace nn
} // namespace sems
} // namespace gr
