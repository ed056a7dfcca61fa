// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: what every decoder network shares, and how one is rebuilt from bundle.json.
 *
 * Input convention for all decoders: the pilot observations Y/x_k (x_k the pilot sent) scattered into a
 * sparse grid, float B x 2 x N x M (real, imag), zero where there is no pilot. The
 * trainer builds that grid from the Gumbel mask; inference builds it from the mask
 * file with scatter_pilots(). Both then call the same forward(), so the app and the
 * sinks compute the same answers.
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_TASK_DECODER_H
#define INCLUDED_SEMS_LIB_LEARNING_TASK_DECODER_H

#include <gnuradio/sems/learning/api.h>
#include <gnuradio/sems/learning/networks/network_settings.h>
#include <torch/torch.h>
#include <nlohmann/json.hpp>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace gr {
namespace sems {
namespace nn {

struct decoder_output {
    torch::Tensor logits;      // classifier: B x C; delay: B x Q (dictionary scores)
    torch::Tensor features;    // classifier: B x 16 embedding; otherwise undefined
    torch::Tensor profile;     // spectral classifier: B x channels x K log Doppler profile (its input); otherwise undefined
    torch::Tensor delay_index; // delay: B, τ̂·B (soft-argmax); otherwise undefined
    torch::Tensor channel;     // reconstruction: B x 2 x N x M; otherwise undefined
};

class SEMS_LEARNING_API task_decoder_module : public torch::nn::Module
{
public:
    virtual ~task_decoder_module() = default;
    virtual decoder_output forward(const torch::Tensor& grid) = 0;
    // The same with the pilot mask: `mask` is N x M (or B x N x M), 1 at the pilots (during
    // mask learning it also carries the encoder's gradient). The trainer and bundle_decoder
    // call this one. Decoders that need the mask (the spectral classifier's per-subcarrier
    // counts) override it; the default ignores the mask.
    virtual decoder_output forward(const torch::Tensor& grid, const torch::Tensor& mask)
    {
        (void)mask;
        return forward(grid);
    }
    // "classifier_spectral", "classifier_resnet", "delay_correlation" or "reconstruction_mlp".
    virtual std::string kind() const = 0;
    // {"kind": ..., "settings": {...}} as stored in bundle.json.
    virtual nlohmann::json describe() const = 0;
};
using task_decoder = std::shared_ptr<task_decoder_module>;

// Rebuilds a decoder from {"kind", "settings"}; n_symbols/n_subcarriers/n_pilots come
// from the bundle's frame and mask. Throws std::invalid_argument naming `source`.
SEMS_LEARNING_API task_decoder make_decoder(const nlohmann::json& description,
                                   int n_symbols,
                                   int n_subcarriers,
                                   int n_pilots,
                                   const std::string& source);

// The classifier decoder of settings.architecture ("spectral" or "resnet").
SEMS_LEARNING_API task_decoder make_classifier(int n_symbols,
                                               int n_subcarriers,
                                               int n_pilots,
                                               const classifier_settings& settings);

// obs: B x N_p complex as float B x N_p x 2 -> sparse grid B x 2 x N x M.
SEMS_LEARNING_API torch::Tensor scatter_pilots(const torch::Tensor& obs,
                                      const std::vector<int64_t>& flat_indices,
                                      int n_symbols,
                                      int n_subcarriers);
//! The same with the flat indices already a kLong tensor (N_p), for callers that keep one.
SEMS_LEARNING_API torch::Tensor scatter_pilots(const torch::Tensor& obs,
                                      const torch::Tensor& flat_index,
                                      int n_symbols,
                                      int n_subcarriers);
// grid B x 2 x N x M -> obs B x N_p x 2 at the given flat indices (mask order).
SEMS_LEARNING_API torch::Tensor gather_pilots(const torch::Tensor& grid, const std::vector<int64_t>& flat_indices);

// Scales each frame so its pilots have unit mean power. The task answers do not depend
// on the path gain, and a fixed scale keeps 1e-20 and 1e20 amplitudes equally
// well-conditioned (max-abs first, so squaring cannot underflow or overflow).
SEMS_LEARNING_API torch::Tensor normalise_frames(const torch::Tensor& grid, int n_pilots);

// A BatchNorm at inference as the per-channel affine map x -> scale x + offset of its
// running statistics: scale = gamma / sqrt(var + eps), offset = beta - mean scale (no
// gradient). What the decoders fold into the convolution next to it.
SEMS_LEARNING_API std::pair<torch::Tensor, torch::Tensor> batchnorm_inference_affine(const torch::nn::BatchNorm1d& bn);

// Saves / loads a module's parameters and buffers (decoder.pt).
SEMS_LEARNING_API void save_module(const std::shared_ptr<torch::nn::Module>& module, const std::string& path);
// Throws std::invalid_argument naming the file when it is missing or corrupt, or its
// tensors do not fit the module the bundle describes.
SEMS_LEARNING_API void load_module(const std::shared_ptr<torch::nn::Module>& module, const std::string& path);

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_TASK_DECODER_H */
