// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: the channel-reconstruction decoder (see reconstruction_decoder.h). */
#include "learning/networks/reconstruction_decoder.h"

namespace gr {
namespace sems {
namespace nn {

reconstruction_decoder_module::reconstruction_decoder_module(int n, int m, int np, reconstruction_settings s)
    : d_n(n), d_m(m), d_np(np), d_s(s)
{
    const int k = 2 * n * m;
    d_fc1 = register_module("fc1", torch::nn::Linear(k, s.hidden));
    d_fc2 = register_module("fc2", torch::nn::Linear(s.hidden, s.hidden));
    d_out = register_module("out", torch::nn::Linear(s.hidden, k));
}

decoder_output reconstruction_decoder_module::forward(const torch::Tensor& grid)
{
    auto h = torch::relu(d_fc1->forward(grid.flatten(1)));
    h = torch::relu(d_fc2->forward(h));
    decoder_output out;
    out.channel = d_out->forward(h).view({ grid.size(0), 2, d_n, d_m });
    return out;
}

nlohmann::json reconstruction_decoder_module::describe() const
{
    return { { "kind", kind() }, { "settings", d_s.to_json() } };
}

} // namespace nn
} // namespace sems
} // namespace gr
