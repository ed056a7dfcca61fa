// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the channel-reconstruction decoder of the MSE objective (the baseline the
 * paper calls reconstruction-based): sparse grid -> MLP -> the whole N x M channel.
 * No per-frame normalisation: it must reproduce H itself (unit mean power).
 */
#ifndef INCLUDED_SEMS_LIB_LEARNING_RECONSTRUCTION_DECODER_H
#define INCLUDED_SEMS_LIB_LEARNING_RECONSTRUCTION_DECODER_H

#include "learning/networks/task_decoder.h"
#include <gnuradio/sems/learning/networks/network_settings.h>

namespace gr {
namespace sems {
namespace nn {

class SEMS_LEARNING_API reconstruction_decoder_module : public task_decoder_module
{
public:
    reconstruction_decoder_module(int n_symbols, int n_subcarriers, int n_pilots, reconstruction_settings s);
    decoder_output forward(const torch::Tensor& grid) override;
    std::string kind() const override { return "reconstruction_mlp"; }
    nlohmann::json describe() const override;

private:
    int d_n, d_m, d_np;
    reconstruction_settings d_s;
    torch::nn::Linear d_fc1{ nullptr }, d_fc2{ nullptr }, d_out{ nullptr };
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_LIB_LEARNING_RECONSTRUCTION_DECODER_H */
