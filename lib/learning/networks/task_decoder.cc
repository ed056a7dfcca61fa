// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: decoder rebuild from bundle.json, pilot scatter/gather, weight files. */
#include "core/common/json_read.h"
#include "learning/networks/classifier_decoder.h"
#include "learning/networks/task_decoder.h"
#include "learning/networks/delay_decoder.h"
#include "learning/networks/reconstruction_decoder.h"
#include "learning/networks/spectral_classifier_decoder.h"
#include <fstream>
#include <stdexcept>

namespace gr {
namespace sems {
namespace nn {

task_decoder make_decoder(const nlohmann::json& d, int n, int m, int np, const std::string& source)
{
    const auto kind = json_read::string(json_read::require(d, "kind", source), "decoder.kind", source);
    const auto it = d.find("settings");
    const nlohmann::json settings = (it == d.end()) ? nlohmann::json::object() : *it;
    const std::string where = source + ": decoder.settings";
    if (kind == "classifier_resnet" || kind == "classifier_spectral") {
        auto cs = classifier_settings::from_json(settings, where);
        cs.architecture = kind == "classifier_resnet" ? "resnet" : "spectral";
        return make_classifier(n, m, np, cs);
    }
    if (kind == "delay_correlation")
        return std::make_shared<delay_decoder_module>(n, m, np, delay_settings::from_json(settings, where));
    if (kind == "reconstruction_mlp")
        return std::make_shared<reconstruction_decoder_module>(
            n, m, np, reconstruction_settings::from_json(settings, where));
    json_read::fail(source, "decoder.kind",
                    "unknown decoder \"" + kind +
                        "\" (known: classifier_spectral, classifier_resnet, delay_correlation, reconstruction_mlp)");
}

task_decoder make_classifier(int n, int m, int np, const classifier_settings& s)
{
    if (s.architecture == "resnet")
        return std::make_shared<classifier_decoder_module>(n, m, np, s);
    if (s.architecture == "spectral")
        return std::make_shared<spectral_classifier_decoder_module>(n, m, np, s);
    throw std::invalid_argument("classifier settings: unknown architecture \"" + s.architecture +
                                "\" (known: spectral, resnet)");
}

torch::Tensor scatter_pilots(const torch::Tensor& obs, const std::vector<int64_t>& idx, int n, int m)
{
    return scatter_pilots(obs, torch::tensor(idx, torch::kLong), n, m);
}

torch::Tensor scatter_pilots(const torch::Tensor& obs, const torch::Tensor& index, int n, int m)
{
    const int64_t b = obs.size(0);
    auto grid = torch::zeros({ b, 2, n * m }, obs.options());
    grid.index_copy_(2, index, obs.permute({ 0, 2, 1 }));
    return grid.view({ b, 2, n, m });
}

torch::Tensor gather_pilots(const torch::Tensor& grid, const std::vector<int64_t>& idx)
{
    auto index = torch::tensor(idx, torch::kLong);
    return grid.flatten(2).index_select(2, index).permute({ 0, 2, 1 }).contiguous();
}

std::pair<torch::Tensor, torch::Tensor> batchnorm_inference_affine(const torch::nn::BatchNorm1d& bn)
{
    torch::NoGradGuard ng;
    auto scale = bn->weight.detach() / torch::sqrt(bn->running_var + bn->options.eps());
    auto offset = bn->bias.detach() - bn->running_mean * scale;
    return { scale, offset };
}

torch::Tensor normalise_frames(const torch::Tensor& grid, int n_pilots)
{
    auto peak = grid.abs().flatten(1).amax(1).clamp_min(1e-30).view({ -1, 1, 1, 1 });
    auto g = grid / peak;
    auto power = (g * g).flatten(1).sum(1) / n_pilots;
    return g / torch::sqrt(power + 1e-12).view({ -1, 1, 1, 1 });
}

void save_module(const std::shared_ptr<torch::nn::Module>& module, const std::string& path)
{
    try {
        torch::serialize::OutputArchive archive;
        module->save(archive);
        archive.save_to(path);
    } catch (const c10::Error& e) {
        throw std::runtime_error(path + ": cannot write weights (" + e.what_without_backtrace() + ")");
    }
}

void load_module(const std::shared_ptr<torch::nn::Module>& module, const std::string& path)
{
    if (!std::ifstream(path))
        throw std::invalid_argument(path + ": weights file missing or unreadable");
    // Module::load replaces tensors whatever their shape: check every shape ourselves.
    std::vector<std::pair<std::string, std::vector<int64_t>>> shapes;
    for (const auto& p : module->named_parameters())
        shapes.emplace_back(p.key(), p.value().sizes().vec());
    for (const auto& b : module->named_buffers())
        shapes.emplace_back(b.key(), b.value().sizes().vec());
    try {
        torch::serialize::InputArchive archive;
        archive.load_from(path);
        module->load(archive);
    } catch (const c10::Error& e) {
        std::string what = e.what_without_backtrace();
        if (what.size() > 300)
            what = what.substr(0, 300) + "...";
        throw std::invalid_argument(path + ": corrupt weights or weights that do not fit the decoder described "
                                           "in bundle.json (" + what + ")");
    }
    auto params = module->named_parameters();
    auto buffers = module->named_buffers();
    for (const auto& [name, shape] : shapes) {
        const torch::Tensor* t = params.find(name);
        if (!t)
            t = buffers.find(name);
        if (!t || t->sizes().vec() != shape)
            throw std::invalid_argument(path + ": weights do not fit the decoder described in bundle.json (tensor \"" +
                                        name + "\" has shape " + (t ? c10::str(t->sizes()) : std::string("none")) +
                                        ", expected " + c10::str(c10::IntArrayRef(shape)) + ")");
    }
}

} // namespace nn
} // namespace sems
} // namespace gr
