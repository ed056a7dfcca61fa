// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: JSON of the network size settings (the bundle's decoder settings). */
#include "core/json_read.h"
#include <gnuradio/sems/learning/network_settings.h>

namespace gr {
namespace sems {
namespace nn {

namespace {
using nlohmann::json;

int int_or(const json& j, const char* key, int fallback, const std::string& source, int min_value)
{
    auto it = j.find(key);
    if (it == j.end())
        return fallback;
    const long long v = json_read::integer(*it, key, source);
    if (v < min_value || v > 1000000)
        json_read::fail(source, key, "must be in [" + std::to_string(min_value) + ", 1000000], got " +
                                         std::to_string(v));
    return static_cast<int>(v);
}

double positive_or(const json& j, const char* key, double fallback, const std::string& source)
{
    const double v = json_read::number_or(j, key, fallback, source);
    if (v <= 0.0)
        json_read::fail(source, key, "must be positive");
    return v;
}

void require_object(const json& j, const std::string& source)
{
    if (!j.is_object())
        json_read::fail(source, "settings", "expected a JSON object");
}
} // namespace

json encoder_settings::to_json() const
{
    return { { "embedding", embedding },
             { "hidden", hidden },
             { "temperature_start", temperature_start },
             { "temperature_floor", temperature_floor },
             { "temperature_decay", temperature_decay },
             { "soft_above", soft_above },
             { "factorized", factorized },
             { "shared", shared },
             { "collision_weight", collision_weight },
             { "lr_scale", lr_scale } };
}

encoder_settings encoder_settings::from_json(const json& j, const std::string& source)
{
    require_object(j, source);
    encoder_settings s;
    s.embedding = int_or(j, "embedding", s.embedding, source, 1);
    s.hidden = int_or(j, "hidden", s.hidden, source, 1);
    s.temperature_start = positive_or(j, "temperature_start", s.temperature_start, source);
    s.temperature_floor = positive_or(j, "temperature_floor", s.temperature_floor, source);
    s.temperature_decay = positive_or(j, "temperature_decay", s.temperature_decay, source);
    if (j.contains("factorized")) {
        if (!j["factorized"].is_boolean())
            json_read::fail(source, "factorized", "expected true or false");
        s.factorized = j["factorized"].get<bool>();
    }
    if (j.contains("shared")) {
        if (!j["shared"].is_boolean())
            json_read::fail(source, "shared", "expected true or false");
        s.shared = j["shared"].get<bool>();
    }
    s.soft_above = json_read::number_or(j, "soft_above", s.soft_above, source);
    s.collision_weight = json_read::number_or(j, "collision_weight", s.collision_weight, source);
    s.lr_scale = positive_or(j, "lr_scale", s.lr_scale, source);
    return s;
}

json classifier_settings::to_json() const
{
    return { { "n_classes", n_classes }, { "width", width },       { "depth", depth },
             { "hidden", hidden },       { "features", features } };
}

classifier_settings classifier_settings::from_json(const json& j, const std::string& source)
{
    require_object(j, source);
    classifier_settings s;
    s.n_classes = int_or(j, "n_classes", s.n_classes, source, 2);
    s.width = int_or(j, "width", s.width, source, 1);
    s.depth = int_or(j, "depth", s.depth, source, 0);
    s.hidden = int_or(j, "hidden", s.hidden, source, 1);
    s.features = int_or(j, "features", s.features, source, 1);
    return s;
}

int delay_settings::receptive_field_points() const
{
    long long rf = kernel; // the stem
    long long d = 1;
    for (int i = 0; i < depth; ++i, d *= dilation_growth)
        rf += 2LL * (kernel - 1) * d;
    return static_cast<int>(std::min<long long>(rf, 1 << 30));
}

json delay_settings::to_json() const
{
    return { { "tau_min_index", tau_min_index },
             { "tau_max_index", tau_max_index },
             { "q", q },
             { "projections", projections },
             { "width", width },
             { "depth", depth },
             { "kernel", kernel },
             { "dilation_growth", dilation_growth },
             { "phase_reference", phase_reference },
             { "residual_maps", residual_maps },
             { "window", window },
             { "refine_paths", refine_paths },
             { "refine_span_index", refine_span_index },
             { "refine_trust_index", refine_trust_index } };
}

delay_settings delay_settings::from_json(const json& j, const std::string& source)
{
    require_object(j, source);
    delay_settings s;
    s.tau_min_index = json_read::number_or(j, "tau_min_index", s.tau_min_index, source);
    s.tau_max_index = json_read::number_or(j, "tau_max_index", s.tau_max_index, source);
    if (s.tau_max_index <= s.tau_min_index)
        json_read::fail(source, "tau_max_index", "must be greater than tau_min_index");
    s.q = int_or(j, "q", s.q, source, 2);
    s.projections = int_or(j, "projections", s.projections, source, 1);
    s.width = int_or(j, "width", s.width, source, 1);
    s.depth = int_or(j, "depth", s.depth, source, 0);
    s.kernel = int_or(j, "kernel", s.kernel, source, 1);
    if (s.kernel % 2 == 0)
        json_read::fail(source, "kernel", "must be odd");
    // Keys added with the dilated decoder: a bundle without them is a legacy bundle.
    s.dilation_growth = int_or(j, "dilation_growth", 1, source, 1);
    if (s.dilation_growth > 4)
        json_read::fail(source, "dilation_growth", "must be in [1, 4]");
    s.phase_reference = false;
    if (j.contains("phase_reference")) {
        if (!j["phase_reference"].is_boolean())
            json_read::fail(source, "phase_reference", "expected true or false");
        s.phase_reference = j["phase_reference"].get<bool>();
    }
    s.residual_maps = int_or(j, "residual_maps", 0, source, 0);
    if (s.residual_maps > 8)
        json_read::fail(source, "residual_maps", "must be in [0, 8]");
    s.window = int_or(j, "window", s.window, source, 0);
    s.refine_paths = int_or(j, "refine_paths", 0, source, 0);
    s.refine_span_index = json_read::number_or(j, "refine_span_index", 8.0, source);
    if (!(s.refine_span_index > 0.25))
        json_read::fail(source, "refine_span_index", "must be > 0.25");
    s.refine_trust_index = json_read::number_or(j, "refine_trust_index", s.refine_trust_index, source);
    if (!(s.refine_trust_index > 0.0))
        json_read::fail(source, "refine_trust_index", "must be > 0");
    return s;
}

json reconstruction_settings::to_json() const { return { { "hidden", hidden } }; }

reconstruction_settings reconstruction_settings::from_json(const json& j, const std::string& source)
{
    require_object(j, source);
    reconstruction_settings s;
    s.hidden = int_or(j, "hidden", s.hidden, source, 1);
    return s;
}

} // namespace nn
} // namespace sems
} // namespace gr
