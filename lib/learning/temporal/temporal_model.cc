// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the causal temporal model over a track, its settings and kind gru_fusion (see
 * temporal_model.h). */
#include "learning/temporal/temporal_model.h"
#include "learning/temporal/tcn_model.h"
#include "core/common/json_object.h"
#include <gnuradio/sems/core/common/limits.h>
#include <algorithm>
#include <limits>
#include <stdexcept>

namespace gr {
namespace sems {
namespace nn {

std::vector<std::string> temporal_settings::kinds() { return { "gru_fusion", "acf_tcn" }; }

int temporal_settings::receptive_field() const
{
    long long r = 1; // in 64 bits: any list is measured before it is refused
    for (int d : dilations)
        r += static_cast<long long>(kernel - 1) * d;
    return static_cast<int>(std::min<long long>(r, std::numeric_limits<int>::max()));
}

void temporal_settings::validate(const std::string& source) const
{
    const auto known = kinds();
    if (std::find(known.begin(), known.end(), kind) == known.end()) {
        std::string list;
        for (const auto& k : known)
            list += (list.empty() ? "" : ", ") + k;
        json_read::fail(source, "kind", "unknown temporal model \"" + kind + "\" (known: " + list + ")");
    }
    if (!(dropout >= 0.0 && dropout < 1.0))
        json_read::fail(source, "dropout", "must be in [0, 1), got " + std::to_string(dropout));
    if (fusion_frames < 0 || fusion_frames > limits::max_track_frames)
        json_read::fail(source, "fusion_frames", "must be in [0, " + std::to_string(limits::max_track_frames) +
                                                     "], got " + std::to_string(fusion_frames));
    auto size = [&](const char* key, int v, int hi) {
        if (v < 1 || v > hi)
            json_read::fail(source, key, "must be in [1, " + std::to_string(hi) + "], got " + std::to_string(v));
    };
    if (kind == "gru_fusion") {
        size("hidden", hidden, limits::max_network_size);
        return;
    }
    size("channels", channels, limits::max_network_size);
    size("kernel", kernel, max_kernel);
    size("head", head, limits::max_network_size);
    if (dilations.empty() || dilations.size() > static_cast<size_t>(max_layers))
        json_read::fail(source, "dilations", "must list 1 to " + std::to_string(max_layers) +
                                                 " dilations (one per convolution), got " +
                                                 std::to_string(dilations.size()));
    for (size_t i = 0; i < dilations.size(); ++i)
        size(("dilations[" + std::to_string(i) + "]").c_str(), dilations[i], max_receptive_field);
    if (receptive_field() > max_receptive_field)
        json_read::fail(source, "dilations",
                        "a receptive field of 1 + (kernel − 1)·Σ dilations = " + std::to_string(receptive_field()) +
                            " frames, more than the " + std::to_string(max_receptive_field) +
                            " a streamed track's state keeps");
}

nlohmann::json temporal_settings::to_json() const
{
    if (kind == "gru_fusion") // the keys every gru_fusion bundle has written
        return { { "kind", kind },
                 { "hidden", hidden },
                 { "doppler_profile", doppler_profile },
                 { "dropout", dropout },
                 { "fusion_frames", fusion_frames } };
    return { { "kind", kind },
             { "channels", channels },
             { "kernel", kernel },
             { "dilations", dilations },
             { "head", head },
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
    s.validate(source); // the kind first: which keys are known follows from it
    s.dropout = r.number_or("dropout", s.dropout);
    if (!(s.dropout >= 0.0 && s.dropout < 1.0))
        json_read::fail(source, "dropout", "must be in [0, 1), got " + std::to_string(s.dropout));
    s.fusion_frames = r.int_or("fusion_frames", s.fusion_frames, 0, limits::max_track_frames);
    if (s.kind == "gru_fusion") {
        s.hidden = r.int_or("hidden", s.hidden, 1, limits::max_network_size);
        s.doppler_profile = r.boolean_or("doppler_profile", s.doppler_profile);
    } else {
        s.channels = r.int_or("channels", s.channels, 1, limits::max_network_size);
        s.kernel = r.int_or("kernel", s.kernel, 1, max_kernel);
        s.head = r.int_or("head", s.head, 1, limits::max_network_size);
        if (r.has("dilations")) {
            const auto& list = r.array("dilations", 1, max_layers);
            s.dilations.clear();
            for (size_t i = 0; i < list.size(); ++i)
                s.dilations.push_back(json_read::int_in(list[i], "dilations[" + std::to_string(i) + "]", source, 1,
                                                        max_receptive_field));
        }
    }
    r.finish(); // a key of the other kind is unknown here
    s.validate(source);
    return s;
}

track_model_module::track_model_module(int evidence_size, int n_classes, temporal_settings s)
    : d_e(evidence_size), d_c(n_classes), d_s(std::move(s))
{
    if (d_c < 2 || d_e < d_c)
        throw std::invalid_argument("temporal model: evidence of " + std::to_string(d_e) + " values for " +
                                    std::to_string(d_c) + " classes (it ends with the C log-probabilities)");
}

temporal_model_module::temporal_model_module(int evidence_size, int n_classes, temporal_settings s)
    : track_model_module(evidence_size, n_classes, std::move(s))
{
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

torch::Tensor track_model_module::decide(const torch::Tensor& logits, const torch::Tensor& evidence) const
{
    auto learned = logits.argmax(-1);
    if (d_s.fusion_frames <= 0)
        return learned;
    auto fused = evidence.slice(2, d_e - d_c, d_e).cumsum(1).argmax(-1);
    auto early = torch::arange(logits.size(1), torch::kLong).view({ 1, -1 }) < d_s.fusion_frames;
    return torch::where(early, fused, learned);
}

nlohmann::json track_model_module::describe() const
{
    return { { "kind", d_s.kind }, { "settings", d_s.to_json() } };
}

std::shared_ptr<track_model_module>
make_temporal_model(int evidence_size, int n_classes, const temporal_settings& s)
{
    s.validate("temporal model");
    if (s.kind == "acf_tcn")
        return std::make_shared<tcn_model_module>(evidence_size, n_classes, s);
    return std::make_shared<temporal_model_module>(evidence_size, n_classes, s);
}

} // namespace nn
} // namespace sems
} // namespace gr
