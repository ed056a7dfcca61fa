// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: JSON of the network size settings (the bundle's decoder settings). */
#include "core/common/json_object.h"
#include <gnuradio/sems/core/common/limits.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace gr {
namespace sems {
namespace nn {

namespace {
using nlohmann::json;

using reader = json_read::object_reader;

// Every settings object is read through an object_reader: unknown keys are refused
// by finish(), integers are range-checked before the cast.
int int_or(reader& r, const char* key, int fallback, const std::string&, int min_value)
{
    return r.int_or(key, fallback, min_value, limits::max_network_size);
}

double positive_or(reader& r, const char* key, double fallback, const std::string& source)
{
    const double v = r.number_or(key, fallback);
    if (v <= 0.0)
        json_read::fail(source, key, "must be positive");
    return v;
}

reader open(const json& j, const std::string& source)
{
    if (!j.is_object())
        json_read::fail(source, "settings", "expected a JSON object");
    return reader(j, source);
}
} // namespace

json encoder_settings::to_json() const
{
    return { { "kind", kind },
             { "free_scores", free_scores },
             { "embedding", embedding },
             { "hidden", hidden },
             { "temperature_start", temperature_start },
             { "temperature_floor", temperature_floor },
             { "temperature_decay", temperature_decay },
             { "soft_epochs", soft_epochs },
             { "factorized", factorized },
             { "shared", shared },
             { "collision_weight", collision_weight },
             { "lr_scale", lr_scale } };
}

encoder_settings encoder_settings::from_json(const json& json_in, const std::string& source)
{
    reader j = open(json_in, source);
    encoder_settings s;
    s.kind = j.string_or("kind", s.kind);
    if (!known_kind(s.kind))
        json_read::fail(source, "kind", "unknown encoder \"" + s.kind + "\" (known: gumbel_topk, gumbel_heads)");
    if (j.has("soft_above"))
        json_read::fail(source, "soft_above",
                        "is no longer a setting: use soft_epochs (the number of mask epochs with a soft "
                        "forward pass; 0 = hard masks from the start)");
    s.free_scores = j.boolean_or("free_scores", s.free_scores);
    s.embedding = int_or(j, "embedding", s.embedding, source, 1);
    s.hidden = int_or(j, "hidden", s.hidden, source, 1);
    s.temperature_start = positive_or(j, "temperature_start", s.temperature_start, source);
    s.temperature_floor = positive_or(j, "temperature_floor", s.temperature_floor, source);
    s.temperature_decay = positive_or(j, "temperature_decay", s.temperature_decay, source);
    s.soft_epochs = int_or(j, "soft_epochs", s.soft_epochs, source, 0);
    s.factorized = j.boolean_or("factorized", s.factorized);
    s.shared = j.boolean_or("shared", s.shared);
    s.collision_weight = j.number_or("collision_weight", s.collision_weight);
    if (s.collision_weight < 0.0) // a negative weight would reward collisions
        json_read::fail(source, "collision_weight", "must be >= 0, got " + std::to_string(s.collision_weight));
    s.lr_scale = positive_or(j, "lr_scale", s.lr_scale, source);
    j.finish();
    return s;
}

json classifier_settings::to_json() const
{
    json j = { { "architecture", architecture }, { "n_classes", n_classes }, { "width", width },
               { "hidden", hidden },             { "features", features } };
    if (architecture == "resnet") {
        j["depth"] = depth;
    } else {
        j["doppler_bins"] = doppler_bins;
        j["kernel"] = kernel;
        j["range_bins"] = range_bins;
        j["conv_slope"] = conv_slope;
        j["mti"] = mti;
        j["chirp_bins"] = chirp_bins;
        j["chirp_sweep_bins"] = chirp_sweep_bins;
        j["chirp_min_pilots"] = chirp_min_pilots;
        if (template_frames != 0) // absent means off: bundles without a bank keep their bundle.json
            j["template_frames"] = template_frames;
    }
    return j;
}

classifier_settings classifier_settings::from_json(const json& json_in, const std::string& source)
{
    reader j = open(json_in, source);
    classifier_settings s;
    // (make_decoder sets the architecture from the bundle's decoder kind.)
    s.architecture = j.string_or("architecture", s.architecture);
    s.n_classes = j.int_or("n_classes", s.n_classes, 2, limits::max_classes);
    s.width = int_or(j, "width", s.width, source, 1);
    s.depth = int_or(j, "depth", s.depth, source, 0);
    s.hidden = int_or(j, "hidden", s.hidden, source, 1);
    s.features = int_or(j, "features", s.features, source, 1);
    s.doppler_bins = int_or(j, "doppler_bins", s.doppler_bins, source, 1);
    s.kernel = int_or(j, "kernel", s.kernel, source, 1);
    s.range_bins = j.int_or("range_bins", 0, -1, limits::max_network_size); // absent: legacy, no range gate
    s.conv_slope = j.number_or("conv_slope", 0.0); // absent: legacy, plain ReLU
    s.mti = j.string_or("mti", s.mti);
    s.chirp_bins = j.int_or("chirp_bins", 0, 0, limits::max_network_size); // absent: legacy, no tone fit
    s.chirp_sweep_bins = j.number_or("chirp_sweep_bins", s.chirp_sweep_bins);
    // absent: legacy, every observed subcarrier counts
    s.chirp_min_pilots = j.int_or("chirp_min_pilots", 1, 1, limits::max_network_size);
    s.template_frames = j.int_or("template_frames", 0, -1, limits::max_template_frames);
    j.finish();
    s.validate(source);
    return s;
}

void classifier_settings::validate(const std::string& source) const
{
    auto fail = [&](const char* key, const std::string& problem) { json_read::fail(source, key, problem); };
    if (!known_architecture(architecture))
        fail("architecture", "unknown classifier \"" + architecture + "\" (known: spectral, resnet)");
    if (n_classes < 2)
        fail("n_classes", "must be >= 2, got " + std::to_string(n_classes));
    for (const auto& [key, value, least] : { std::tuple<const char*, int, int>{ "width", width, 1 },
                                             { "depth", depth, 0 },
                                             { "hidden", hidden, 1 },
                                             { "features", features, 1 },
                                             { "doppler_bins", doppler_bins, 1 } })
        if (value < least)
            fail(key, "must be >= " + std::to_string(least) + ", got " + std::to_string(value));
    if (kernel < 1 || kernel % 2 == 0)
        fail("kernel", "must be odd and >= 1, got " + std::to_string(kernel));
    if (range_bins < -1)
        fail("range_bins", "must be -1 (2·M), 0 (off) or a bin count, got " + std::to_string(range_bins));
    if (!(conv_slope >= 0.0 && conv_slope < 1.0))
        fail("conv_slope", "must be in [0, 1), got " + std::to_string(conv_slope));
    if (!known_mti(mti))
        fail("mti", "unknown zero-Doppler stage \"" + mti + "\" (known: none, mean, both)");
    if (chirp_bins < 0 || (chirp_bins > 0 && chirp_bins % 2 == 0))
        fail("chirp_bins", "must be 0 (off) or odd (the rates are symmetric around 0), got " + std::to_string(chirp_bins));
    if (!(chirp_sweep_bins > 0.0 && std::isfinite(chirp_sweep_bins)))
        fail("chirp_sweep_bins", "must be finite and > 0, got " + std::to_string(chirp_sweep_bins));
    if (chirp_min_pilots < 1)
        fail("chirp_min_pilots", "must be >= 1, got " + std::to_string(chirp_min_pilots));
    if (template_frames < -1 || template_frames > limits::max_template_frames)
        fail("template_frames", "must be -1 (every training frame), 0 (no template bank) or a frame count up to " +
                                    std::to_string(limits::max_template_frames) + ", got " +
                                    std::to_string(template_frames));
    if (template_frames != 0 && architecture != "spectral")
        fail("template_frames", "a template bank needs the spectral architecture, not \"" + architecture + "\"");
}

std::vector<double> classifier_settings::chirp_rates(int n_symbols) const
{
    // A chirp of rate α (cycles/symbol²) changes frequency by α N cycles/symbol over the frame,
    // α N² Doppler bins: the largest rate sweeps chirp_sweep_bins bins.
    if (n_symbols < 1)
        throw std::invalid_argument("classifier chirp_rates: n_symbols must be >= 1, got " + std::to_string(n_symbols));
    const int half = chirp_bins / 2;
    std::vector<double> a(chirp_bins, 0.0); // one rate (or none): 0
    for (int j = 0; half > 0 && j < chirp_bins; ++j)
        a[j] = chirp_sweep_bins * (j - half) / (static_cast<double>(half) * n_symbols * n_symbols);
    return a;
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
             { "refine_trust_index", refine_trust_index },
             { "refine_global_peak", refine_global_peak },
             { "refine_global_min_fraction", refine_global_min_fraction },
             { "refine_global_fit", refine_global_fit } };
}

delay_settings delay_settings::from_json(const json& json_in, const std::string& source)
{
    reader j = open(json_in, source);
    delay_settings s;
    s.tau_min_index = j.number_or("tau_min_index", s.tau_min_index);
    s.tau_max_index = j.number_or("tau_max_index", s.tau_max_index);
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
    s.phase_reference = j.boolean_or("phase_reference", false);
    s.residual_maps = int_or(j, "residual_maps", 0, source, 0);
    if (s.residual_maps > 8)
        json_read::fail(source, "residual_maps", "must be in [0, 8]");
    s.window = int_or(j, "window", s.window, source, 0);
    // -1 (the default) means "resolved by the trainer from the scene"; a decoder refuses it.
    s.refine_paths = int_or(j, "refine_paths", 0, source, -1);
    s.refine_span_index = j.number_or("refine_span_index", 8.0);
    if (!(s.refine_span_index > 0.25) && s.refine_span_index != -1.0)
        json_read::fail(source, "refine_span_index", "must be > 0.25 (or -1: from the training scene)");
    s.refine_trust_index = j.number_or("refine_trust_index", s.refine_trust_index);
    if (!(s.refine_trust_index > 0.0))
        json_read::fail(source, "refine_trust_index", "must be > 0");
    s.refine_global_peak = j.boolean_or("refine_global_peak", false); // added after the first bundles
    s.refine_global_min_fraction = j.number_or("refine_global_min_fraction", 0.0);
    if (!(s.refine_global_min_fraction >= 0.0 && s.refine_global_min_fraction < 1.0))
        json_read::fail(source, "refine_global_min_fraction", "must be in [0, 1)");
    s.refine_global_fit = j.boolean_or("refine_global_fit", false); // added after the first bundles
    j.finish();
    return s;
}

json reconstruction_settings::to_json() const { return { { "hidden", hidden } }; }

reconstruction_settings reconstruction_settings::from_json(const json& json_in, const std::string& source)
{
    reader j = open(json_in, source);
    reconstruction_settings s;
    s.hidden = int_or(j, "hidden", s.hidden, source, 1);
    j.finish();
    return s;
}

void angle_settings::validate(const std::string& source) const
{
    if (grid < 8 || grid > 4096)
        json_read::fail(source, "grid", "must be in [8, 4096], got " + std::to_string(grid));
    if (!(std::isfinite(azimuth_min_rad) && std::isfinite(azimuth_max_rad) && azimuth_min_rad >= -M_PI / 2 &&
          azimuth_max_rad <= M_PI / 2 && azimuth_min_rad < azimuth_max_rad))
        json_read::fail(source, "azimuth_min_rad, azimuth_max_rad", "the grid must run from -pi/2 <= min < max <= pi/2 rad, got [" +
                                                       std::to_string(azimuth_min_rad) + ", " +
                                                       std::to_string(azimuth_max_rad) + "]");
    if (channels < 1)
        json_read::fail(source, "channels", "must be >= 1, got " + std::to_string(channels));
    if (blocks < 0 || blocks > 12)
        json_read::fail(source, "blocks", "must be in [0, 12], got " + std::to_string(blocks));
    if (kernel < 1 || kernel % 2 == 0)
        json_read::fail(source, "kernel", "must be odd and >= 1, got " + std::to_string(kernel));
    if (window < 0 || 2 * window + 1 > grid)
        json_read::fail(source, "window", "must be in [0, (grid - 1) / 2], got " + std::to_string(window));
    if (!(std::isfinite(polish_steps) && polish_steps >= 0.0))
        json_read::fail(source, "polish_steps", "must be a finite number >= 0");
}

json angle_settings::to_json() const
{
    return { { "grid", grid },       { "azimuth_min_rad", azimuth_min_rad }, { "azimuth_max_rad", azimuth_max_rad },
             { "channels", channels }, { "blocks", blocks },                 { "kernel", kernel },
             { "window", window },   { "polish_steps", polish_steps } };
}

angle_settings angle_settings::from_json(const json& json_in, const std::string& source)
{
    reader j = open(json_in, source);
    angle_settings s;
    s.grid = int_or(j, "grid", s.grid, source, 8);
    s.azimuth_min_rad = j.number_or("azimuth_min_rad", s.azimuth_min_rad);
    s.azimuth_max_rad = j.number_or("azimuth_max_rad", s.azimuth_max_rad);
    s.channels = int_or(j, "channels", s.channels, source, 1);
    s.blocks = int_or(j, "blocks", s.blocks, source, 0);
    s.kernel = int_or(j, "kernel", s.kernel, source, 1);
    s.window = int_or(j, "window", s.window, source, 0);
    s.polish_steps = j.number_or("polish_steps", s.polish_steps);
    j.finish();
    s.validate(source);
    return s;
}

} // namespace nn
} // namespace sems
} // namespace gr
