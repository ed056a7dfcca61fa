// SPDX-License-Identifier: GPL-3.0-or-later
/* gr-sems: sizes of the learning networks (DESIGN §5), the one place their defaults live.
 *
 * Torch-free on purpose: the trainer settings, bundle.json and the Python bindings carry
 * these structs without pulling in LibTorch. Users trade speed for accuracy here
 * (width, depth, dictionary size Q).
 */
#ifndef INCLUDED_SEMS_NN_SETTINGS_H
#define INCLUDED_SEMS_NN_SETTINGS_H

#include <gnuradio/sems/learning/api.h>
#include <nlohmann/json.hpp>
#include <string>

namespace gr {
namespace sems {
namespace nn {

// Semantic encoder: N_p Gumbel-Softmax heads over the N x M grid.
struct SEMS_LEARNING_API encoder_settings {
    int embedding = 16;          // learned embedding per head
    int hidden = 64;             // MLP hidden width (embedding -> hidden -> N*M scores)
    double temperature_start = 2.0;
    double temperature_floor = 0.1; // annealing never goes below this
    double temperature_decay = 0.8;  // per epoch: tau <- max(floor, tau * decay)
    double soft_above = 1.0;         // while tau > this the forward pass uses the soft selection
                                     // (a dense weighted grid the decoder can learn from first);
                                     // at or below it, the straight-through exact one-hot
    double collision_weight = 5.0;   // penalty on two heads wanting the same element
    bool factorized = true;          // Z_r[n,m] = a_r[n] + b_r[m] (the MLP emits N + M scores per
                                     // head): a head's symbol and subcarrier preferences each
                                     // gather gradient over a whole row/column, which learns
                                     // structured patterns (shared subcarriers or symbols) in
                                     // few epochs; false: a free N*M score matrix
    bool shared = false;             // add one shared score matrix (from an extra embedding)
                                     // to every head's: heads can agree on a subcarrier or
                                     // symbol while the collision penalty keeps them apart
    double lr_scale = 1.0;           // encoder learning rate = lr * lr_scale

    nlohmann::json to_json() const;
    static encoder_settings from_json(const nlohmann::json& j, const std::string& source);
};

// Classifier decoder: sparse 2 x N x M grid -> 2-D ResNet -> MLP -> 16 -> C.
struct SEMS_LEARNING_API classifier_settings {
    int n_classes = 3;
    int width = 16;      // channels of the stem and the residual blocks
    int depth = 2;       // residual blocks (3 x 1 along slow time)
    int hidden = 64;     // MLP hidden width
    int features = 16;   // the embedding the t-SNE looks at

    nlohmann::json to_json() const;
    static classifier_settings from_json(const nlohmann::json& j, const std::string& source);
};

// Delay decoder: time projection -> dictionary correlation -> dilated 1-D ResNet ->
// local soft-argmax -> (optional) model-based refinement of the first path.
// Bundles written before a key existed load with its legacy value (noted per key), so
// they compute exactly what they computed when they were trained.
struct SEMS_LEARNING_API delay_settings {
    double tau_min_index = -2.0;  // dictionary grid, in delay indices (tau * B)
    double tau_max_index = 50.0;
    int q = 417;                  // grid points; spacing = (max - min) / (q - 1)
    int projections = 2;          // complex time projections (2 -> the 4 x M of the paper)
    int width = 16;               // 1-D CNN channels
    int depth = 6;                // residual blocks
    int kernel = 3;               // 1-D kernel (odd)
    int dilation_growth = 2;      // block i dilates by growth^i (1, 2, 4, ...): the receptive
                                  // field grows exponentially with depth; 1 = undilated
                                  // (legacy value for bundles without this key)
    bool phase_reference = true;  // rotate the correlations so the strongest one is real: the
                                  // features become invariant to the frame's common phase
                                  // (legacy: false)
    int residual_maps = 2;        // extra feature maps: |correlation| of the residual after
                                  // removing the 1..K strongest dictionary atoms (orthogonal
                                  // matching pursuit on the first projection): a weak first
                                  // path under a strong later path's sidelobes shows up there
                                  // (legacy: 0)
    int window = 8;               // local soft-argmax half-window (grid points); 0 = global
    int refine_paths = -1;        // model-based refinement after the network: L paths fitted by
                                  // least squares, the first one started at the network's
                                  // estimate (see delay_decoder.h); 0 = off (legacy value);
                                  // -1 = the training scene's paths per target (the trainer
                                  // resolves it; a decoder refuses an unresolved -1)
    double refine_span_index = -1.0; // later paths are searched in (tau1 + 0.25, tau1 + span];
                                     // -1 = the training scene's largest excess delay + 1
                                     // (resolved by the trainer, like refine_paths)
    double refine_trust_index = 0.5; // the refined delay replaces the network's only when it
                                     // moved less than this

    double spacing() const { return (tau_max_index - tau_min_index) / (q - 1); }
    // Receptive field of one output score, in grid points: the stem and two convolutions
    // per residual block, block i with dilation dilation_growth^i.
    int receptive_field_points() const;
    // The same in delay indices (points x spacing).
    double receptive_field_index() const { return receptive_field_points() * spacing(); }
    nlohmann::json to_json() const;
    // Missing keys: the legacy values above; bad values: std::invalid_argument naming
    // `source` and the key.
    static delay_settings from_json(const nlohmann::json& j, const std::string& source);
};

// Channel reconstruction decoder (the MSE-objective baseline).
struct SEMS_LEARNING_API reconstruction_settings {
    int hidden = 256;

    nlohmann::json to_json() const;
    static reconstruction_settings from_json(const nlohmann::json& j, const std::string& source);
};

} // namespace nn
} // namespace sems
} // namespace gr

#endif /* INCLUDED_SEMS_NN_SETTINGS_H */
